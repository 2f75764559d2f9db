"""Paths of generated files: relative, inside the output directory, portable, never colliding.

A model name often becomes part of a file name (``rules/SpeedLimiting.fcl``). Whatever the model
holds, a generated path must stay inside the output directory and mean the same file on every
system the output may be copied to. :func:`path_problem` says why a path is refused;
:func:`segment_problem` does the same for one name about to become a file name (it lives with the
rules on model names, :mod:`acordcs.model.generated_names`, which ``validate`` runs too).
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from acordcs.bounded_read import READ_LIMIT, Unreadable, read_bounded
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
