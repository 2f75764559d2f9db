"""vulture at 80% confidence finds nothing in the package: no unused import, variable or
unreachable code (a callback's parameter that the library passes and the code does not read is
named with a leading ``_``). Functions and methods vulture is less sure of (60%) are the package's
public API or called by name (Pyro5, lark's transformer, click), so they are not held here."""

from __future__ import annotations

from pathlib import Path

import vulture

PACKAGE = Path(__file__).resolve().parent.parent / "src" / "acordcs"


def test_vulture_finds_nothing_unused_at_80_percent():
    finder = vulture.Vulture()
    finder.scavenge([str(PACKAGE)])
    found = [
        f"{item.filename}:{item.first_lineno}: {item.message}"
        for item in finder.get_unused_code(min_confidence=80)
    ]
    assert not found, "\n".join(found)
