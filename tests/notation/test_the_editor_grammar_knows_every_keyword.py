"""The TextMate grammar for editors (docs/editors/acord.tmLanguage.json: VS Code, Sublime Text,
TextMate and others highlight with it) knows every keyword of acord.lark, and only those."""

from __future__ import annotations

import json
import re

from acordcs.notation import outline
from acordcs.notation.syntax import grammar
from tests.support.toolchain import ROOT

EDITOR = json.loads((ROOT / "docs" / "editors" / "acord.tmLanguage.json").read_text("utf-8"))


def _patterns(node: object):
    if isinstance(node, dict):
        for key in ("match", "begin", "end"):
            if key in node:
                yield node[key]
        for value in node.values():
            yield from _patterns(value)
    elif isinstance(node, list):
        for value in node:
            yield from _patterns(value)


def _alternatives(scope: str) -> set[str]:
    found = next(p for p in EDITOR["patterns"] if p.get("name") == scope)
    return set(re.search(r"\(([a-z|]+)\)", found["match"]).group(1).split("|"))


def test_its_element_and_relation_keywords_are_the_grammars() -> None:
    assert _alternatives("storage.type.element.acord") == set(outline.KINDS)
    assert _alternatives("keyword.control.relation.acord") == set(outline.RELATIONS)


def test_its_other_keywords_are_the_grammars() -> None:
    declared = set(re.findall(r"^_[A-Z]+: /([a-z]+)\\b/", grammar(), flags=re.M))
    assert _alternatives("keyword.other.acord") | {"rules", "variable"} == declared


def test_every_pattern_is_a_regular_expression() -> None:
    patterns = list(_patterns(EDITOR))
    assert len(patterns) > 15
    for pattern in patterns:
        re.compile(pattern)  # Oniguruma's syntax, in the part Python's re shares with it
