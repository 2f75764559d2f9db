"""Membership functions: values, defined edge behaviour, bad parameters."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.engines.fuzzy import make_membership
from acordcs.engines.fuzzy.membership import Membership, function_membership
from acordcs.engines.rule_engine import RuleError


def _generated(mf: Membership):
    """The membership as the rule set's generated code computes it."""
    ns = {"_exp": math.exp}
    exec(
        "def f(x):\n"
        + "\n".join("    " + line for line in mf.code("x", "out"))
        + "\n    return out",
        ns,
    )
    return ns["f"]


SHAPES = [
    ("triangle", (0, 5, 10)),
    ("trapezoid", (0, 0, 20, 50)),
    ("trapezoid", (130, 170, 200, 200)),
    ("points", (0, 1, 4, 0)),
    ("points", (1, 0, 4, 1, 6, 1, 9, 0)),
    ("points", (0, 0, 2, 0, 2, 1, 5, 1, 5, 0.5)),
    ("points", (0, 0, 1, 1, 3, 1)),  # a slope of exactly 1
    ("points", (2, 0, 2, 1, 5, 1)),  # a vertical edge first
    ("gaussian", (5, 2)),
    ("bell", (2, 3, 5)),
    ("sigmoid", (2, 5)),
    ("sigmoid", (-400, 5)),
    ("singleton", (3,)),
]


@pytest.mark.parametrize(("shape", "params"), SHAPES)
def test_scalar_vector_and_generated_code_agree(shape, params):
    mf = make_membership(shape, params)
    xs = np.concatenate([np.linspace(-20, 220, 2401), np.array(params, dtype=float)])
    gen = _generated(mf)
    vec = mf.evaluate(xs)
    for x, v in zip(xs, vec, strict=False):
        assert mf(float(x)) == pytest.approx(v, abs=1e-12)
        assert gen(float(x)) == pytest.approx(v, abs=1e-12)
        assert 0.0 <= v <= 1.0


def test_known_values():
    tri = make_membership("triangle", (0, 5, 10))
    assert (tri(0), tri(2.5), tri(5), tri(7.5), tri(10), tri(11)) == (0, 0.5, 1, 0.5, 0, 0)
    assert make_membership("gaussian", (5, 2))(7) == pytest.approx(math.exp(-0.5))
    assert make_membership("bell", (2, 3, 5))(7) == pytest.approx(0.5)
    assert make_membership("sigmoid", (2, 5))(5) == pytest.approx(0.5)
    assert make_membership("sigmoid", (-400, 5))(100) == 0.0  # no overflow far out
    single = make_membership("singleton", (3,))
    assert (single(3), single(3.0001)) == (1.0, 0.0)


def test_vertical_edges_take_the_upper_value():
    shoulder = make_membership("trapezoid", (0, 0, 20, 50))
    assert shoulder(0) == 1.0 and shoulder(-1) == 0.0
    right = make_membership("trapezoid", (130, 170, 200, 200))
    assert right(200) == 1.0 and right(200.1) == 0.0
    step = make_membership("points", (0, 0, 2, 0, 2, 1, 5, 1))
    assert (step(1.9), step(2), step(2.1)) == (0.0, 1.0, 1.0)
    assert float(step.evaluate(np.array([2.0]))[0]) == 1.0


def test_point_lists_extend_their_end_values():
    poor = make_membership("points", (0, 1, 4, 0))
    assert poor(-3) == 1.0 and poor(10) == 0.0
    excellent = make_membership("points", (6, 0, 9, 1))
    assert excellent(12) == 1.0


@pytest.mark.parametrize(
    ("shape", "params", "words"),
    [
        ("triangle", (50, 20, 80), "inverted"),
        ("triangle", (0, 10, 5), "inverted"),
        ("trapezoid", (0, 30, 20, 50), "inverted"),
        ("triangle", (5, 5, 5), "zero width"),
        ("trapezoid", (7, 7, 7, 7), "zero width"),
        ("points", (4, 0, 1, 1), "must not decrease"),
        ("points", (2, 0, 2, 1, 2, 0.5, 3, 0), "three points"),
        ("points", (2, 1, 2, 0), "zero width"),
        ("points", (0, 0, 1, 1.5), "within 0..1"),
        ("points", (0, 1), "at least two"),
        ("gaussian", (5, 0), "sigma must be > 0"),
        ("bell", (0, 2, 5), "must be > 0"),
        ("bell", (2, 0, 5), "must be > 0"),
        ("sigmoid", (0, 5), "gain must not be 0"),
        ("triangle", (0, 5), "takes 3 parameters"),
        ("triangle", (0, float("nan"), 5), "finite"),
        ("cosine", (1, 2), "unknown membership shape"),
    ],
)
def test_bad_parameters_are_clear_errors(shape, params, words):
    with pytest.raises(RuleError, match=words) as info:
        make_membership(shape, params, where="term 'x' of variable 'v'")
    assert "term 'x' of variable 'v'" in str(info.value)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.integers(0, 20), min_size=3, max_size=3), st.floats(-5, 25))
def test_sorted_triangles_are_accepted_and_bounded(points, x):
    a, b, c = sorted(points)
    if a == c:
        with pytest.raises(RuleError):
            make_membership("triangle", (a, b, c))
        return
    mf = make_membership("triangle", (a, b, c))
    assert 0.0 <= mf(x) <= 1.0
    assert mf(b) == 1.0


@pytest.mark.parametrize(("shape", "params"), SHAPES)
def test_fcl_text_reads_back_as_the_same_function(shape, params):
    from acordcs.rules import parse_terms

    mf = make_membership(shape, params)
    (term,) = parse_terms(f"t := {mf.fcl()}")
    assert make_membership(term.shape, term.parameters) == mf


def test_trapezoid_edges_rise_and_fall_linearly():
    trap = make_membership("trapezoid", (0, 10, 20, 30))
    assert [trap(x) for x in (-1, 0, 5, 10, 15, 20, 25, 30, 31)] == [0, 0, 0.5, 1, 1, 1, 0.5, 0, 0]


def test_an_inverted_shape_is_described_by_its_own_points():
    with pytest.raises(RuleError, match=r"\(left foot, peak, right foot\)"):
        make_membership("triangle", (0, 10, 5))
    with pytest.raises(RuleError, match=r"\(left foot, shoulders, right foot\)"):
        make_membership("trapezoid", (0, 10, 5, 20))


def test_narrow_but_positive_widths_and_a_leading_vertical_edge_are_accepted():
    assert make_membership("gaussian", (5, 0.5))(5.5) == pytest.approx(math.exp(-0.5))
    assert make_membership("bell", (0.5, 0.5, 5))(5.5) == pytest.approx(0.5)
    step = make_membership("points", (2, 0, 2, 1, 5, 1))
    assert (step(1), step(2), step(3), step(6)) == (0.0, 1.0, 1.0, 1.0)


def test_singletons_and_function_terms_are_single_points_and_write_their_fcl():
    function = function_membership(SimpleNamespace(text="2 * x + 1"))
    assert function.singleton and make_membership("singleton", (3,)).singleton
    assert not make_membership("triangle", (0, 5, 10)).singleton
    assert function.fcl() == "FUNCTION 2 * x + 1"
    assert not function.linear and make_membership("points", (0, 1, 4, 0)).linear


def test_a_sigmoid_at_its_overflow_cutoff_is_the_same_number_scalar_and_vectorised():
    mf = make_membership("sigmoid", (1, 0))  # exp's argument is exactly the cutoff, 700, at -700
    assert mf(-700.0) == float(mf.evaluate(np.array([-700.0]))[0]) == 1.0 / (1.0 + math.exp(700.0))
    assert mf(-700.0) > 0.0 and mf(-701.0) == float(mf.evaluate(np.array([-701.0]))[0]) == 0.0
