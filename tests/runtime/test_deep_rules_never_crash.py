"""No rule that parses (and so validates) crashes an engine: deep or long rules are refused by the
parser with the limit, or run; what an engine raises is its own RuleError, never RecursionError
(issue 14, item 7). FCL files are held to the same limit."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.engines.clips import ClipsEngine
from acordcs.engines.fuzzy import FuzzyEngine
from acordcs.engines.fuzzy.fcl import read_fcl
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import (
    MAX_DEPTH,
    BoolOp,
    Consequent,
    Is,
    Name,
    Rule,
    RuleSyntaxError,
    parse_rule,
)

# Each step wraps the expression once more; runs of one step build the chains of the attack.
CRISP_STEPS = {
    "and": "{} and x > 1",
    "or": "{} or x < 2",
    "not": "not ({})",
    "neg": "-({})",
    "plus": "({}) + 1",
    "times": "({}) * x",
    "compare": "({}) > 0",
    "paren": "({})",
}
FUZZY_STEPS = {
    "and": "{} and x is high",
    "or": "{} or x is low",
    "not": "not ({})",
    "paren": "({})",
}


def _runs(steps: dict[str, str]):
    return st.lists(
        st.tuples(st.sampled_from(sorted(steps)), st.integers(1, MAX_DEPTH + 20)),
        min_size=1,
        max_size=4,
    )


def _build(seed: str, steps: dict[str, str], runs) -> str:
    text = seed
    for step, count in runs:
        for _ in range(count):
            text = steps[step].format(text)
    return text


def _fuzzy_engine() -> FuzzyEngine:
    engine = FuzzyEngine()
    engine.define_variable("x", 0, 10, "low := trian 0 0 5; high := trian 5 10 10")
    engine.define_variable("y", 0, 10, "low := trian 0 0 5; high := trian 5 10 10")
    engine.set("x", 3)
    return engine


def _clips_engine() -> ClipsEngine:
    engine = ClipsEngine()
    engine.declare("x", 3)
    engine.declare("y", 0)
    engine.declare_operation("A.op", ["value"])
    engine.bind_operation("A.op", lambda value: None)
    return engine


def _parses(text: str, kind: str) -> bool:
    try:
        parse_rule(text, kind)  # type: ignore[arg-type]
    except RuleSyntaxError as err:
        assert "limit of" in err.message or "unexpected" in err.message, err.message
        return False
    return True


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(runs=_runs(CRISP_STEPS), where=st.sampled_from(["condition", "assign", "call"]))
def test_a_crisp_rule_that_parses_runs_or_raises_rule_error(runs, where: str) -> None:
    expr = _build("x", CRISP_STEPS, runs)
    text = {
        "condition": f"if {expr} then y = 1",
        "assign": f"if x > 1 then y = {expr}",
        "call": f"if x > 1 then A.op({expr})",
    }[where]
    if not _parses(text, "crisp"):
        return
    engine = _clips_engine()
    try:
        engine.defrule(text, "s")
        engine.fire("s")
    except RuleError:
        pass  # e.g. "a condition must be true or false": the engine's own error, with the rule


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(runs=_runs(FUZZY_STEPS))
def test_a_fuzzy_rule_that_parses_runs(runs) -> None:
    text = f"if {_build('x is low', FUZZY_STEPS, runs)} then y is high"
    if not _parses(text, "fuzzy"):
        return
    engine = _fuzzy_engine()
    engine.defrule(text, "s")
    engine.fire("s")
    assert 0 <= engine.get("y") <= 10


def test_a_tree_built_in_python_too_deep_is_a_rule_error() -> None:
    condition: object = Is(Name("x", 1), (), Name("low", 6))
    for _ in range(5 * MAX_DEPTH):
        condition = BoolOp("and", condition, Is(Name("x", 1), (), Name("high", 6)))
    rule = Rule("fuzzy", "deep", condition, (Consequent(Name("y", 1), Name("high", 6)),))
    with pytest.raises(RuleError, match=f"limit of {MAX_DEPTH} levels"):
        _fuzzy_engine().add_rule(rule, "s")


def _fcl(condition: str) -> str:
    return f"""FUNCTION_BLOCK t
VAR_INPUT x : REAL; END_VAR
VAR_OUTPUT y : REAL; END_VAR
FUZZIFY x TERM low := (0, 1) (10, 0); RANGE := (0 .. 10); END_FUZZIFY
DEFUZZIFY y TERM high := (0, 0) (10, 1); RANGE := (0 .. 10); END_DEFUZZIFY
RULEBLOCK r
RULE 1 : IF {condition} THEN y IS high;
END_RULEBLOCK
END_FUNCTION_BLOCK
"""


def test_fcl_with_ten_thousand_and_is_refused_with_file_line_column() -> None:
    text = _fcl(" AND ".join(["x IS low"] * 10_000))
    with pytest.raises(RuleError, match=f"limit of {MAX_DEPTH} levels") as caught:
        read_fcl(text, filename="deep.fcl")
    assert (caught.value.file, caught.value.line, caught.value.column) == ("deep.fcl", 7, 13)


def test_fcl_at_the_limit_reads_and_fires() -> None:
    engine = read_fcl(_fcl(" AND ".join(["x IS low"] * MAX_DEPTH)))["t"]
    engine.set("x", 3)
    engine.fire("r")
    assert engine.get("y") > 5


@pytest.mark.parametrize("step", sorted(CRISP_STEPS))
@pytest.mark.parametrize("where", ["condition", "assign"])
def test_the_deepest_crisp_rule_that_parses_runs(step: str, where: str) -> None:
    # compare and plus alternate: the shape that costs the compiler the most frames per level
    runs = [(step, 1), ("compare", 1), ("plus", 1)] * MAX_DEPTH

    def rule(n: int) -> str:
        expr = _build("x", CRISP_STEPS, runs[:n])
        return f"if {expr} then y = 1" if where == "condition" else f"if x > 1 then y = ({expr})"

    low, high = 1, len(runs)  # the longest prefix that parses (the limit is monotonic)
    while low < high:
        mid = (low + high + 1) // 2
        low, high = (mid, high) if _parses(rule(mid), "crisp") else (low, mid - 1)
    assert low > MAX_DEPTH // 3
    text = rule(low)
    engine = _clips_engine()
    try:
        engine.defrule(text, "s")
        engine.fire("s")
    except RuleError:
        pass
