"""Paths of generated files: relative, inside the output directory, portable, never colliding.

A model name often becomes part of a file name (``rules/SpeedLimiting.fcl``). Whatever the model
holds, a generated path must stay inside the output directory and mean the same file on every
system the output may be copied to. :func:`path_problem` says why a path is refused;
:func:`segment_problem` does the same for one name about to become a file name.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

MANIFEST = ".acordcs-manifest.json"
"""The build's record of what it wrote (see :mod:`acordcs.codegen.manifest`); no target may write it."""

# Characters no portable file name holds: separators, NUL and other controls, and what Windows
# refuses (a generated tree is copied, committed, checked out elsewhere).
_BAD_CHARS = re.compile(r'[\x00-\x1f\x7f/\\<>:"|?*]')
# Device names Windows reserves whatever the extension (CON.txt is CON).
_DEVICES = frozenset(
    ["CON", "PRN", "AUX", "NUL"]
    + [f"COM{n}" for n in range(1, 10)]
    + [f"LPT{n}" for n in range(1, 10)]
)
RULE = (
    "a file name: not empty, not '.' or '..', no '/', '\\', control characters or <>:\"|?*, "
    "not ending in a dot or space, not a Windows device name such as CON or NUL, at most 200 bytes"
)


NAME_BYTES = 200
"""The longest model name the build lets become part of a file name: a target adds to it (an
extension, ``.descriptor.xml``), and file systems allow 255 bytes per component."""


def segment_problem(name: str, limit: int = 255) -> str | None:
    """Why ``name`` cannot be one component of a generated path, at most ``limit`` bytes long
    (None when it can)."""
    if not name:
        return "it is empty"
    if name in (".", ".."):
        return f"{name!r} names a directory, not a file"
    bad = _BAD_CHARS.search(name)
    if bad:
        char = bad.group()
        shown = repr(char) if char.isprintable() else f"U+{ord(char):04X}"
        return f"it contains {shown}"
    if name[-1] in ". ":
        return "it ends in a dot or a space"
    if len(name.encode("utf-8", "surrogatepass")) > limit:
        room = "" if limit == 255 else ", to leave room for what a target adds to it"
        return f"it is longer than {limit} bytes (file systems allow 255{room})"
    if name.split(".", 1)[0].rstrip(" ").upper() in _DEVICES:
        return f"{name.split('.', 1)[0]!r} is a device name on Windows"
    return None


def path_problem(path: str) -> str | None:
    """Why ``path`` (relative, '/'-separated) cannot be a generated file (None when it can)."""
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
