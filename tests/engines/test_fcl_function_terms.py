"""jFuzzyLogic's FUNCTION terms (issue 23, real FCL files): an output singleton at a point computed
from the inputs, read from FCL, fired, batched and written back. The expression language is held
to jFuzzyLogic's grammar (Fcl.g: fun_pm / fun_md / fun_mp / fun_atom, all left-associative) and
its evaluators (membership/functions/Mff*.java: MffLog is log10, MffLn the natural log, MffModulus
Java's % (sign of the dividend), MffPow Math.pow); it is parsed by a grammar and run as a postfix
program, never by eval, with limits on size and nesting."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.engines.fuzzy import read_fcl, write_fcl
from acordcs.engines.fuzzy.fcl_function import MAX_DEPTH, MAX_TEXT, parse_function
from acordcs.engines.rule_engine import RuleError


def _java(op: str, a: float, b: float) -> float:
    """The binary operators as Java doubles compute them (NaN where Java gives NaN or infinity)."""
    try:
        if op == "+":
            return a + b
        if op == "-":
            return a - b
        if op == "*":
            return a * b
        if op == "/":
            return a / b if b != 0 else math.nan
        if op == "%":
            return math.fmod(a, b) if b != 0 else math.nan
        return math.pow(a, b) if not (a < 0 and b != int(b)) else math.nan
    except (OverflowError, ValueError):
        return math.nan


@st.composite
def _tree(draw, depth: int = 0):
    """(text, value) of a random expression over x = 1.5 and z = -2."""
    if depth > 3 or draw(st.booleans()):
        kind = draw(st.sampled_from(["num", "x", "z"]))
        if kind == "num":
            v = draw(st.sampled_from([0.0, 1.0, 2.0, 0.5, 3.25, 10.0]))
            return repr(v), v
        return kind, {"x": 1.5, "z": -2.0}[kind]
    if draw(st.integers(0, 3)) == 0:
        fn = draw(st.sampled_from(["exp", "ln", "log", "sin", "cos", "tan", "abs"]))
        text, v = draw(_tree(depth + 1))
        f = {"exp": math.exp, "ln": math.log, "log": math.log10, "sin": math.sin,
             "cos": math.cos, "tan": math.tan, "abs": abs}[fn]  # fmt: skip
        try:
            value = f(v) if math.isfinite(v) else math.nan
        except (ValueError, OverflowError):
            value = math.nan
        return f"{fn}({text})", value
    op = draw(st.sampled_from(["+", "-", "*", "/", "%", "^"]))
    (lt, lv), (rt, rv) = draw(_tree(depth + 1)), draw(_tree(depth + 1))
    value = _java(op, lv, rv) if math.isfinite(lv) and math.isfinite(rv) else math.nan
    return f"({lt} {op} {rt})", value


@settings(max_examples=300, deadline=None)
@given(tree=_tree())
def test_an_expression_computes_what_jfuzzylogic_computes(tree) -> None:
    text, want = tree
    got = parse_function(text).evaluate({"x": 1.5, "z": -2.0})
    if math.isfinite(want) and abs(want) < 1e300:
        assert got == pytest.approx(want, rel=1e-12, abs=1e-12)
    else:
        assert not math.isfinite(got) or abs(got) >= 1e300


@pytest.mark.parametrize(
    ("text", "want"),
    [
        ("2 ^ 3 ^ 2", 64.0),  # left to right, as Fcl.g's fun_mp
        ("8 - 2 - 1", 5.0),
        ("8 / 2 / 2", 2.0),
        ("1 + 2 * 3", 7.0),
        ("7 % 3 * 2", 2.0),  # % binds as ^, tighter than *
        ("-7 % 3", -1.0),  # Java's remainder keeps the dividend's sign
        ("LOG(1000) + Ln(1)", 3.0),
        ("2 * (x + 1) (* a comment *)", 5.0),
    ],
)
def test_precedence_and_functions_are_jfuzzylogics(text, want) -> None:
    assert parse_function(text).evaluate({"x": 1.5}) == pytest.approx(want)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("1 +" * (MAX_TEXT // 3 + 1) + "1", "characters; at most"),
        ("(" * (MAX_DEPTH + 1) + "1" + ")" * (MAX_DEPTH + 1), "nest 51 deep; at most 50"),
        ("sqrt(2)", "unknown function sqrt()"),
        ("2 +* 3", "does not parse at character"),
        ("__import__('os')", "does not parse"),
    ],
)
def test_what_the_expression_language_refuses(text, words) -> None:
    with pytest.raises(RuleError, match=words.replace("(", r"\(").replace(")", r"\)")):
        parse_function(text)


HEAD = "FUNCTION_BLOCK tsk\nVAR_INPUT x : REAL; z : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
INPUTS = (
    "FUZZIFY x TERM lo := trian 0 0 10; TERM hi := trian 0 10 10; END_FUZZIFY\n"
    "FUZZIFY z TERM any := trape 0 0 10 10; END_FUZZIFY\n"
)
RULES = (
    "RULEBLOCK r\n RULE 1 : IF x IS lo THEN y IS a;\n RULE 2 : IF x IS hi AND z IS any THEN y IS b;\n"
    "END_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
)


def _tsk(a: str = "FUNCTION 2 * x + 1", b: str = "FUNCTION ln(z) + x ^ 2", extra: str = "") -> str:
    return (
        HEAD
        + INPUTS
        + f"DEFUZZIFY y\n TERM a := {a};\n TERM b := {b};\n{extra} METHOD : COGS;\n"
        + " RANGE := (0 .. 100);\n DEFAULT := 50;\nEND_DEFUZZIFY\n"
        + RULES
    )


@settings(max_examples=40, deadline=None)
@given(x=st.floats(0, 10), z=st.floats(0, 10))
def test_a_function_output_fires_batches_and_reads_back_as_its_formula(x, z) -> None:
    engine = read_fcl(_tsk())["tsk"]
    lo, hi = 1 - x / 10, x / 10
    a, b = 2 * x + 1, (math.log(z) if z > 0 else math.nan) + x**2
    engine.set("x", x)
    engine.set("z", z)
    engine.fire("r")
    if hi > 0 and not math.isfinite(b):  # ln(0): the term is undefined, the output its DEFAULT
        want = 50.0
    else:
        b = min(max(b, 0.0), 100.0) if hi > 0 else 0.0  # a point is clamped into the range
        want = (lo * a + hi * b) / (lo + hi)
    assert engine.get("y") == pytest.approx(want, abs=1e-9)
    batch = engine.batch("r", {"x": np.array([x]), "z": np.array([z])})["y"][0]
    assert batch == pytest.approx(engine.get("y"), abs=1e-12)
    again = read_fcl(write_fcl(engine))["tsk"]
    again.set("x", x)
    again.set("z", z)
    again.fire("r")
    assert again.get("y") == pytest.approx(engine.get("y"), abs=1e-12)


@pytest.mark.parametrize(
    ("text", "words"),
    [
        (_tsk(b="trian 0 5 10"), "output y mixes FUNCTION terms with shaped ones"),
        (_tsk(a="FUNCTION 2 * w"), "reads w, which is not declared in VAR_INPUT"),
        (_tsk(a="FUNCTION 2 * y"), "reads y, which is not declared in VAR_INPUT"),
        (_tsk().replace(" RANGE := (0 .. 100);\n", ""), "give it RANGE"),
        (_tsk(a="FUNCTION sqrt(x)"), "unknown function sqrt()"),
        (
            _tsk().replace("TERM any := trape 0 0 10 10;", "TERM any := FUNCTION x + 1;"),
            "a FUNCTION term in FUZZIFY is 1 only where the input equals",
        ),
    ],
)
def test_what_the_reader_refuses_is_said_at_the_term(text, words) -> None:
    with pytest.raises(RuleError, match=words.replace("(", r"\(").replace(")", r"\)")) as caught:
        read_fcl(text, filename="t.fcl")
    assert caught.value.line is not None and str(caught.value).startswith("t.fcl:")
