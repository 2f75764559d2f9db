"""Paths of generated files: relative, inside the output directory, portable, never colliding.

A model name often becomes part of a file name (``rules/SpeedLimiting.fcl``). Whatever the model
holds, a generated path must stay inside the output directory and mean the same file on every
system the output may be copied to. :func:`path_problem` says why a path is refused;
:func:`segment_problem` does the same for one name about to become a file name (it lives with the
rules on model names, :mod:`acordcs.model.generated_names`, which ``validate`` runs too).
"""

from __future__ import annotations

import errno
import os
import re
import stat
from collections.abc import Iterable

from acordcs.model.generated_names import DEVICE_NAMES, NAME_BYTES, RULE, segment_problem

__all__ = [
    "MANIFEST",
    "NAME_BYTES",
    "READ_LIMIT",
    "RULE",
    "Unreadable",
    "case_collisions",
    "path_problem",
    "read_bounded",
    "segment_problem",
]

MANIFEST = ".acordcs-manifest.json"
"""The build's record of what it wrote (see :mod:`acordcs.generator.manifest`); no target may write it."""


# Paths made of plain names (what targets write): no character a rule below is about. Such a path
# is accepted without looking at each name again (a manifest lists thousands); what it does not
# match goes through every rule.
_PLAIN = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.+-]{0,199}(?:/[A-Za-z0-9_][A-Za-z0-9_.+-]{0,199})*\Z")
_DEVICE = re.compile(
    f"(?:^|/)(?:{'|'.join(sorted(DEVICE_NAMES))})(?:[./]|\\Z)", re.IGNORECASE
)  # a name that is a device name, with or without an extension


def path_problem(path: str) -> str | None:
    """Why ``path`` (relative, '/'-separated) cannot be a generated file (None when it can)."""
    if (
        isinstance(path, str)
        and _PLAIN.match(path)
        and not path.endswith(".")
        and "./" not in path
        and path != MANIFEST
        and not _DEVICE.search(path)
    ):
        return None
    if not isinstance(path, str) or not path:
        return "the path is empty"
    if path.startswith("/") or re.match(r"[A-Za-z]:", path):
        return "the path is absolute"
    for part in path.split("/"):
        problem = segment_problem(part)
        if problem:
            return f"component {part!r} is not {RULE.split(':', 1)[0]}: {problem}"
    if path == MANIFEST:
        return f"{MANIFEST} is the build's own record"
    return None


def case_collisions(paths: Iterable[str]) -> list[tuple[str, str]]:
    """Pairs of paths that differ only in case (or in Unicode case folding): the same file on
    case-insensitive file systems (macOS, Windows)."""
    seen: dict[str, str] = {}
    pairs = []
    for path in sorted(paths):
        key = path.casefold()
        if key in seen and seen[key] != path:
            pairs.append((seen[key], path))
        seen.setdefault(key, path)
    return pairs


READ_LIMIT = 64 * 1024 * 1024
"""The most a build reads of a file of the output directory (64 MiB): a generated file, the
manifest, the package's previous descriptor, a user's class. A larger one is not read
(:class:`Unreadable`): the 2,000-class benchmark's largest generated file is a few MB."""


class Unreadable(OSError):
    """A file of the output directory that a build does not read: not a regular file (a FIFO, a
    device, a socket, a directory, a symbolic link) or larger than :data:`READ_LIMIT`.
    ``what`` says which, in words."""

    def __init__(self, path: str, what: str) -> None:
        super().__init__(what)
        self.path = path
        self.what = what


def read_bounded(path: str | os.PathLike[str], limit: int = READ_LIMIT) -> bytes:
    """The bytes of the regular file ``path``, never waiting and never more than ``limit``: opened
    without following a final symbolic link and without blocking (a FIFO opens at once), looked at
    (``fstat``) before a byte is read. :class:`Unreadable` for anything else; the other OSErrors
    as ``open`` raises them (FileNotFoundError: no such file)."""
    try:
        handle = os.open(path, os.O_RDONLY | os.O_NONBLOCK | os.O_NOFOLLOW | os.O_CLOEXEC)
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise Unreadable(os.fspath(path), "a symbolic link") from None
        raise
    try:
        info = os.fstat(handle)
        if not stat.S_ISREG(info.st_mode):
            raise Unreadable(os.fspath(path), _kind(info.st_mode))
        if info.st_size > limit:
            raise Unreadable(os.fspath(path), _too_large(info.st_size, limit))
        chunks, size = [], 0
        while chunk := os.read(handle, min(limit + 1 - size, 1 << 20) or 1):
            chunks.append(chunk)
            size += len(chunk)
            if size > limit:  # it grew while read
                raise Unreadable(os.fspath(path), _too_large(size, limit))
        return b"".join(chunks)
    finally:
        os.close(handle)


def _kind(mode: int) -> str:
    for test, what in (
        (stat.S_ISFIFO, "a named pipe (FIFO)"),
        (stat.S_ISCHR, "a character device"),
        (stat.S_ISBLK, "a block device"),
        (stat.S_ISSOCK, "a socket"),
        (stat.S_ISDIR, "a directory"),
    ):
        if test(mode):
            return what
    return "not a regular file"


def _too_large(size: int, limit: int) -> str:
    return f"larger than {limit // (1024 * 1024)} MiB ({size} bytes)"
