"""A file read without waiting and within a bound: what the build reads of an output directory
and what the tools read of a built application (its descriptor), whatever is found there (a FIFO,
a device, a huge file).
"""

from __future__ import annotations

import errno
import os
import stat

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
