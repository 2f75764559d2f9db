"""Protected regions: the user's lines inside a generated file, kept when it is regenerated.

A target marks a file as having regions (``context.emit(path, text, regions="hash")``) and writes
each region as a pair of marker lines around the default text (often nothing)::

    # BEGIN USER BOUML_0x1f602_4
    # END USER BOUML_0x1f602_4

A marker is a whole line: the comment prefix of the syntax (``#`` for ``hash``), one space,
``BEGIN USER`` or ``END USER``, one space and the region's key, nothing else (trailing blanks
allowed); the key is a stable id (the model element's id, see :func:`key`). Any other line,
wherever a marker-like text sits in it, is text. When the build regenerates the file, :func:`merge`
puts the text the user wrote between the markers of the file on disk into the region of the same
key of the new text. A region of the file on disk whose key the new text no longer has (its
element left the model) is *lost*: its text is returned to be appended to ``<file>.lost``.
A key twice in one file, a region not closed, an end without a begin, or a begin inside a region
is a :class:`RegionError` (in the file on disk: the build stops, naming the line; in the new
text: a fault of the target).
"""

from __future__ import annotations

import hashlib
import re
from dataclasses import dataclass

PREFIXES = {"hash": "#"}
"""The comment prefix of each region syntax."""

_KEY = re.compile(r"[A-Za-z0-9_.:@+-]{1,120}\Z")


class RegionError(ValueError):
    """Regions that cannot be read: ``line`` (1-based) says where."""

    def __init__(self, message: str, line: int) -> None:
        super().__init__(f"line {line}: {message}")
        self.line = line


def key(element_id: str) -> str:
    """A region key for a model element id: the id when it is a plain token (letters, digits,
    ``_.:@+-``, at most 120 characters), else ``id-`` and its sha256 (16 hex digits), so that no
    id can forge a marker line and the key stays the same from build to build."""
    if _KEY.match(element_id):
        return element_id
    return "id-" + hashlib.sha256(element_id.encode("utf-8")).hexdigest()[:16]


def begin(syntax: str, region: str) -> str:
    return f"{PREFIXES[syntax]} BEGIN USER {region}"


def end(syntax: str, region: str) -> str:
    return f"{PREFIXES[syntax]} END USER {region}"


@dataclass(frozen=True)
class Region:
    key: str
    start: int  # index of the BEGIN line
    stop: int  # index of the END line
    text: tuple[str, ...]  # the lines between the markers, with their line ends


def _marker(syntax: str, line: str) -> tuple[str, str] | None:
    match = re.fullmatch(
        re.escape(PREFIXES[syntax]) + r" (BEGIN|END) USER ([^\s]+)[ \t]*\r?\n?", line
    )
    return (match.group(1), match.group(2)) if match else None


def parse(syntax: str, text: str) -> list[Region]:
    """The regions of ``text`` in order; :class:`RegionError` when they are not well formed."""
    lines = text.splitlines(keepends=True)
    regions: list[Region] = []
    seen: dict[str, int] = {}
    open_key, open_at = None, 0
    for n, line in enumerate(lines):
        found = _marker(syntax, line)
        if found is None:
            continue
        kind, name = found
        if kind == "BEGIN":
            if open_key is not None:
                raise RegionError(
                    f"region {name!r} begins inside region {open_key!r} "
                    f"(begun at line {open_at + 1})",
                    n + 1,
                )
            if name in seen:
                raise RegionError(
                    f"region {name!r} appears twice (first at line {seen[name] + 1}); "
                    "keep one and move the other's lines into it",
                    n + 1,
                )
            seen[name] = n
            open_key, open_at = name, n
        elif name != open_key:
            raise RegionError(
                f"end of region {name!r} without its begin"
                + (f" (region {open_key!r} is open)" if open_key else ""),
                n + 1,
            )
        else:
            regions.append(Region(name, open_at, n, tuple(lines[open_at + 1 : n])))
            open_key = None
    if open_key is not None:
        raise RegionError(f"region {open_key!r} is not closed", open_at + 1)
    return regions


def merge(syntax: str, new: str, old: str) -> tuple[str, dict[str, str]]:
    """``new`` with the text of each of its regions taken from the region of the same key in
    ``old``, and the regions of ``old`` that ``new`` does not have (key -> their text). A region
    of ``old`` is kept as written, even empty. :class:`RegionError` for regions of ``old`` that
    are not well formed; ``new``'s are checked first (a :class:`ValueError` naming the target's
    text)."""
    try:
        fresh = parse(syntax, new)
    except RegionError as err:
        raise ValueError(f"the generated text's regions: {err}") from None
    kept = {r.key: r for r in parse(syntax, old)}
    lines = new.splitlines(keepends=True)
    out: list[str] = []
    at = 0
    for region in fresh:
        out += lines[at : region.start + 1]
        previous = kept.pop(region.key, None)
        out += previous.text if previous is not None else region.text
        if out and not out[-1].endswith("\n"):
            out[-1] += "\n"
        at = region.stop
    out += lines[at:]
    lost = {k: "".join(r.text) for k, r in kept.items()}
    return "".join(out), lost


def outside(syntax: str, text: str) -> str:
    """``text`` without what its regions hold (their marker lines kept): the lines a build owns.
    Two versions of a file with the same lines outside their regions have the same ``outside``,
    whatever the user wrote inside them. :class:`RegionError` when the regions are not well
    formed."""
    lines = text.splitlines(keepends=True)
    out: list[str] = []
    at = 0
    for region in parse(syntax, text):
        out += lines[at : region.start + 1]
        at = region.stop
    out += lines[at:]
    return "".join(out)


def lost_text(syntax: str, path: str, lost: dict[str, str]) -> str:
    """What goes to ``<path>.lost`` for the ``lost`` regions: each with its markers, after a
    comment saying where it came from."""
    out = []
    for name, text in lost.items():
        out.append(
            f"{PREFIXES[syntax]} From {path}: region {name}, whose model element is no longer "
            "in the model\n"
        )
        out.append(begin(syntax, name) + "\n")
        out.append(text if not text or text.endswith("\n") else text + "\n")
        out.append(end(syntax, name) + "\n")
    return "".join(out)


__all__ = [
    "PREFIXES",
    "Region",
    "RegionError",
    "begin",
    "end",
    "key",
    "lost_text",
    "merge",
    "outside",
    "parse",
]
