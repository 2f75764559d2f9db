"""CLIPS integers are 64-bit and wrap silently; the engine's integer + - * and negation do not:
a result past the 64-bit range is an evaluation error (a FireError, the fire goes on), as a
division by zero is (issue 14). Python's unbounded integers are the oracle."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.engines.clips import ClipsEngine

LOW, HIGH = -(2**63), 2**63 - 1
# products within this distance of the limit are refused too (see the prelude): never wrapped
MARGIN = 4096


def _run(rule: str, a: int, b: int) -> tuple[object, list[str]]:
    engine = ClipsEngine()
    engine.declare("A.a", a, type="int")
    engine.declare("A.b", b, type="int")
    engine.declare("A.r", None)
    engine.declare("A.hit", False)
    engine.defrule(rule, "s")
    engine.fire("s")
    return engine.get("A.r"), [str(e) for e in engine.errors]


def test_the_attack_shapes_are_faults_not_wrapped_numbers() -> None:
    for rule, a in [
        ("if A.a > 0 then A.r = A.a + 1", HIGH),
        ("if A.a < 0 then A.r = A.a - 1", LOW),
        ("if A.a > 0 then A.r = A.a * 2", HIGH),
        ("if A.a < 0 then A.r = -A.a", LOW),
    ]:
        value, errors = _run(rule, a, 0)
        assert value is None, (rule, value)
        assert len(errors) == 1 and "integer overflow" in errors[0], errors


def test_an_overflow_in_a_condition_is_a_fault_and_the_rule_does_not_fire() -> None:
    value, errors = _run("if A.a + A.b < 0 then A.r = 1", HIGH, 1)
    assert value is None
    assert len(errors) == 1 and "integer overflow: '+'" in errors[0]


_ints = st.one_of(
    st.integers(LOW, HIGH),
    st.integers(-(2**32), 2**32),
    st.sampled_from([LOW, LOW + 1, -1, 0, 1, 2, HIGH - 1, HIGH, 2**62, -(2**62), 3037000500]),
)


@settings(max_examples=60, deadline=None)
@given(
    a=_ints,
    b=_ints,
    op=st.sampled_from(["+", "-", "*"]),
    where=st.sampled_from(["action", "condition"]),
)
def test_integer_arithmetic_is_exact_or_a_fault(a: int, b: int, op: str, where: str) -> None:
    exact = {"+": a + b, "-": a - b, "*": a * b}[op]
    if where == "action":
        value, errors = _run(f"if A.a == A.a then A.r = A.a {op} A.b", a, b)
        got = value
    else:  # the condition holds exactly when the result equals the oracle's
        clamped = max(LOW, min(HIGH, exact))
        value, errors = _run(f"if A.a {op} A.b == {clamped} then A.r = 1", a, b)
        got = clamped if value == 1 else None
    if LOW <= exact <= HIGH and not (op == "*" and abs(exact) >= 2**63 - MARGIN):
        assert errors == [] and got == exact, (a, op, b, got, errors)
    elif LOW <= exact <= HIGH:  # a product within the margin: exact, or refused
        assert got == exact or (got is None and "integer overflow" in errors[0])
    else:
        assert got is None and len(errors) == 1 and "integer overflow" in errors[0], (got, errors)


def test_floats_and_small_integers_are_unchanged() -> None:
    assert _run("if A.a > 0 then A.r = A.a * A.b + 1", 3, 4) == (13, [])
    assert _run("if A.a > 0 then A.r = -A.a - A.b", 3, 4) == (-7, [])
    engine = ClipsEngine()
    engine.declare("A.x", 1e308)
    engine.declare("A.r", None)
    engine.defrule("if A.x > 0 then A.r = A.x * 10", "s")
    engine.fire("s")
    assert engine.get("A.r") == float("inf") and list(engine.errors) == []
