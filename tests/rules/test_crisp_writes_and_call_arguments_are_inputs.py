"""What ``bind`` makes of a crisp set's written variables and of the variables an operation call
is given: a crisp engine keeps what it assigned between firings, so what it writes is also given
to it before each firing; a call's arguments are read by the action (inputs, never triggers)."""

from __future__ import annotations

from acordcs.rules import parse_rule
from acordcs.rules.binding import Scope, ScopeElement, Unresolved, bind


def scope() -> Scope:
    return Scope(
        [
            ScopeElement("Sensor", {"level": "l", "trend": "t"}, {}),
            ScopeElement("Pump", {"rate": "r", "count": "c"}, {"start": 2, "stop": 0}),
            ScopeElement("Pump.Valve", {"open": "o"}, {"set": 1}, short="Valve"),
        ]
    )


CRISP = [
    "a: if Sensor.level > 3 then Pump.rate = 2 and Pump.count = Pump.count + 1",
    "b: if Pump.rate > 1 then Pump.start(Sensor.trend, Valve.open * 2)",
    "c: if Sensor.level < 1 then Valve.set(Pump.rate) and Pump.stop()",
]


def test_a_crisp_sets_written_variables_are_inputs_after_what_it_reads():
    found = bind(scope(), [parse_rule(r, "crisp") for r in CRISP], "crisp")
    assert found.problems == []
    # condition reads first, then what actions read (assigned values, call arguments), then
    # the written variables not already there, each once, in order of first use
    assert found.inputs == (
        "Sensor.level",
        "Pump.rate",
        "Pump.count",
        "Sensor.trend",
        "Pump.Valve.open",
    )
    assert found.outputs == ("Pump.rate", "Pump.count")
    assert found.triggers == ("Sensor.level", "Pump.rate")


def test_the_same_rules_under_a_fuzzy_kind_give_no_written_variable_as_input():
    rules = [parse_rule("if Sensor.level > 3 then Pump.rate = 2", "crisp")]
    crisp, fuzzy = bind(scope(), rules, "crisp"), bind(scope(), rules, "fuzzy")
    assert crisp.inputs == ("Sensor.level", "Pump.rate")
    assert fuzzy.inputs == ("Sensor.level",)
    assert crisp.outputs == fuzzy.outputs == ("Pump.rate",)


def test_a_calls_variable_arguments_are_inputs_and_never_triggers():
    rules = [
        parse_rule("if Sensor.level > 3 then Pump.start(Sensor.trend, Valve.open * 2)", "crisp")
    ]
    found = bind(scope(), rules, "fuzzy")  # not crisp: the arguments are inputs for their own sake
    assert found.inputs == ("Sensor.level", "Sensor.trend", "Pump.Valve.open")
    assert found.triggers == ("Sensor.level",)
    assert found.outputs == ()
    assert found.operations == ("Pump.start",)
    assert {w: t.name for w, t in found.variables.items()} == {
        "Sensor.level": "Sensor.level",
        "Sensor.trend": "Sensor.trend",
        "Valve.open": "Pump.Valve.open",
    }
    assert {w: (t.name, t.kind, t.payload) for w, t in found.calls.items()} == {
        "Pump.start": ("Pump.start", "operation", 2)
    }


def test_operations_are_listed_once_in_order_of_first_call():
    found = bind(scope(), [parse_rule(r, "crisp") for r in CRISP], "crisp")
    assert found.operations == ("Pump.start", "Pump.Valve.set", "Pump.stop")
    assert list(found.calls) == ["Pump.start", "Valve.set", "Pump.stop"]
    targets = found.targets()
    assert list(targets) == [
        ("attribute", "Sensor.level"),
        ("attribute", "Pump.rate"),
        ("attribute", "Pump.count"),
        ("attribute", "Sensor.trend"),
        ("attribute", "Pump.Valve.open"),
        ("operation", "Pump.start"),
        ("operation", "Pump.Valve.set"),
        ("operation", "Pump.stop"),
    ]


def test_an_unknown_call_argument_is_a_problem_of_its_use_and_binds_nothing():
    rule = parse_rule("if Sensor.level > 3 then Pump.start(Sensor.depth, Pump.rate)", "crisp")
    found = bind(scope(), [rule], "crisp")
    ((where, name, use, why),) = found.problems
    assert (where, name.text, use) == (rule, "Sensor.depth", "action-read")
    assert isinstance(why, Unresolved)
    assert (why.member, why.element, set(why.known)) == ("depth", "Sensor", {"level", "trend"})
    assert found.inputs == ("Sensor.level", "Pump.rate")
    assert "Sensor.depth" not in found.variables


def test_an_operation_name_resolves_among_operations_not_attributes():
    # "rate" is an attribute of Pump, not an operation: called, it does not resolve
    rule = parse_rule("if Sensor.level > 3 then Pump.rate(1)", "crisp")
    ((_, name, use, why),) = bind(scope(), [rule], "crisp").problems
    assert (name.text, use) == ("Pump.rate", "call")
    assert isinstance(why, Unresolved) and set(why.known) == {"start", "stop"}
    # and a bare operation name only one element has resolves to it
    found = bind(scope(), [parse_rule("if Sensor.level > 3 then set(1)", "crisp")], "crisp")
    assert found.operations == ("Pump.Valve.set",)


def test_aliases_apply_to_called_operations_and_their_arguments():
    rule = parse_rule("if lvl > 3 then go(tr)", "crisp")
    found = bind(
        scope(),
        [rule],
        "crisp",
        aliases={"lvl": "Sensor.level", "go": "Pump.start", "tr": "Sensor.trend"},
    )
    assert found.problems == []
    assert found.inputs == ("Sensor.level", "Sensor.trend")
    assert found.operations == ("Pump.start",)
    assert found.calls["go"].name == "Pump.start"
