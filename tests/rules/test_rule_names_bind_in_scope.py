"""What a policy set's rule names stand for (``acordcs.rules.binding``): the one resolution the
validator, ``describe`` and hand-made runtime policy sets share."""

from __future__ import annotations

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
