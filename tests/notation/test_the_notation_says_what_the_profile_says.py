"""The notation says what the profile says, and only that: an element keyword for every
stereotype the architecture reads (CtxVariable is written on an attribute), a relation keyword
for every relation it finds, and tags checked against the profile by the model checks."""

from __future__ import annotations

from acordcs.model.architecture import STEREOTYPES
from acordcs.notation import outline
from acordcs.notation.syntax import grammar
from acordcs.profile import profile


def test_every_stereotype_has_a_keyword_and_every_keyword_a_stereotype() -> None:
    stereotypes = {s.name for s in profile()}
    assert set(outline.KINDS.values()) | {outline.VARIABLE} == stereotypes
    for keyword in outline.KINDS:
        assert keyword in grammar()


def test_every_relation_the_architecture_finds_has_a_keyword() -> None:
    from acordcs.model.architecture import relation_between

    found = {
        relation_between(a, b, directed=True)[0]
        for a in STEREOTYPES
        for b in STEREOTYPES
        if relation_between(a, b, directed=True) is not None
    }
    assert found == set(outline.RELATIONS.values())
    for keyword in outline.RELATIONS:
        assert keyword in grammar()
