"""Outputs whose terms overlap deeply are defuzzified by merging whole polylines (issue 22, item 4):
the same numbers as the former exact defuzzifiers (a pinned copy, ``tests/support/defuzz_before.py``)
to 1e-9 of the range for every exact combination and method, and as scikit-fuzzy's exact
piecewise-linear centroid and bisector fed with every kink of the aggregated set, found here by
brute force. Speed is shown by ``benchmarks/bench_fuzzy_deep.py``.

Tolerance 1e-9 of the range: both sides are exact in closed form; what differs is the order of
floating-point operations over up to a few hundred pieces (observed differences are ~1e-13).
LM/RM/MM are compared with the pinned copy only: scikit-fuzzy's som/lom/mom take the samples equal
to the maximum, a test of float equality on values this oracle interpolates.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import skfuzzy
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import tests.support.defuzz_before as before
from acordcs.engines.fuzzy import FuzzyEngine, Semantics, make_membership
from acordcs.engines.fuzzy.defuzz import DEEP, Envelope, OutputShape, make_defuzzifier
from tests.support.fuzzy_oracle import oracle, oracle_mu

LO, HI = 0.0, 10.0
SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
_x = st.sampled_from([0.0, 0.5, 1.0, 2.5, 3.0, 4.25, 5.0, 6.0, 7.5, 9.0, 10.0, -2.0, 12.0])
_y = st.sampled_from([0.0, 0.25, 0.5, 1.0])
_level = st.one_of(st.sampled_from([0.0, 0.25, 0.5, 0.75, 1.0, 1e-28]), st.floats(0.0, 1.0))


@st.composite
def _term(draw):
    kind = draw(st.sampled_from(["trian", "trape", "points"]))
    if kind == "points":
        xs = sorted(draw(st.lists(_x, min_size=2, max_size=5)))
        xs = [x for i, x in enumerate(xs) if i < 2 or xs[i - 2] != x]  # two per x at most
        if xs[0] == xs[-1]:
            xs[-1] += 1.0
        params = [v for x in xs for v in (x, draw(_y))]
        if not any(params[1::2]):
            params[1] = 1.0
    else:
        params = sorted(draw(st.lists(_x, min_size=3 if kind == "trian" else 4, max_size=4)))
        params = params[: 3 if kind == "trian" else 4]
        if params[0] == params[-1]:
            params[-1] += 1.0
    return make_membership(kind, params)


SEMANTICS = st.builds(
    lambda act, accu, method: Semantics(act=act, accu=accu, method=method),
    st.sampled_from(["MIN", "PROD"]),
    st.sampled_from(["MAX", "SUM", "NSUM", "BSUM"]),
    st.sampled_from(["COG", "COA", "LM", "RM", "MM"]),
)


def _data(sem: Semantics, levels: list[float], extra: list[tuple[int, float]]):
    """Collapsed semantics take one level per term; the others (pairs of term, level) per rule."""
    if Envelope(OutputShape(LO, HI, []), sem, sem.method).collapsed:
        return tuple(levels)
    return tuple([(k, lev) for k, lev in enumerate(levels)] + extra)


@SETTINGS
@given(
    terms=st.lists(_term(), min_size=1, max_size=9),
    sem=SEMANTICS,
    levels=st.lists(_level, min_size=9, max_size=9),
    extra=st.lists(st.tuples(st.integers(0, 8), _level), max_size=3),
)
def test_the_polyline_path_equals_the_former_exact_one(terms, sem, levels, extra) -> None:
    levels = levels[: len(terms)]
    extra = [(k % len(terms), lev) for k, lev in extra]
    if sem.method in ("LM", "RM", "MM"):
        # The former LM/RM/MM took the points within 1e-12 (absolute) of the top: for a set lower
        # than that, every point. Both now take it relative to the height (see
        # test_fuzzy_engine.py::test_a_set_of_tiny_height_still_has_its_own_maximum).
        assume(all(lev == 0.0 or lev > 1e-6 for lev in levels + [lev for _, lev in extra]))
    data = _data(sem, levels, extra)
    ours = Envelope(OutputShape(LO, HI, terms), sem, sem.method)(data)
    old = before.ExactGeneric(before.OutputShape(LO, HI, terms), sem, sem.method)(data)
    if old is None:
        assert ours is None
    else:
        assert ours == pytest.approx(old, abs=1e-9 * (HI - LO))


@SETTINGS
@given(terms=st.lists(_term(), min_size=1, max_size=9), levels=st.lists(_level, min_size=9))
def test_the_mamdani_centroid_equals_the_former_fast_path(terms, levels) -> None:
    alpha = tuple(levels[: len(terms)])
    ours = Envelope(OutputShape(LO, HI, terms), Semantics(), "COG")(alpha)
    old = before.MaxMinCog(before.OutputShape(LO, HI, terms))(alpha)
    assert (ours is None) == (old is None)
    if old is not None:
        assert ours == pytest.approx(old, abs=1e-9 * (HI - LO))


# ---------------------------------------------------------------------------------- scikit-fuzzy
def _params(t) -> tuple:
    return t.params


def _kinks(terms, levels, sem) -> np.ndarray:
    """Every x where the aggregated set can bend, by brute force: the terms' breakpoints, where an
    edge meets a clip level, and where any two lines (edges and levels) meet."""
    xs = {LO, HI} | {x for t in terms for x in t.xs if LO < x < HI}
    lines = []  # (slope, intercept, x0, x1)
    for t, lev in zip(terms, levels, strict=True):
        pts = [(LO, t.limits(LO)[1])] + [(x, y) for x, y in zip(t.xs, t.ys, strict=True)]
        pts.append((HI, t.limits(HI)[0]))
        for (x0, y0), (x1, y1) in itertools.pairwise(sorted(pts, key=lambda p: p[0])):
            if x1 > x0:
                k = (y1 - y0) / (x1 - x0)
                scale = lev if sem.act == "PROD" else 1.0
                lines.append((k * scale, (y0 - k * x0) * scale, x0, x1))
        if sem.act == "MIN":
            lines.append((0.0, lev, LO, HI))
    for (k1, c1, a1, b1), (k2, c2, a2, b2) in itertools.combinations(lines, 2):
        if k1 != k2:
            x = (c2 - c1) / (k1 - k2)
            if max(a1, a2, LO) < x < min(b1, b2, HI):
                xs.add(x)
    return np.array(sorted(xs))


def _aggregated(terms, levels, sem, xs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The aggregated set as samples skfuzzy integrates exactly: on each piece between two kinks
    it is straight, so its end values come from two inner points (jumps become two samples)."""
    a, b = xs[:-1], xs[1:]
    inner = np.stack([a + (b - a) / 3.0, a + 2.0 * (b - a) / 3.0])
    acc = np.zeros_like(inner)
    for t, lev in zip(terms, levels, strict=True):
        mu = oracle_mu(t.shape, _params(t), inner)
        act = np.minimum(lev, mu) if sem.act == "MIN" else lev * mu
        acc = np.maximum(acc, act) if sem.accu == "MAX" else acc + act
    left, right = 2.0 * acc[0] - acc[1], 2.0 * acc[1] - acc[0]
    x = np.repeat(xs, 2)[1:-1]
    y = np.stack([left, right], axis=1).ravel()
    y = np.clip(y, 0.0, None)
    if sem.accu == "BSUM":  # min(1, sum): a kink where the (straight) sum crosses 1
        cx, cy = [x[0]], [y[0]]
        for (x0, y0), (x1, y1) in itertools.pairwise(zip(x, y, strict=True)):
            if (y0 - 1.0) * (y1 - 1.0) < 0.0 and x1 > x0:
                cx.append(x0 + (1.0 - y0) / (y1 - y0) * (x1 - x0))
                cy.append(1.0)
            cx.append(x1)
            cy.append(y1)
        x, y = np.array(cx), np.minimum(np.array(cy), 1.0)
    return x, y


@SETTINGS
@given(
    terms=st.lists(_term(), min_size=1, max_size=9),
    act=st.sampled_from(["MIN", "PROD"]),
    accu=st.sampled_from(["MAX", "SUM", "BSUM"]),
    method=st.sampled_from(["COG", "COA"]),
    levels=st.lists(st.sampled_from([0.0, 0.3, 0.5, 0.8, 1.0]), min_size=9),
)
def test_the_polyline_path_equals_scikit_fuzzy_on_every_kink(
    terms, act, accu, method, levels
) -> None:
    sem = Semantics(act=act, accu=accu, method=method)
    levels = levels[: len(terms)]
    ours = Envelope(OutputShape(LO, HI, terms), sem, method)(_data(sem, levels, []))
    x, y = _aggregated(terms, levels, sem, _kinks(terms, levels, sem))
    if ours is None:
        assert y.max() < 1e-12
        return
    if method == "COG":
        assert ours == pytest.approx(skfuzzy.defuzz(x, y, "centroid"), abs=1e-9 * (HI - LO))
    else:
        # skfuzzy's bisector loses the area left of a zero-width step (its running sum is not
        # carried over one), and no shift of the jumps fixes that when the set starts with one:
        # the exact bisector of the polyline is the oracle instead.
        assert ours == pytest.approx(_bisector(x, y), abs=1e-9 * (HI - LO))


def _bisector(x: np.ndarray, y: np.ndarray) -> float:
    """The abscissa halving the area under the polyline through ``(x, y)``: the running area of
    its trapezoids, then, in the one where half is reached, the root of the area's quadratic."""
    widths, y0, y1 = np.diff(x), y[:-1], y[1:]
    areas = widths * (y0 + y1) / 2.0
    half = areas.sum() / 2.0
    before = np.concatenate([[0.0], np.cumsum(areas)])
    i = int(np.searchsorted(before, half, side="left")) - 1
    i = min(max(i, 0), len(areas) - 1)
    while areas[i] == 0.0 and i + 1 < len(areas):  # a zero-width or zero-height piece
        i += 1
    need, w, a, b = half - before[i], widths[i], y0[i], y1[i]
    slope = (b - a) / w
    if abs(slope) < 1e-15:
        return float(x[i] + need / a)
    # a t + slope t^2 / 2 = need, the root in [0, w]
    t = (-a + np.sqrt(max(a * a + 2.0 * slope * need, 0.0))) / slope
    return float(x[i] + t)


# ---------------------------------------------------------------------------------- the engine
def test_an_output_deeper_than_the_cut_takes_the_polyline_path() -> None:
    terms = [make_membership("triangle", (0.0, 1.0 + k, 10.0)) for k in range(DEEP + 1)]
    shape = OutputShape(LO, HI, terms)
    assert shape.deep and shape.intervals == []
    assert isinstance(make_defuzzifier(shape, Semantics(), "COG", where="t"), Envelope)
    assert not OutputShape(LO, HI, terms[:DEEP]).deep  # at the depth limit: still cut


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(
    peaks=st.lists(st.integers(1, 99), min_size=DEEP + 1, max_size=12),
    x=st.floats(0.0, 10.0),
    sem=st.sampled_from([Semantics(), Semantics(accu="SUM"), Semantics(act="PROD", accu="BSUM")]),
)
def test_a_deep_rule_base_equals_the_dense_oracle(peaks, x, sem) -> None:
    """Every output term spans the range (overlap = number of terms), the rules fire them at
    different degrees; the engine against the 200,001-point oracle of the other property tests."""
    out_terms = "; ".join(f"o{k} := trian 0 {p} 100" for k, p in enumerate(peaks))
    variables = {
        "x": (
            0.0,
            10.0,
            "; ".join(
                f"i{k} := trian {k % 10 - 3} {k % 10} {k % 10 + 3}" for k in range(len(peaks))
            ),
        ),
        "y": (0.0, 100.0, out_terms),
    }
    rules = [f"if x is i{k} then y is o{k}" for k in range(len(peaks))]
    engine = FuzzyEngine(sem)
    for name, (lo, hi, terms) in variables.items():
        engine.define_variable(name, lo, hi, terms)
    for rule in rules:
        engine.defrule(rule, "s")
    engine.set("x", x)
    engine.fire("s")
    want = oracle(variables, rules, {"x": x}, "y", sem)
    if want is None:
        assert engine.defaulted("s") == ("y",)
    else:
        assert engine.get("y") == pytest.approx(want, abs=2e-6 * 100)
    batch = engine.batch("s", {"x": [x, x]})["y"]  # the batch call loops over the deep output
    assert list(batch) == pytest.approx([engine.get("y")] * 2, abs=1e-12)
