"""The batch call gives what set/fire/get give row by row, for every semantics."""

from __future__ import annotations

import logging

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from acordcs.engines.fuzzy import FuzzyEngine
from acordcs.engines.rule_engine import RuleError
from tests.support.fuzzy_bases import bandwidth_engine, speed_engine
from tests.support.fuzzy_oracle import OPERATORS, rule_base


def _row_by_row(engine: FuzzyEngine, ruleset: str, cols: dict, out: str) -> np.ndarray:
    n = len(next(iter(cols.values())))
    got = []
    for i in range(n):
        for k, v in cols.items():
            engine.set(k, float(v[i]))
        engine.fire(ruleset)
        got.append(engine.get(out))
    return np.array(got)


@pytest.mark.parametrize("semantics", ["mamdani", "sazonov", "fcl"])
@pytest.mark.parametrize("base", ["speed", "bandwidth"])
def test_batch_equals_single_calls_on_the_paper_bases(base, semantics):
    rng = np.random.default_rng(5)
    if base == "speed":
        engine, rs, out = speed_engine(semantics), "speed", "speed"
        cols = {"cycleRate": rng.uniform(0, 3, 500), "angle": rng.uniform(0, 90, 500)}
    else:
        engine, rs, out = bandwidth_engine(semantics), "bandwidth", "fps"
        cols = {"cycleRate": rng.uniform(0, 3, 500), "numUsers": rng.uniform(0, 10, 500)}
    cols = {
        k: np.concatenate([v, [0.0, 3.0 if k == "cycleRate" else v.max()]]) for k, v in cols.items()
    }
    batch = engine.batch(rs, cols)[out]
    np.testing.assert_allclose(batch, _row_by_row(engine, rs, cols, out), rtol=0, atol=1e-9)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rule_base(), OPERATORS)
def test_batch_equals_single_calls_on_random_bases(base, sem):
    variables, rules, _ = base
    e = FuzzyEngine(sem)
    for name, (lo, hi, terms) in variables.items():
        e.define_variable(name, lo, hi, terms, default=lo)
    for r in rules:
        e.defrule(r, "rs")
    rng = np.random.default_rng(1)
    inputs = {v for r in e.rules("rs") for v in r.inputs()}
    cols = {v: rng.uniform(e.variables[v].lo, e.variables[v].hi, 30) for v in sorted(inputs)}
    if not cols:
        return
    lo, hi = e.variables["out"].lo, e.variables["out"].hi
    np.testing.assert_allclose(
        e.batch("rs", cols)["out"], _row_by_row(e, "rs", cols, "out"), atol=1e-9 * (hi - lo)
    )


def test_batch_leaves_the_engine_alone_and_broadcasts():
    e = speed_engine()
    e.set("cycleRate", 1.0)
    e.set("angle", 45.0)
    e.fire("speed")
    before = e.get("speed")
    angles = np.linspace(0, 90, 7)
    from_current = e.batch("speed", {"angle": angles})["speed"]  # cycleRate: its current value
    scalar = e.batch("speed", {"cycleRate": 1.0, "angle": angles})["speed"]
    np.testing.assert_array_equal(from_current, scalar)
    assert e.get("speed") == before and e.get("angle") == 45.0


def test_batch_bad_rows_and_clamping(caplog):
    e = speed_engine()
    with pytest.raises(RuleError, match=r"input 'angle' row 2 is nan"):
        e.batch("speed", {"cycleRate": [1, 1, 1], "angle": [1, 2, np.nan]})
    with pytest.raises(RuleError, match="unknown variable 'sped'"):
        e.batch("speed", {"sped": [1.0]})
    with pytest.raises(RuleError, match="differ in length"):
        e.batch("speed", {"cycleRate": [1, 1, 1], "angle": [1, 2]})
    with caplog.at_level(logging.WARNING, logger="acordcs.engines.fuzzy"):
        got = e.batch("speed", {"cycleRate": [5.0, 3.0, -1.0], "angle": [10, 10, 10]})["speed"]
        e.batch("speed", {"cycleRate": [7.0], "angle": [10]})
    assert got[0] == got[1]
    assert sum("outside its range" in r.getMessage() for r in caplog.records) == 1


def test_batch_rows_where_nothing_fires_take_the_default():
    e = FuzzyEngine()
    e.define_variable("x", 0, 10, "high := trian 5 10 10")
    e.define_variable("y", 0, 100, "big := trian 50 100 100", default=3)
    e.defrule("if x is high then y is big", "r")
    got = e.batch("r", {"x": [0, 10]})["y"]
    assert got[0] == 3 and got[1] == pytest.approx(250 / 3)


def test_non_linear_outputs_are_sampled_the_same_way_in_batch():
    e = FuzzyEngine()
    e.define_variable("x", 0, 10, "low := gauss 0 3; high := sigm 1.5 6")
    e.define_variable("y", 0, 100, "small := gauss 20 10; large := gbell 20 3 80")
    e.defrule("if x is low then y is small", "g")
    e.defrule("if x is high then y is large", "g")
    xs = np.linspace(0, 10, 41)
    np.testing.assert_allclose(
        e.batch("g", {"x": xs})["y"], _row_by_row(e, "g", {"x": xs}, "y"), atol=1e-9
    )


@pytest.mark.parametrize(
    "column",
    ["5", ["5", 3], [1, "a"], np.array(["1", "2"]), [10**400]],
    ids=["text", "text in a list", "mixed", "numpy text", "beyond a float"],
)
def test_text_and_huge_numbers_are_a_rule_error_as_in_set(column) -> None:
    engine = speed_engine()
    with pytest.raises(RuleError, match="must be numbers: text"):
        engine.batch("speed", {"cycleRate": column, "angle": 5.0})
