"""The fuzzy engine against independent oracles (property-based, bounded example counts).

- a dense oracle (``tests/support/fuzzy_oracle.py``): memberships from the shape parameters, rule
  degrees by a plain recursive evaluator, the aggregated set on 200,001 points, trapezoid-rule
  integrals;
- scikit-fuzzy's ControlSystemSimulation(cache=False) on the paper's two policies;
- the paper's engine (sazonov): product activation, sum accumulation, 100 samples, written here.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.engines.fuzzy import FuzzyEngine, Semantics
from acordcs.engines.fuzzy.sampled import FALLBACK_SAMPLES
from acordcs.rules import parse_terms
from tests.support.fuzzy_bases import (
    ANGLES,
    BANDWIDTH_RULES,
    BANDWIDTH_TABLE,
    BANDWIDTH_VARIABLES,
    SPEED_RULES,
    SPEED_TABLE,
    SPEED_VARIABLES,
    USERS,
    bandwidth_engine,
    speed_engine,
)
from tests.support.fuzzy_oracle import DENSE, GRID, OPERATORS, oracle, ours, rule_base

SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# ---------------------------------------------------------------------------------- the paper's bases
rates = st.floats(0, 3, allow_nan=False)
angles = st.floats(0, 90, allow_nan=False)
users = st.floats(0, 10, allow_nan=False)
MAMDANI = Semantics()


@SETTINGS
@given(rates, angles)
def test_speed_base_equals_dense_oracle(rate, angle):
    inputs = {"cycleRate": rate, "angle": angle}
    want = oracle(SPEED_VARIABLES, SPEED_RULES, inputs, "speed", MAMDANI)
    assert ours(speed_engine(), "speed", inputs, "speed") == pytest.approx(want, abs=1e-6)


@SETTINGS
@given(rates, users)
def test_bandwidth_base_equals_dense_oracle(rate, n):
    inputs = {"cycleRate": rate, "numUsers": n}
    want = oracle(BANDWIDTH_VARIABLES, BANDWIDTH_RULES, inputs, "fps", MAMDANI)
    assert ours(bandwidth_engine(), "bandwidth", inputs, "fps") == pytest.approx(want, abs=1e-7)


@settings(max_examples=25, deadline=None)
@given(rates, angles)
def test_sazonov_equals_its_oracle(rate, angle):
    sem = Semantics(act="PROD", accu="SUM", samples=100)
    inputs = {"cycleRate": rate, "angle": angle}
    want = oracle(SPEED_VARIABLES, SPEED_RULES, inputs, "speed", sem, n=100)
    assert ours(speed_engine("sazonov"), "speed", inputs, "speed") == pytest.approx(want, abs=1e-9)


def test_sazonov_and_mamdani_really_differ_on_the_speed_base():
    rng = np.random.default_rng(3)
    a, b = rng.uniform(0, 3, 2000), rng.uniform(0, 90, 2000)
    diff = (
        speed_engine("sazonov").batch("speed", {"cycleRate": a, "angle": b})["speed"]
        - speed_engine().batch("speed", {"cycleRate": a, "angle": b})["speed"]
    )
    assert 5.0 < np.abs(diff).max() < 40.0  # the reference measured up to 17 mm/s on its own base


# ---------------------------------------------------------------------------------- scikit-fuzzy
def _skfuzzy(variables: dict, table: dict, inputs: tuple, out: str):
    skfuzzy = pytest.importorskip("skfuzzy")
    from skfuzzy import control as ctrl

    def universe(name, n):
        lo, hi, _ = variables[name]
        return np.linspace(lo, hi, n)

    def add_terms(var, name):
        for t in parse_terms(variables[name][2]):
            p = list(t.parameters)
            var[t.name.text] = (skfuzzy.trimf if t.shape == "triangle" else skfuzzy.trapmf)(
                var.universe, p
            )

    a = ctrl.Antecedent(universe(inputs[0], 3001), inputs[0])
    b = ctrl.Antecedent(universe(inputs[1], 3001), inputs[1])
    c = ctrl.Consequent(universe(out, 4001), out)
    for var, name in ((a, inputs[0]), (b, inputs[1]), (c, out)):
        add_terms(var, name)
    rules = [ctrl.Rule(a[ta] & b[tb], c[tc]) for ta, row in table.items() for tb, tc in row.items()]
    return ctrl.ControlSystemSimulation(ctrl.ControlSystem(rules), cache=False)


@pytest.mark.parametrize("base", ["speed", "bandwidth"])
@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # inside scikit-fuzzy 0.5 with numpy 2
def test_agrees_with_scikit_fuzzy(base):
    if base == "speed":
        variables, second, cols, table, out = SPEED_VARIABLES, "angle", ANGLES, SPEED_TABLE, "speed"
        engine, ruleset, tol = speed_engine(), "speed", 0.01  # on 0..200
    else:
        variables, second, cols, table, out = (
            BANDWIDTH_VARIABLES,
            "numUsers",
            USERS,
            BANDWIDTH_TABLE,
            "fps",
        )
        engine, ruleset, tol = bandwidth_engine(), "bandwidth", 0.001  # on 0..15
    sim = _skfuzzy(
        variables,
        {r: dict(zip(cols, row, strict=False)) for r, row in table.items()},
        ("cycleRate", second),
        out,
    )
    rng = np.random.default_rng(11)
    lo, hi, _ = variables[second]
    worst = 0.0
    for rate, x in zip(rng.uniform(0, 3, 40), rng.uniform(lo, hi, 40), strict=False):
        sim.input["cycleRate"], sim.input[second] = rate, x
        sim.compute()
        worst = max(
            worst, abs(sim.output[out] - ours(engine, ruleset, {"cycleRate": rate, second: x}, out))
        )
    assert worst < tol


def _engine(variables, rules, sem) -> FuzzyEngine:
    e = FuzzyEngine(sem)
    for name, (lo, hi, terms) in variables.items():
        e.define_variable(name, lo, hi, terms, default=lo)
    for r in rules:
        e.defrule(r, "rs")
    return e


def assert_matches_oracle(variables, rules, values, sem, tol):
    e = _engine(variables, rules, sem)
    want = oracle(variables, rules, values, "out", sem, n=sem.samples or DENSE)
    got = ours(e, "rs", values, "out")
    lo, hi, _ = variables["out"]
    if want is None:
        assert got == lo and e.defaulted("rs") == ("out",)
    elif sem.method == "COA" and not sem.samples:
        # A bisector is ill-conditioned where the set is (near) zero: a tiny integration error moves
        # the oracle's x far (a zero between two equal halves). Check COA by its definition: the
        # engine's x halves the oracle's area.
        share, per_step = oracle(variables, rules, values, "out", sem, split_at=got)
        steps = 10 * (hi - lo) / (DENSE - 1)  # the oracle's grid, a few edges
        if sem.accu == "PROBOR":
            steps += (hi - lo) * SAMPLED_STEP  # the engine's own grid for non-linear sets
        assert share == pytest.approx(0.5, abs=tol + steps * per_step)
        batch = e.batch("rs", {k: [v] for k, v in values.items()})["out"][0]
        assert batch == pytest.approx(got, abs=1e-9 * (hi - lo))
    else:
        assert got == pytest.approx(want, abs=tol * (hi - lo))
        batch = e.batch("rs", {k: [v] for k, v in values.items()})["out"][0]
        assert batch == pytest.approx(got, abs=1e-9 * (hi - lo))


@SETTINGS
@given(rule_base())
def test_random_rule_bases_mamdani(base):
    assert_matches_oracle(
        *base, Semantics(), 2e-5
    )  # vertical edges cost the 200,001-point oracle O(h)


@SETTINGS
@given(rule_base())
def test_random_rule_bases_sazonov(base):
    assert_matches_oracle(*base, Semantics(act="PROD", accu="SUM", samples=100), 1e-9)


# PROBOR is not piecewise linear: the engine integrates it on 2,001 points, which at a vertical
# edge is exact to about one step of that grid (documented in docs/fuzzy-engine.md).
SAMPLED_STEP = 1 / (FALLBACK_SAMPLES - 1)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rule_base(), OPERATORS)
def test_random_rule_bases_every_fcl_operator(base, sem):
    assert_matches_oracle(*base, sem, SAMPLED_STEP if sem.accu == "PROBOR" else 2e-5)


@st.composite
def skfuzzy_base(draw):
    """Two inputs, AND/OR/NOT conditions (what scikit-fuzzy's rules express); breakpoints on a 1/8
    grid of each range, so scikit-fuzzy's sampled universes hold every breakpoint exactly."""
    variables = {}
    for name, lo, hi in (("a", 0.0, 8.0), ("b", -40.0, 40.0), ("out", 0.0, 200.0)):
        count = draw(st.integers(2, 4))
        terms = []
        for k in range(count):
            # no vertical edge inside the range: scikit-fuzzy's sampled terms would smear it over a
            # grid step and be off by more than 0.01; a shoulder at an end of the range is fine
            steps = sorted(
                draw(st.lists(st.sampled_from(GRID), min_size=4, max_size=4, unique=True))
            )
            pts = [lo + (hi - lo) * u for u in steps]
            if pts[0] == lo and draw(st.booleans()):
                pts[1] = lo
            if pts[3] == hi and draw(st.booleans()):
                pts[2] = hi
            terms.append(f"t{k} := trape {pts[0]!r} {pts[1]!r} {pts[2]!r} {pts[3]!r}")
        variables[name] = (lo, hi, "; ".join(terms))
    names = {v: [t.name.text for t in parse_terms(variables[v][2])] for v in ("a", "b")}
    rules = []
    for _ in range(draw(st.integers(1, 6))):
        ta, tb = draw(st.sampled_from(names["a"])), draw(st.sampled_from(names["b"]))
        op = draw(st.sampled_from(["and", "or"]))
        neg = draw(st.booleans())
        cond = f"a is {ta} {op} {'not (b is ' + tb + ')' if neg else 'b is ' + tb}"
        out = draw(st.sampled_from([t.name.text for t in parse_terms(variables["out"][2])]))
        rules.append((cond, out, ta, tb, op, neg))
    # inputs on a 1e-3 grid: a degree like 1e-180 underflows inside scikit-fuzzy (it answers 0)
    values = {"a": draw(st.integers(0, 8000)) / 1000, "b": draw(st.integers(-40000, 40000)) / 1000}
    return variables, rules, values


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(skfuzzy_base())
def test_random_rule_bases_agree_with_scikit_fuzzy(base):
    skfuzzy = pytest.importorskip("skfuzzy")
    from skfuzzy import control as ctrl

    variables, rules, values = base
    e = FuzzyEngine()
    for name, (lo, hi, terms) in variables.items():
        e.define_variable(name, lo, hi, terms)
    for cond, out, *_ in rules:
        e.defrule(f"if {cond} then out is {out}", "rs")
    got = ours(e, "rs", values, "out")
    if e.defaulted("rs"):
        return  # scikit-fuzzy has no answer when nothing fires
    sk = {}
    for name, kind, n in (
        ("a", ctrl.Antecedent, 801),
        ("b", ctrl.Antecedent, 801),
        ("out", ctrl.Consequent, 1601),
    ):
        lo, hi, terms = variables[name]
        sk[name] = kind(np.linspace(lo, hi, n), name)
        for t in parse_terms(terms):
            sk[name][t.name.text] = skfuzzy.trapmf(sk[name].universe, list(t.parameters))
    sk_rules = []
    for _, out, ta, tb, op, neg in rules:
        right = ~sk["b"][tb] if neg else sk["b"][tb]
        sk_rules.append(
            ctrl.Rule(sk["a"][ta] & right if op == "and" else sk["a"][ta] | right, sk["out"][out])
        )
    sim = ctrl.ControlSystemSimulation(ctrl.ControlSystem(sk_rules), cache=False)
    sim.input["a"], sim.input["b"] = values["a"], values["b"]
    sim.compute()
    assert got == pytest.approx(sim.output["out"], abs=0.01)  # on 0..200, as the reference found
