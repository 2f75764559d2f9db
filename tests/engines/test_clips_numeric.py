"""Numeric mode: conditions on variables declared as numbers run without type checks, only while safe.

Each test shows that a value of another kind in a numeric variable (unset, text from a rule, a
native rule's binding, a changed declaration) still gives the documented result: an evaluation
error and a false condition, never a CLIPS error; and that the oracle agrees on random typed rules.
"""

from __future__ import annotations

import functools
import math

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.engines.clips import ClipsEngine
from tests.support.clips_oracle import (
    STRINGS,
    Oracle,
    check_fire,
    conditions,
    numbers_,
    recorder,
    string_literal,
    values,
)


def flag(engine: ClipsEngine) -> bool:
    """Numeric mode as CLIPS has it."""
    return str(engine._bridge.env.eval("?*acord-num*")) == "TRUE"


def typed() -> ClipsEngine:
    engine = ClipsEngine()
    engine.declare("A.x", 1.0, type="double")
    engine.declare("A.n", 0, type="int")
    engine.declare("A.s", "txt", type="string")
    engine.declare("A.out", 0, type="int")
    return engine


def clips_errors(engine: ClipsEngine) -> list[str]:
    return [e.message for e in engine.errors if "CLIPS" in e.message]


def test_conditions_on_numeric_variables_compile_with_an_unchecked_branch():
    engine = typed()
    engine.declare("B.any", 0)  # untyped
    engine.defrule("r: if A.x < 3 and A.n >= A.x then A.out = 1", "s")
    text = engine.construct("s", "r")
    unchecked = "(if ?*acord-num* then (and (not (>= ?*A.x* 3)) (not (< ?*A.n* ?*A.x*))"
    assert unchecked in text
    for other in (
        "if B.any < 3 then A.out = 1",  # untyped: could hold anything
        "if A.x / 2 < 3 then A.out = 1",  # division: by zero would be a CLIPS error
        "if -A.n * 2 >= A.x + 1 then A.out = 1",  # integer arithmetic may overflow: checked
        "if A.s < 'b' then A.out = 1",  # text
        "if A.x == true then A.out = 1",  # a boolean literal in a comparison
    ):
        engine.defrule(f"o: {other}", "s")
        assert "?*acord-num*" not in engine.construct("s", "o").split("=>")[0], other


def test_the_flag_holds_only_while_every_numeric_variable_holds_a_number():
    engine = typed()
    engine.defrule("r: if A.x < 3 then A.out = A.out + 1", "s")
    engine.fire("s")
    assert flag(engine) and engine.get("A.out") == 1
    engine.set("A.x", None)
    engine.fire("s")
    assert not flag(engine) and engine.get("A.out") == 1
    assert [e.message for e in engine.errors] == [
        "'<' needs two numbers or two strings, not unset and number"
    ]
    engine.set("A.x", 2)  # an int is a number too
    engine.fire("s")
    assert flag(engine) and engine.get("A.out") == 2


def test_a_numeric_variable_never_set_gives_the_documented_results():
    engine = ClipsEngine()
    engine.declare("A.x", type="double")  # unset
    engine.declare("A.hits", "", type="string")
    engine.defrule("lt: if A.x < 1 then A.hits = 'lt'", "s")
    engine.defrule("eq: if A.x == 0 then A.hits = 'eq'", "s")
    engine.defrule("ne: if A.x != 0 then A.hits = A.hits + 'ne'", "s")
    engine.fire("s")
    assert not flag(engine)
    assert engine.get("A.hits") == ""  # ne fired, its action failed: text + text is no number
    assert {(e.rule, e.message) for e in engine.errors} == {
        ("lt", "'<' needs two numbers or two strings, not unset and number"),
        ("ne", "'+' needs two numbers, not string and string"),
    }
    assert not clips_errors(engine)


def test_a_rule_giving_a_numeric_variable_text_turns_the_flag_off_at_once():
    engine = typed()
    engine.defrule("first: if A.x > 0 then A.x = A.s", "s")
    engine.defrule("second: if A.x < 3 then A.out = 1", "s")  # evaluated again on the text
    engine.defrule("third: if A.x == 1 then A.out = 2", "s")
    engine.fire("s")
    assert engine.get("A.x") == "txt" and engine.get("A.out") == 0
    assert not flag(engine)
    assert [(e.rule, e.message) for e in engine.errors] == [
        ("second", "'<' needs two numbers or two strings, not string and number")
    ]
    engine.set("A.x", 5.0)
    engine.fire("s")  # numbers again: unchecked until first puts the text back
    assert engine.get("A.x") == "txt" and engine.error_count == 2
    assert not clips_errors(engine)


def test_a_literal_of_another_kind_turns_the_flag_off_too():
    engine = typed()
    engine.defrule("first: if A.n == 0 then A.n = 'none'", "s")
    engine.defrule("second: if A.n >= 0 then A.out = 7", "s")
    engine.fire("s")
    assert engine.get("A.n") == "none" and engine.get("A.out") == 0 and not flag(engine)
    assert [e.rule for e in engine.errors] == ["second"]


def test_a_number_then_text_in_one_firing_leaves_the_flag_off():
    """Found by the oracle: the first assignment alone would turn numeric mode on again."""
    engine = typed()
    engine.declare("A.u", type="double")  # unset: numeric mode off
    engine.defrule("r: if A.u == A.u then A.out = A.out + 1 and A.u = A.n and A.u = A.s", "s")
    for expected in (1, 2, 3):
        engine.fire("s")
        assert not flag(engine)
        assert engine.get("A.u") == "txt" and engine.get("A.out") == expected
    assert engine.error_count == 0


def test_native_rules_turn_numeric_mode_off_for_good():
    engine = typed()
    engine.defrule("lt: if A.x < 3 then A.out = 1", "crisp")
    engine.fire("crisp")
    assert flag(engine)
    # A native rule binds the global directly: the engine never hears of it.
    engine.defrule('(defrule poke (acord-fire) => (bind ?*A.x* "poked"))', "native")
    engine.fire("native")
    engine.set("A.out", 0)
    engine.fire("crisp")
    assert not flag(engine) and engine.get("A.out") == 0
    assert [e.message for e in engine.errors] == [
        "'<' needs two numbers or two strings, not string and number"
    ]
    engine.set("A.x", 1.0)
    engine.fire("crisp")
    assert not flag(engine) and engine.get("A.out") == 1  # right, checked: off for good


def test_a_changed_declaration_turns_numeric_mode_off_for_good():
    engine = typed()
    engine.defrule("lt: if A.x < 3 then A.out = 1", "s")
    engine.declare("A.x", "now text", type="string")
    engine.fire("s")
    assert not flag(engine) and engine.get("A.out") == 0
    assert [e.message for e in engine.errors] == [
        "'<' needs two numbers or two strings, not string and number"
    ]


def test_nan_in_numeric_mode_follows_ieee():
    engine = ClipsEngine()
    engine.declare("A.x", math.nan, type="double")
    engine.declare("A.hits", "", type="string")
    engine.defrule("eq: if A.x == A.x then A.hits = 'eq'", "s")
    engine.defrule("ne: if A.x != 0 then A.hits = 'ne'", "s")
    engine.defrule("lt: if A.x < 1 or A.x >= 1 or A.x > 1 or A.x <= 1 then A.hits = 'ordered'", "s")
    engine.defrule("prop: if not (A.x - 1 < 0) then A.x = A.x + 1", "s")
    engine.fire("s")
    assert flag(engine)
    assert "?*acord-num*" in engine.construct("s", "lt")
    assert engine.get("A.hits") == "ne"
    assert math.isnan(engine.get("A.x"))
    assert engine.error_count == 0


# ------------------------------------------------------------------ the oracle, on typed variables
NUMERIC = ["A.x", "A.y", "B.z"]
TYPES = {"A.x": "double", "A.y": "double", "B.z": "int", "B.s": "string", "A.f": "boolean"}


@functools.cache  # made once per index: see tests.support.clips_oracle.numbers_
def typed_actions(index: int) -> st.SearchStrategy[str]:
    assign = st.one_of(
        st.tuples(st.sampled_from(NUMERIC), numbers_()).map(lambda t: f"{t[0]} = {t[1]}"),
        # Something else than a number in a numeric variable: numeric mode must go off at once.
        st.tuples(st.sampled_from(NUMERIC), st.sampled_from(["B.s", "A.f", "'a'", "true"])).map(
            lambda t: f"{t[0]} = {t[1]}"
        ),
        st.tuples(st.just("A.f"), conditions()).map(lambda t: f"A.f = ({t[1]})"),
        st.sampled_from(STRINGS).map(lambda s: f"B.s = {string_literal(s)}"),
    )
    trace = f"Trace.fired({index})"
    return st.lists(assign, max_size=3).map(lambda xs: " and ".join([trace, *xs]))


@st.composite
def typed_rule_sets(draw):
    n = draw(st.integers(1, 6))
    return [f"if {draw(conditions())} then {draw(typed_actions(i))}" for i in range(n)]


typed_values = values.map(
    lambda v: {**v, "A.x": v["A.x"] if v["A.y"] != 0 else None}  # now and then unset
)


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(typed_rule_sets(), st.lists(typed_values, min_size=1, max_size=3))
def test_typed_random_rule_sets_match_oracle(rules, rounds):
    engine = ClipsEngine()
    for name, value in rounds[0].items():
        engine.declare(name, value, type=TYPES[name])
    for i, text in enumerate(rules):
        engine.defrule(f"r{i}: {text}", "random")
    calls = recorder(engine, ["Trace.fired"])
    oracle = Oracle(rules, list(TYPES))
    env = dict(rounds[0])
    for i, round_values in enumerate(rounds):
        if i:
            for name, value in round_values.items():
                engine.set(name, value)
            env.update(round_values)
        check_fire(engine, oracle, env, calls, "random")
        check_fire(engine, oracle, env, calls, "random")
        assert not clips_errors(engine)
