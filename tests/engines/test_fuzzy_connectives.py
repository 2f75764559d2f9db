"""The rule connection methods jFuzzyLogic implements (issue 23, real FCL files), each held to its
formula, written here from jFuzzyLogic's sources (net.sourceforge.jFuzzyLogic.ruleConnectionMethod:
RuleConnectionMethodAndMin/OrMax, AndProduct/OrProbOr, AndBoundedDif/OrBoundedSum, AndDrastic/
OrDrastic, AndNilpotent/OrNilpotent, AndHamacher/OrEinstein), on the three paths a degree is
computed: the compiled rule set (fire), the batch call and explain. An AND line sets its dual OR
as jFuzzyLogic's RuleBlock.fclTree does (HAMACHER goes with EINSTEIN)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.engines.fuzzy import FuzzyEngine, Semantics, read_fcl, write_fcl
from acordcs.engines.fuzzy.semantics import AND_OPS

FORMULA = {
    "MIN": min,
    "MAX": max,
    "PROD": lambda a, b: a * b,
    "ASUM": lambda a, b: a + b - a * b,
    "BDIF": lambda a, b: max(0.0, a + b - 1.0),
    "BSUM": lambda a, b: min(1.0, a + b),
    # drastic t-norm: b if a = 1, a if b = 1, 0 otherwise; t-conorm: b if a = 0, a if b = 0, else 1
    "DMIN": lambda a, b: b if a == 1 else (a if b == 1 else 0.0),
    "DMAX": lambda a, b: b if a == 0 else (a if b == 0 else 1.0),
    # nilpotent minimum: min(a, b) if a + b > 1, else 0; maximum: max(a, b) if a + b < 1, else 1
    "NIPMIN": lambda a, b: min(a, b) if a + b > 1 else 0.0,
    "NIPMAX": lambda a, b: max(a, b) if a + b < 1 else 1.0,
    # Hamacher product a*b / (a + b - a*b), 0 when both are 0; Einstein sum (a + b) / (1 + a*b)
    "HAMACHER": lambda a, b: 0.0 if a == 0 and b == 0 else a * b / (a + b - a * b),
    "EINSTEIN": lambda a, b: (a + b) / (1 + a * b),
}
PAIRS = [("MIN", "MAX"), ("PROD", "ASUM"), ("BDIF", "BSUM"), ("DMIN", "DMAX"),
         ("NIPMIN", "NIPMAX"), ("HAMACHER", "EINSTEIN")]  # fmt: skip
DEGREE = st.one_of(st.sampled_from([0.0, 1.0, 0.5, 0.25, 0.75]), st.floats(0.0, 1.0))


def _engine(and_: str, or_: str) -> FuzzyEngine:
    """Inputs a, b whose term 'up' is the input itself (0..1), and c = 1 firing a reference rule
    at degree 1: y = d / (d + 1) over the singletons 1 and 0, so d = y / (1 - y)."""
    engine = FuzzyEngine(Semantics(and_=and_, or_=or_))
    for name in ("a", "b", "c"):
        engine.define_variable(name, 0, 1, "up := (0, 0) (1, 1)")
    engine.define_variable("y", 0, 1, "one := 1; zero := 0")
    engine.defrule("both: if a is up and b is up then y is one", "and")
    engine.defrule("ref: if c is up then y is zero", "and")
    engine.defrule("either: if a is up or b is up then y is one", "or")
    engine.defrule("ref: if c is up then y is zero", "or")
    engine.set("c", 1.0)
    return engine


@pytest.mark.parametrize(("and_", "or_"), PAIRS)
@settings(max_examples=60, deadline=None)
@given(a=DEGREE, b=DEGREE)
def test_each_connective_is_its_formula_on_every_path(and_, or_, a, b) -> None:
    engine = _engine(and_, or_)
    engine.set("a", a)
    engine.set("b", b)
    for ruleset, op, label in (("and", and_, "both"), ("or", or_, "either")):
        want = FORMULA[op](a, b)
        assert engine.explain(ruleset)[label] == pytest.approx(want, abs=1e-12)
        engine.fire(ruleset)
        y = engine.get("y")
        assert y / (1.0 - y) == pytest.approx(want, abs=1e-9)
        batch = engine.batch(ruleset, {"a": np.array([a, b]), "b": np.array([b, a])})["y"]
        for got, w in zip(batch, (want, FORMULA[op](b, a)), strict=True):
            assert got / (1.0 - got) == pytest.approx(w, abs=1e-9)


@pytest.mark.parametrize(("and_", "or_"), PAIRS)
def test_an_and_line_sets_its_dual_or_as_jfuzzylogic_does_and_reads_back(and_, or_) -> None:
    text = (
        "FUNCTION_BLOCK t\nVAR_INPUT a : REAL; b : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        "FUZZIFY a\n TERM up := (0, 0) (1, 1);\nEND_FUZZIFY\nFUZZIFY b\n TERM up := (0, 0) (1, 1);\n"
        "END_FUZZIFY\nDEFUZZIFY y\n TERM hi := TRIAN 0 1 1;\n RANGE := (0 .. 1);\nEND_DEFUZZIFY\n"
        f"RULEBLOCK r\n AND : {and_.lower()};\n RULE 1 : IF a IS up AND b IS up OR a IS up THEN y IS hi;\n"
        "END_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
    )
    engine = read_fcl(text)["t"]
    sem = engine.semantics_of("r")
    assert (sem.and_, sem.or_) == (and_, AND_OPS[and_]) == (and_, or_)
    again = read_fcl(write_fcl(engine))["t"]
    assert again.semantics_of("r") == sem
    engine.set("a", 0.6)
    engine.set("b", 0.7)
    want = FORMULA[or_](FORMULA[and_](0.6, 0.7), 0.6)  # left to right, equal precedence
    assert engine.explain("r")["1"] == pytest.approx(want, abs=1e-12)
