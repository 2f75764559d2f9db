"""Independent oracles of the fuzzy engine, and random rule bases to feed them.

- :func:`oracle`: a dense evaluation written from the definitions: memberships from the shape
  parameters, rule degrees by a plain recursive evaluator, the aggregated set on 200,001 points,
  trapezoid-rule integrals (or the paper's engine's plain sums over its samples);
- :func:`rule_base`: random variables, terms and rules (hypothesis); :data:`OPERATORS`: random FCL
  operator choices.
"""

from __future__ import annotations

import itertools
import math

import numpy as np
from hypothesis import strategies as st

from acordcs.engines.fuzzy import FuzzyEngine, Semantics, make_membership
from acordcs.rules import Is, Not, parse_rule, parse_terms

DENSE = 200_001


# ---------------------------------------------------------------------------------- the oracle
def oracle_mu(shape: str, p: tuple, y: np.ndarray) -> np.ndarray:
    """Membership on an array, straight from the definitions (vertical edges: either side, the
    integrals do not care)."""
    if shape == "triangle":
        a, b, c = p
        up = np.where(b > a, (y - a) / (b - a if b > a else 1.0), 1.0)
        down = np.where(c > b, (c - y) / (c - b if c > b else 1.0), 1.0)
        return np.clip(np.where((y >= a) & (y <= c), np.minimum(up, down), 0.0), 0.0, 1.0)
    if shape == "trapezoid":
        a, b, c, d = p
        up = (y - a) / (b - a) if b > a else np.ones_like(y)
        down = (d - y) / (d - c) if d > c else np.ones_like(y)
        return np.clip(
            np.where((y >= a) & (y <= d), np.minimum(np.minimum(up, down), 1.0), 0.0), 0.0, 1.0
        )
    if shape == "points":
        xs, ys = np.array(p[0::2]), np.array(p[1::2])
        return np.interp(y, xs, ys)
    raise AssertionError(shape)


def oracle_point(shape: str, p: tuple, x: float) -> float:
    """Membership at one input value; at a vertical edge the upper value (the documented rule)."""
    if shape == "points":
        xs, ys = p[0::2], p[1::2]
        pts = list(zip(xs, ys, strict=False))
    elif shape == "triangle":
        pts = [(p[0], 0.0), (p[1], 1.0), (p[2], 0.0)]
    else:
        pts = [(p[0], 0.0), (p[1], 1.0), (p[2], 1.0), (p[3], 0.0)]
    if x < pts[0][0]:
        return pts[0][1] if shape == "points" else 0.0
    if x > pts[-1][0]:
        return pts[-1][1] if shape == "points" else 0.0
    best = 0.0
    for (x0, y0), (x1, y1) in itertools.pairwise(pts):
        if x0 <= x <= x1:
            v = max(y0, y1) if x1 == x0 else y0 + (y1 - y0) * (x - x0) / (x1 - x0)
            best = max(best, v)
    return best


def _degree(node, memb, and_, or_) -> float:
    if isinstance(node, Is):
        m = memb(node.var.text, node.term.text)
        for h in reversed(node.hedges):
            m = {"not": lambda v: 1.0 - v, "very": lambda v: v * v, "somewhat": math.sqrt}[h](m)
        return m
    if isinstance(node, Not):
        return 1.0 - _degree(node.operand, memb, and_, or_)
    a, b = _degree(node.left, memb, and_, or_), _degree(node.right, memb, and_, or_)
    return and_(a, b) if node.op == "and" else or_(a, b)


AND = {"MIN": min, "PROD": lambda a, b: a * b, "BDIF": lambda a, b: max(0.0, a + b - 1.0)}
OR = {"MAX": max, "ASUM": lambda a, b: a + b - a * b, "BSUM": lambda a, b: min(1.0, a + b)}


def oracle(
    variables: dict,
    rules: list[str],
    inputs: dict,
    out: str,
    sem: Semantics,
    n: int = DENSE,
    split_at: float | None = None,
):
    """Crisp output (None when nothing fired) by brute force on n points.

    With ``split_at`` (COA only): (share of the area left of ``split_at``, the integration's error
    bound on that share), to check a bisector by its definition.
    """
    defs = {
        name: {
            t.name.text: (make_membership(t.shape, t.parameters).shape, t.parameters)
            for t in parse_terms(terms)
        }
        for name, (_, _, terms) in variables.items()
    }

    def memb(var: str, term: str) -> float:
        shape, p = defs[var][term]
        lo, hi, _ = variables[var]
        return oracle_point(shape, p, min(max(inputs[var], lo), hi))

    lo, hi, _ = variables[out]
    y = np.linspace(lo, hi, n)
    mu = np.zeros(n)
    fired = False
    for text in rules:
        rule = parse_rule(text)
        d = _degree(rule.condition, memb, AND[sem.and_], OR[sem.or_]) * rule.weight
        for c in rule.actions:
            shape, p = defs[out][c.term.text]
            act = (
                np.minimum(d, oracle_mu(shape, p, y))
                if sem.act == "MIN"
                else d * oracle_mu(shape, p, y)
            )
            fired = fired or d > 0
            if sem.accu == "MAX":
                mu = np.maximum(mu, act)
            elif sem.accu in ("SUM", "NSUM"):
                mu = mu + act
            elif sem.accu == "BSUM":
                mu = np.minimum(1.0, mu + act)
            else:
                mu = mu + act - mu * act
    if sem.samples:  # the paper's engine: plain sums over its samples
        total = mu.sum()
        return None if total <= 0 else float((mu * y).sum() / total)
    w = np.full(n, y[1] - y[0])
    w[0] = w[-1] = w[0] / 2
    area = float((w * mu).sum())
    if not fired or area <= 0:
        return None
    if sem.method == "COG":
        return float((w * mu * y).sum() / area)
    if sem.method == "COA":
        cum = np.concatenate(([0.0], np.cumsum((mu[1:] + mu[:-1]) / 2 * np.diff(y))))
        if split_at is not None:
            # a grid of step h errs by about h * height / area in the share at a vertical edge
            per_step = float(mu.max()) / cum[-1]
            return float(np.interp(split_at, y, cum)) / cum[-1], per_step
        return float(np.interp(cum[-1] / 2, cum, y))
    raise AssertionError(sem.method)


def ours(engine: FuzzyEngine, ruleset: str, inputs: dict, out: str) -> float:
    for k, v in inputs.items():
        engine.set(k, v)
    engine.fire(ruleset)
    return engine.get(out)


# ---------------------------------------------------------------------------------- random rule bases
GRID = [i / 8 for i in range(9)]


@st.composite
def term_list(draw, lo: float, hi: float, count: int) -> str:
    out = []
    for k in range(count):
        kind = draw(st.sampled_from(["trian", "trape", "points"]))
        pick = lambda n: sorted(lo + (hi - lo) * draw(st.sampled_from(GRID)) for _ in range(n))  # noqa: E731
        if kind == "trian":
            a, b, c = pick(3)
            if a == c:
                c = hi if a < hi else lo
                a, b, c = sorted((a, b, c))
            out.append(f"t{k} := trian {a!r} {b!r} {c!r}")
        elif kind == "trape":
            a, b, c, d = pick(4)
            if a == d:
                a, d = lo, hi
            out.append(f"t{k} := trape {a!r} {b!r} {c!r} {d!r}")
        else:
            xs = sorted(set(pick(draw(st.integers(2, 4)))))
            if len(xs) < 2:
                xs = [lo, hi]
            ys = [draw(st.sampled_from([0.0, 0.25, 0.5, 1.0])) for _ in xs]
            out.append(
                f"t{k} := " + " ".join(f"({x!r}, {y!r})" for x, y in zip(xs, ys, strict=False))
            )
    return "; ".join(out)


@st.composite
def condition(draw, inputs: dict, depth: int = 0) -> str:
    if depth >= 2 or draw(st.booleans()):
        var = draw(st.sampled_from(sorted(inputs)))
        term = draw(st.sampled_from(inputs[var]))
        hedges = draw(st.lists(st.sampled_from(["not", "very", "somewhat"]), max_size=2))
        return f"{var} is {' '.join(hedges) + ' ' if hedges else ''}{term}"
    op = draw(st.sampled_from(["and", "or", "not"]))
    if op == "not":
        return f"not ({draw(condition(inputs, depth + 1))})"
    return f"({draw(condition(inputs, depth + 1))}) {op} {draw(condition(inputs, depth + 1))}"


@st.composite
def rule_base(draw):
    variables, inputs = {}, {}
    for i in range(draw(st.integers(1, 3))):
        lo = float(draw(st.integers(-50, 50)))
        hi = lo + float(draw(st.sampled_from([1, 8, 40, 200])))
        count = draw(st.integers(2, 4))
        variables[f"in{i}"] = (lo, hi, draw(term_list(lo, hi, count)))
        inputs[f"in{i}"] = [f"t{k}" for k in range(count)]
    lo = float(draw(st.integers(-100, 100)))
    hi = lo + float(draw(st.sampled_from([10, 100, 200])))
    nout = draw(st.integers(2, 5))
    variables["out"] = (lo, hi, draw(term_list(lo, hi, nout)))
    rules = []
    for _ in range(draw(st.integers(1, 8))):
        w = draw(st.sampled_from([1.0, 1.0, 0.5, 0.8]))
        rule = f"if {draw(condition(inputs))} then out is t{draw(st.integers(0, nout - 1))}"
        rules.append(rule + (f" with {w}" if w != 1.0 else ""))
    values = {
        name: draw(st.one_of(st.sampled_from([lo, hi]), st.floats(lo, hi)))
        for name, (lo, hi, _) in variables.items()
        if name != "out"
    }
    return variables, rules, values


OPERATORS = st.builds(
    lambda and_, act, accu, method: Semantics(
        and_=and_,
        or_={"MIN": "MAX", "PROD": "ASUM", "BDIF": "BSUM"}[and_],
        act=act,
        accu=accu,
        method=method,
    ),
    st.sampled_from(["MIN", "PROD", "BDIF"]),
    st.sampled_from(["MIN", "PROD"]),
    st.sampled_from(["MAX", "SUM", "NSUM", "BSUM", "PROBOR"]),
    st.sampled_from(["COG", "COA"]),
)
