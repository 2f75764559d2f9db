"""A membership's one-sided limits (``limits``: what defuzzification integrates from at a
breakpoint) and its extent (where an FCL variable without RANGE gets its universe), to the exact
value: each against a hand-worked table, and the limits against the function itself."""

from __future__ import annotations

import math

import pytest

from acordcs.engines.fuzzy import make_membership, read_fcl
from acordcs.engines.fuzzy.membership import function_membership

LEFT_SHOULDER = make_membership("trapezoid", (0, 0, 20, 50))
RIGHT_SHOULDER = make_membership("trapezoid", (130, 170, 200, 200))
STEP = make_membership("points", (0, 0.25, 2, 0.25, 2, 1, 5, 1, 8, 0.5))  # keeps 0.25, 0.5 beyond


@pytest.mark.parametrize(
    ("mf", "u", "expected"),
    [
        (LEFT_SHOULDER, -1, (0.0, 0.0)),
        (LEFT_SHOULDER, 0, (0.0, 1.0)),  # the vertical edge: 0 from the left, 1 from the right
        (LEFT_SHOULDER, 10, (1.0, 1.0)),
        (LEFT_SHOULDER, 20, (1.0, 1.0)),
        (LEFT_SHOULDER, 35, (0.5, 0.5)),
        (LEFT_SHOULDER, 50, (0.0, 0.0)),
        (LEFT_SHOULDER, 60, (0.0, 0.0)),
        (RIGHT_SHOULDER, 129, (0.0, 0.0)),
        (RIGHT_SHOULDER, 130, (0.0, 0.0)),
        (RIGHT_SHOULDER, 150, (0.5, 0.5)),
        (RIGHT_SHOULDER, 170, (1.0, 1.0)),
        (RIGHT_SHOULDER, 200, (1.0, 0.0)),  # the vertical edge at the right end
        (RIGHT_SHOULDER, 201, (0.0, 0.0)),
        (STEP, -3, (0.25, 0.25)),
        (STEP, 0, (0.25, 0.25)),
        (STEP, 1, (0.25, 0.25)),
        (STEP, 2, (0.25, 1.0)),
        (STEP, 3.5, (1.0, 1.0)),
        (STEP, 6.5, (0.75, 0.75)),
        (STEP, 8, (0.5, 0.5)),
        (STEP, 9, (0.5, 0.5)),
    ],
)
def test_limits_are_the_hand_worked_one_sided_values(mf, u, expected):
    assert mf.limits(u) == expected


@pytest.mark.parametrize("mf", [LEFT_SHOULDER, RIGHT_SHOULDER, STEP])
def test_limits_are_the_functions_values_just_left_and_right(mf):
    for u in sorted({*mf.xs, *(x + 0.37 for x in mf.xs), mf.xs[0] - 1, mf.xs[-1] + 1}):
        left, right = mf.limits(u)
        assert left == pytest.approx(mf(u - 1e-9), abs=1e-6), u
        assert right == pytest.approx(mf(u + 1e-9), abs=1e-6), u
        assert mf(u) == max(left, right), u  # a vertical edge belongs to the set


@pytest.mark.parametrize(
    ("shape", "params", "extent"),
    [
        ("triangle", (1, 5, 12), (1.0, 12.0)),
        ("trapezoid", (-4, 0, 2, 3), (-4.0, 3.0)),
        ("points", (2, 0, 3, 1, 7, 0.5), (2.0, 7.0)),
        ("gaussian", (5, 2), (-3.0, 13.0)),  # mean -+ 4 sigma
        ("bell", (2, 3, 5), (-3.0, 13.0)),  # mean -+ 4 a
        ("sigmoid", (2, 5), (1.0, 9.0)),  # center -+ 8 / |gain|
        ("sigmoid", (-4, 5), (3.0, 7.0)),
        ("singleton", (3,), (3.0, 3.0)),
    ],
)
def test_extent_of_each_shape(shape, params, extent):
    assert make_membership(shape, params).extent() == extent


def test_a_function_terms_extent_is_unknown_until_it_fires():
    assert all(math.isnan(v) for v in function_membership(object()).extent())


def _universe(fuzzify: str, defuzzify: str = "TERM s := 3; TERM t := 3;") -> dict:
    text = (
        "FUNCTION_BLOCK u\nVAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        f"FUZZIFY x {fuzzify} END_FUZZIFY\nDEFUZZIFY y {defuzzify} END_DEFUZZIFY\n"
        "RULEBLOCK r\n RULE 1 : IF x IS a THEN y IS s;\nEND_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
    )
    return {n: (v.lo, v.hi) for n, v in read_fcl(text)["u"].variables.items()}


@pytest.mark.parametrize(
    ("terms", "universe"),
    [
        ("TERM a := trian 1 5 12; TERM b := trape 4 6 8 20;", (1.0, 20.0)),
        ("TERM a := gauss 5 2; TERM b := sigm 2 20;", (-3.0, 24.0)),  # 5 - 4*2, 20 + 8/2
        ("TERM a := gbell 2 3 5; TERM b := (6, 0) (7, 1);", (-3.0, 13.0)),
        ("TERM a := sigm -4 5;", (3.0, 7.0)),
    ],
)
def test_a_universe_without_range_spans_every_terms_extent(terms, universe):
    assert _universe(terms)["x"] == universe


def test_an_output_of_singletons_at_one_x_gets_a_universe_around_it():
    found = _universe("TERM a := trian 0 5 10;", "TERM s := 3; TERM t := 3;")
    assert found == {"x": (0.0, 10.0), "y": (2.0, 4.0)}
    spread = _universe("TERM a := trian 0 5 10;", "TERM s := 3; TERM t := 9;")
    assert spread["y"] == (3.0, 9.0)
