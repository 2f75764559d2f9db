"""What a policy set's rule names stand for (``acordcs.rules.binding``): the one resolution the
validator, ``describe`` and hand-made runtime policy sets share."""

from __future__ import annotations

import dataclasses

import pytest

from acordcs.rules import parse_rule
from acordcs.rules.binding import (
    Ambiguous,
    Scope,
    ScopeElement,
    Target,
    Unresolved,
    bind,
    default_label,
    rule_syntax,
)


def scope() -> Scope:
    return Scope(
        [
            ScopeElement("Control", {"speed": "s", "angle": "a"}, {}),
            ScopeElement("Robot", {"retries": "r", "speed": "rs"}, {"recover": 0, "stop": 0}),
            ScopeElement("Robot.Drive", {"rate": "d"}, {}, short="Drive"),
            ScopeElement("Arm", {"rate": "x"}, {"stop": 0}),
        ]
    )


def test_qualified_bare_and_port_names_resolve():
    s = scope()
    assert s.resolve("Control.angle", "attribute").name == "Control.angle"
    assert s.resolve("angle", "attribute").payload == "a"
    # a port by its own name or with its component
    assert s.resolve("Drive.rate", "attribute").name == "Robot.Drive.rate"
    assert s.resolve("Robot.Drive.rate", "attribute").name == "Robot.Drive.rate"
    assert s.resolve("recover", "operation").name == "Robot.recover"


def test_ambiguous_and_unknown_names_say_why():
    s = scope()
    found = s.resolve("speed", "attribute")
    assert isinstance(found, Ambiguous)
    assert [t.name for t in found.candidates] == ["Control.speed", "Robot.speed"]
    assert isinstance(s.resolve("stop", "operation"), Ambiguous)
    unknown = s.resolve("Nowhere.speed", "attribute")
    assert isinstance(unknown, Unresolved) and unknown.owners == () and unknown.element == "Nowhere"
    missing = s.resolve("Control.sped", "attribute")
    assert isinstance(missing, Unresolved) and set(missing.known) == {"speed", "angle"}
    bare = s.resolve("sped", "attribute")
    assert isinstance(bare, Unresolved) and bare.element is None and "speed" in bare.known


def test_inputs_outputs_and_triggers_follow_first_use_per_kind():
    rules = [
        parse_rule(text, "crisp")
        for text in (
            "a: if Control.angle > 1 then Robot.retries = Robot.retries + 1",
            "b: if Drive.rate > 0 then Arm.rate = Control.speed",
            "c: if Arm.rate < 0 then Robot.recover()",
        )
    ]
    found = bind(scope(), rules, "crisp")
    assert found.problems == []
    assert found.triggers == ("Control.angle", "Robot.Drive.rate", "Arm.rate")
    assert found.outputs == ("Robot.retries", "Arm.rate")
    # condition reads, then what actions read, then (crisp) what they assign
    assert found.inputs == (
        "Control.angle",
        "Robot.Drive.rate",
        "Arm.rate",
        "Robot.retries",
        "Control.speed",
    )
    assert found.operations == ("Robot.recover",)
    assert {w: t.name for w, t in found.variables.items()}["Drive.rate"] == "Robot.Drive.rate"
    targets = found.targets()
    assert targets["attribute", "Robot.retries"][1] == ["Robot.retries"]
    assert isinstance(targets["operation", "Robot.recover"][0], Target)


def test_fuzzy_outputs_are_not_inputs_and_problems_are_listed_not_raised():
    rules = [parse_rule("if angle is wide and speed is low then Robot.retries is high", "fuzzy")]
    found = bind(scope(), rules, "fuzzy")
    assert found.outputs == ("Robot.retries",) and "Robot.retries" not in found.inputs
    ((rule, name, use, why),) = found.problems
    assert (name.text, use, type(why)) == ("speed", "read", Ambiguous)
    assert rule is rules[0]


def test_names_bound_by_hand_resolve_in_place_of_the_written_ones():
    rules = [parse_rule("if speed is low then Robot.retries is high", "fuzzy")]
    found = bind(scope(), rules, "fuzzy", aliases={"speed": "Control.speed"})
    assert found.problems == []
    assert found.variables["speed"].name == "Control.speed"


def test_one_default_label_and_one_syntax_per_engine():
    assert default_label(2, {"rule2", "rule3"}) == "rule4"
    assert default_label(1, ()) == "rule1"
    assert (rule_syntax("fuzzy"), rule_syntax("clips"), rule_syntax(None)) == (
        "fuzzy",
        "crisp",
        "fuzzy",
    )
    assert rule_syntax("jess") == "crisp"  # an engine registered at run time: crisp unless it says


def test_a_scope_lists_its_elements_and_members_and_shows_a_port_by_its_own_name():
    s = scope()
    assert s.names() == ["Control", "Robot", "Robot.Drive", "Arm"]
    assert s.members("attribute") == ["speed", "angle", "retries", "rate"]
    assert s.members("operation") == ["recover", "stop"]
    assert [e.shown for e in s.elements] == ["Control", "Robot", "Drive", "Arm"]


def test_a_short_name_equal_to_the_name_is_one_owner_not_two():
    s = Scope([ScopeElement("Pump", {"rate": 1, "count": 2}, {}, short="Pump")])
    missing = s.resolve("Pump.nope", "attribute")
    assert isinstance(missing, Unresolved)
    assert len(missing.owners) == 1 and missing.known == ("rate", "count")


def test_resolutions_are_immutable_the_scope_hands_the_same_one_to_every_rule():
    s = scope()
    target = s.resolve("Control.angle", "attribute")
    assert target is s.resolve("Control.angle", "attribute")
    assert isinstance(target, Target)
    for value, field in ((target, "member"), (target.element, "name")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(value, field, "x")
    ambiguous = s.resolve("speed", "attribute")
    unresolved = s.resolve("nothing", "attribute")
    for value, field in ((ambiguous, "candidates"), (unresolved, "member")):
        with pytest.raises(dataclasses.FrozenInstanceError):
            setattr(value, field, ())


def test_the_next_free_default_label_is_the_first_not_taken():
    assert default_label(2, {"rule2"}) == "rule3"
    assert default_label(3, {"rule1", "rule3", "rule4", "rule6"}) == "rule5"
