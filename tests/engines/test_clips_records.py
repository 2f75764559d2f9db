"""What comes back from CLIPS: the lean call and the records read through clipspy's C types.

These tests fail loudly if a new clipspy changes the internals the engine reads (type codes, the
layout of values and multifields, the function-call builder).
"""

from __future__ import annotations

import math

import pytest
from clips import common
from clips._clips import lib

from acordcs.engines.clips import ClipsEngine
from acordcs.engines.clips.bridge import MULTIFIELD, Bridge
from acordcs.engines.clips.records import Sites, decode, python_constant, read_value


def call(bridge: Bridge, body: str, *args: object) -> object:
    """Define a deffunction returning ``body`` and call it through the lean call."""
    params = " ".join(f"?a{i}" for i in range(len(args)))
    bridge.build(f"(deffunction MAIN::probe ({params}) {body})")
    return bridge.call(b"probe", list(args))


def test_the_clipspy_internals_the_engine_uses_are_there():
    assert lib.FCBE_NO_ERROR == 0
    assert [int(t) for t in common.CLIPSType] == list(range(10))
    assert int(common.CLIPSType.MULTIFIELD) == MULTIFIELD


def test_values_cross_the_lean_call_both_ways_exactly():
    bridge = Bridge()
    sent = [2.5, -7, 2**62, True, False, None, 'it\'s "x" ü', math.inf]
    params = " ".join(f"?a{i}" for i in range(len(sent)))
    result = call(bridge, f"(create$ {params} a-symbol)", *sent)
    assert result.header.type == MULTIFIELD
    multifield = result.multifieldValue
    got = [read_value(multifield.contents + i, bridge.ptr) for i in range(multifield.length)]
    assert got == [*sent, "a-symbol"]
    assert [type(v) for v in got[:3]] == [float, int, int]
    nan = call(bridge, "?a0", math.nan)
    assert nan.header.type == 0 and math.isnan(read_value(nan, bridge.ptr))


def test_decode_applies_assignments_and_returns_calls_and_notes_in_order():
    bridge = Bridge()
    sites = Sites()
    assert sites.constant(2, 120) == 1
    assert sites.call(7, 3, 2) == 2
    assert sites.call(8, 4, 0) == 3
    values: list[object] = [False, 0.0, 0.0, "old"]
    result = call(
        bridge,
        '(create$ 1 1.5 -1 -2 "a" 2.5 err 3 "boom" 3 "new" op "A.f" 2 x 9 -3 1 nil)',
    )
    calls, notes = decode(result.multifieldValue, bridge.ptr, sites.entries, values, {1, 2}, set())
    assert values == [False, None, 120, "new"]
    assert calls == [(7, 3, ["a", 2.5]), ("A.f", 0, ["x", 9]), (8, 4, [])]
    assert notes == [("err", 3, "boom"), ("set", 1, None)]  # None: numeric variable 1 unset


@pytest.mark.parametrize(
    ("body", "what"),
    [
        ("(create$ bogus)", "'bogus'"),
        ("(create$ 1 2.0 99 1)", "99"),  # no variable 99
        ("(create$ -5)", "-5"),  # no site 5
        ("(create$ 1)", "1"),  # cut short
        ("(create$ -1)", "-1"),  # a call site whose arguments are missing
        ("(create$ 0 1)", "0"),
    ],
)
def test_unreadable_records_are_reported_not_read_past(body, what):
    bridge = Bridge()
    sites = Sites()
    sites.call(1, 1, 2)
    values: list[object] = [False, 0]
    _calls, notes = decode(
        call(bridge, body).multifieldValue, bridge.ptr, sites.entries, values, set(), set()
    )
    assert notes[-1][0] == "err" and notes[-1][2].startswith(f"unreadable record {what} ")


def test_a_native_rule_that_spoils_the_records_is_a_fault():
    engine = ClipsEngine()
    engine.declare("A.x", 0)
    engine.defrule(
        "(defrule spoil (acord-fire) => (bind ?*acord-out* (create$ ?*acord-out* x)))", "s"
    )
    engine.fire("s")
    assert [e.message for e in engine.errors] == [
        "unreadable record 'x' from CLIPS; did a native rule bind ?*acord-out*?"
    ]


@pytest.mark.parametrize(
    ("literal", "expected"),
    [
        ("3", 3),
        ("2.5", 2.5),
        ("1e3", 1000.0),
        ("100000000000000000000000", 1e23),  # beyond 64 bits: CLIPS holds a float
        ("'say \"hi\" \\ (assert (x))'", 'say "hi" \\ (assert (x))'),
        ("true", True),
        ("false", False),
    ],
)
def test_an_assigned_literal_comes_back_as_clips_holds_it(literal, expected):
    """A literal's assignment is recorded by its site: Python's copy must be what CLIPS holds."""
    engine = ClipsEngine()
    engine.declare("A.v", "start")
    engine.declare("A.copy", "start")
    engine.defrule(f"r: if true then A.v = {literal}", "s")
    # The same value through a variable: recorded as a value CLIPS sends back.
    engine.defrule("c: if A.v != A.copy then A.copy = A.v", "s")
    engine.fire("s")
    got, copy = engine.get("A.v"), engine.get("A.copy")
    assert got == expected and type(got) is type(expected)
    assert copy == got and type(copy) is type(got)
    assert python_constant(expected) == got


def test_a_variable_gets_its_fact_when_a_rule_first_reads_it():
    engine = ClipsEngine()
    engine.declare("A.go", 0)
    engine.declare("A.x", 0)
    engine.declare("A.seen", False)
    # The writer is compiled while nothing reads A.x: its firing must still wake a later reader.
    engine.defrule("write: if A.go == 1 then A.x = 5", "s")

    def facts() -> list[str]:
        return sorted(str(f) for f in engine._bridge.env.facts() if "acord-var" in str(f))

    assert facts() == ["(acord-var (i 1))"]
    engine.defrule("read: if A.x == 5 then A.seen = true", "s")
    assert facts() == ["(acord-var (i 1))", "(acord-var (i 2))"]
    engine.set("A.go", 1)
    engine.fire("s")
    assert engine.get("A.seen") is True
