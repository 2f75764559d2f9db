"""Building a fuzzy rule base costs in proportion to its rules and terms (issue 14, item 8): an
output's plan (its cut into linear intervals and its defuzzifier) is built once per variable and
semantics, not once per rule, and cutting an output visits each term's own intervals only. Speed
is shown by benchmarks/bench_fuzzy_build.py; here the plans are counted and the cut is held to its
definition."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import acordcs.engines.fuzzy.fuzzy_engine as fuzzy_engine
from acordcs.engines.fuzzy import FuzzyEngine
from acordcs.engines.fuzzy.defuzz import OutputShape
from acordcs.engines.fuzzy.fcl import read_fcl
from acordcs.engines.fuzzy.membership import make_membership

TERMS = 250


def _terms(prefix: str) -> str:
    return "; ".join(f"{prefix}{k} := trian {k} {k + 0.5} {k + 1}" for k in range(TERMS))


@pytest.fixture
def plans_built(monkeypatch) -> list[str]:
    built: list[str] = []
    real = fuzzy_engine.output_plan

    def counting(ruleset, var, sem):
        built.append(var.name)
        return real(ruleset, var, sem)

    monkeypatch.setattr(fuzzy_engine, "output_plan", counting)
    return built


def test_a_thousand_rules_build_the_output_plan_once(plans_built: list[str]) -> None:
    engine = FuzzyEngine()
    engine.define_variable("x", 0, TERMS, _terms("i"))
    engine.define_variable("y", 0, TERMS, _terms("o"))
    for n in range(1000):
        engine.defrule(f"if x is i{n % TERMS} then y is o{n % TERMS}", "s")
    engine.set("x", 3.2)
    engine.fire("s")
    engine.defrule("extra: if x is i1 then y is o1", "s")
    engine.fire("s")  # recompiled: the plan is reused
    assert plans_built == ["y"]
    assert engine.get("y") == pytest.approx(3.5)


def test_a_redeclared_output_gets_a_new_plan(plans_built: list[str]) -> None:
    engine = FuzzyEngine()
    engine.define_variable("x", 0, 10, "lo := trian 0 0 10")
    engine.define_variable("y", 0, 10, "lo := trian 0 0 10; hi := trian 0 10 10")
    engine.defrule("if x is lo then y is hi", "s")
    engine.define_variable("y", 0, 10, "lo := trian 0 0 10; hi := trian 5 10 10")
    engine.set("x", 0)
    engine.fire("s")
    assert plans_built == ["y", "y"]
    assert engine.get("y") == pytest.approx(25 / 3)  # the centroid of the new hi


def test_an_fcl_file_of_250_one_rule_terms_builds_one_plan(plans_built: list[str]) -> None:
    terms = "\n".join(f"TERM o{k} := ({k}, 0) ({k + 0.5}, 1) ({k + 1}, 0);" for k in range(TERMS))
    rules = "\n".join(f"RULE {k + 1} : IF x IS i{k} THEN y IS o{k};" for k in range(TERMS))
    text = (
        "FUNCTION_BLOCK b\nVAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        f"FUZZIFY x\n{terms.replace(' o', ' i')}\nEND_FUZZIFY\n"
        f"DEFUZZIFY y\n{terms}\nMETHOD : COG;\nEND_DEFUZZIFY\n"
        f"RULEBLOCK r\n{rules}\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
    )
    engine = read_fcl(text)["b"]
    engine.set("x", 7.5)
    engine.fire("r")
    assert plans_built == ["y"]
    assert engine.get("y") == pytest.approx(7.5)


def _brute_force_cut(lo: float, hi: float, terms) -> list:
    """The definition: every term's line on every interval between consecutive breakpoints."""
    cuts = sorted({lo, hi} | {x for t in terms for x in t.xs if lo < x < hi})
    out = []
    for x0, x1 in itertools.pairwise(cuts):
        lines = []
        for k, t in enumerate(terms):
            v0, v1 = t.limits(x0)[1], t.limits(x1)[0]
            if v0 or v1:
                lines.append((k, v0, v1))
        out.append((x0, x1, tuple(lines)))
    return out


_x = st.sampled_from([-5.0, 0.0, 2.5, 5.0, 7.5, 10.0, 15.0])
_y = st.sampled_from([0.0, 0.25, 1.0])


@st.composite
def _term(draw):
    kind = draw(st.sampled_from(["trian", "trape", "points"]))
    if kind == "points":
        xs = sorted(set(draw(st.lists(_x, min_size=2, max_size=4))))
        if len(xs) < 2:
            xs = [xs[0], xs[0] + 1.0]
        params = [v for x in xs for v in (x, draw(_y))]
    else:
        params = sorted(draw(st.lists(_x, min_size=3 if kind == "trian" else 4, max_size=4)))
        params = params[: 3 if kind == "trian" else 4]
        if params[0] == params[-1]:
            params[-1] += 1.0
    return make_membership(kind, params)


@settings(max_examples=200, deadline=None)
@given(terms=st.lists(_term(), min_size=1, max_size=6))
def test_the_cut_of_an_output_is_its_definition(terms) -> None:
    assert OutputShape(0.0, 10.0, terms).intervals == _brute_force_cut(0.0, 10.0, terms)
