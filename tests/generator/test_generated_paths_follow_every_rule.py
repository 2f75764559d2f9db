"""``path_problem`` accepts exactly the paths every rule accepts (relative, each name a file name:
:func:`segment_problem`, not the manifest's own name), whatever short cut it takes for the plain
paths targets write (a manifest lists thousands of them)."""

from __future__ import annotations

import re

from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.generator.paths import MANIFEST, path_problem, segment_problem

PIECES = ["a", "B", "_", ".", "..", "-", "+", "/", " ", "CON", "nul", "Com1", "x" * 120, "é"]
PIECES += ["\\", ":", "\x00", "\n", "1", "*", ".acordcs-manifest.json"]


def _by_the_rules(path: str) -> bool:
    if not path or path.startswith("/") or re.match(r"[A-Za-z]:", path) or path == MANIFEST:
        return False
    return all(segment_problem(name) is None for name in path.split("/"))


@settings(max_examples=3000, deadline=None)
@given(st.lists(st.sampled_from(PIECES), max_size=8).map("".join))
def test_path_problem_accepts_exactly_what_every_rule_accepts(path: str):
    assert (path_problem(path) is None) == _by_the_rules(path)


def test_plain_paths_and_their_traps():
    assert path_problem("weblab_app/base/Locomotion.py") is None
    assert path_problem("bin/UserSide-start") is None
    for bad in ("a/CON.py", "a/nul", "a./b", "a/b.", "a/" + "x" * 256, MANIFEST, "a//b", "./a"):
        assert path_problem(bad) is not None, bad
