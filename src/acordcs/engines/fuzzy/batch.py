"""Many inferences at once with numpy (simulation, what-if analysis).

Same semantics and same numbers as ``set``/``fire``/``get`` row by row. Vectorised: mamdani's exact
max-min centroid, product/sum centroid, sampled semantics (the paper's engine, non-linear terms),
singletons. Other exact combinations (COA/LM/RM/MM, BSUM) loop over the rows in Python.
"""

from __future__ import annotations

import itertools
from collections.abc import Callable

import numpy as np

from acordcs.engines.fuzzy.defuzz import MaxMinCog, Singletons, SumProdCog
from acordcs.engines.fuzzy.fuzzy_compiler import CompiledRuleSet, OutputPlan
from acordcs.engines.fuzzy.sampled import Sampled, accumulate, sampled_method
from acordcs.engines.rule_engine import RuleError

_CHUNK = 4096  # rows per step of the max-min centroid: bounds the (rows x pieces x terms) arrays


def run_batch(
    compiled: CompiledRuleSet,
    columns: dict[str, object],
    values: dict[str, float | None],
    warn: Callable[[str, float], None],
) -> dict[str, np.ndarray]:
    xs = _inputs(compiled, columns, values, warn)
    n = max((len(a) for a in xs.values()), default=1)
    xs = {k: np.broadcast_to(a, (n,)) for k, a in xs.items()}
    sem = compiled.semantics
    mem: dict[tuple, np.ndarray] = {}

    def degree(node: tuple) -> np.ndarray:
        kind = node[0]
        if kind == "is":
            _, var, hedges, term = node
            key = (var, term)
            if key not in mem:
                mf = compiled.variables[var].terms[term]
                mem[key] = mf.evaluate(xs[var])
            m = mem[key]
            for h in reversed(hedges):
                m = m * m if h == "very" else (np.sqrt(m) if h == "somewhat" else 1.0 - m)
            return m
        if kind == "not":
            return 1.0 - degree(node[1])
        return _binary(sem.and_ if kind == "and" else sem.or_, degree(node[1]), degree(node[2]))

    degrees = []
    for e in compiled.entries:
        d = degree(e.condition)
        degrees.append(np.broadcast_to(d * e.weight if e.weight != 1.0 else d, (n,)))
    out = {}
    for plan in compiled.outputs:
        dz = plan.defuzzifier
        if getattr(dz, "needs_values", False):  # FUNCTION terms: their points row by row
            alpha = _alpha(plan, degrees, sem.accu, n)
            rows = [{k: float(a[i]) for k, a in xs.items()} for i in range(n)]
            result = np.array(
                [np.nan if (v := dz(tuple(alpha[i]), rows[i])) is None else v for i in range(n)]
            )
        else:
            result = _defuzz(plan, degrees, sem.accu, n)
        missing = np.isnan(result)
        if missing.any():
            result[missing] = plan.variable.fallback(values.get(plan.name))
        out[plan.name] = result
    return out


def _numbers(name: str, column: object, ruleset: str) -> np.ndarray:
    """``column`` as a 1-D float array; text (``'5'``) and numbers beyond a float are a RuleError,
    as in ``set``."""
    raw = np.asarray(column)
    text = raw.dtype.kind in "USV" or (
        raw.dtype.kind == "O" and any(isinstance(v, str | bytes) for v in raw.ravel())
    )
    if not text:
        try:
            return np.atleast_1d(raw.astype(float))
        except (OverflowError, TypeError, ValueError):
            pass
    raise RuleError(
        f"input {name!r} must be numbers: text (such as '5') and numbers beyond a float's "
        "range are refused",
        ruleset=ruleset,
    )


def _inputs(compiled, columns, values, warn) -> dict[str, np.ndarray]:
    out = {}
    variables = compiled.variables
    for name in compiled.inputs:
        var = variables[name]
        if name in columns:
            arr = _numbers(name, columns[name], compiled.name)
        elif values.get(name) is not None:
            arr = np.atleast_1d(np.asarray(values[name], dtype=float))
        else:
            raise RuleError(
                f"input {name!r} has no value and no column; pass it in inputs or set() it first",
                ruleset=compiled.name,
            )
        if arr.ndim != 1:
            raise RuleError(
                f"input {name!r} must be a 1-D array, got shape {arr.shape}", ruleset=compiled.name
            )
        bad = ~np.isfinite(arr)
        if bad.any():
            row = int(np.argmax(bad))
            raise RuleError(
                f"input {name!r} row {row} is {float(arr[row])!r}, not a finite number; remove or fix that row",
                ruleset=compiled.name,
            )
        outside = (arr < var.lo) | (arr > var.hi)
        if outside.any():
            warn(name, float(arr[int(np.argmax(outside))]))
            arr = np.clip(arr, var.lo, var.hi)
        out[name] = arr
    lengths = {len(a) for a in out.values() if len(a) != 1}
    if len(lengths) > 1:
        raise RuleError(f"input columns differ in length: {sorted(lengths)}", ruleset=compiled.name)
    return out


def _binary(op: str, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    if op == "MIN":
        return np.minimum(a, b)
    if op == "MAX":
        return np.maximum(a, b)
    if op == "PROD":
        return a * b
    if op == "ASUM":
        return a + b - a * b
    if op == "BDIF":
        return np.maximum(a + b - 1.0, 0.0)
    if op == "BSUM":
        return np.minimum(a + b, 1.0)
    if op == "DMIN":
        return np.where(a == 1.0, b, np.where(b == 1.0, a, 0.0))
    if op == "DMAX":
        return np.where(a == 0.0, b, np.where(b == 0.0, a, 1.0))
    if op == "NIPMIN":
        return np.where(a + b > 1.0, np.minimum(a, b), 0.0)
    if op == "NIPMAX":
        return np.where(a + b < 1.0, np.maximum(a, b), 1.0)
    if op == "HAMACHER":
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where((a == 0.0) & (b == 0.0), 0.0, a * b / (a + b - a * b))
    return (a + b) / (1.0 + a * b)  # EINSTEIN


def _alpha(plan: OutputPlan, degrees: list[np.ndarray], accu: str, n: int) -> np.ndarray:
    """The folded degree of each term of a collapsed output, one row per input row."""
    nterms = len(plan.variable.terms)
    alpha = np.zeros((n, nterms))
    for k in range(nterms):
        acc = None
        for r, kk in plan.sources:
            if kk == k:
                acc = degrees[r] if acc is None else _fold(accu, acc, degrees[r])
        if acc is not None:
            alpha[:, k] = acc
    return alpha


def _defuzz(plan: OutputPlan, degrees: list[np.ndarray], accu: str, n: int) -> np.ndarray:
    dz = plan.defuzzifier
    nterms = len(plan.variable.terms)
    if plan.collapsed:
        alpha = _alpha(plan, degrees, accu, n)
        if isinstance(dz, MaxMinCog):
            return np.concatenate([_maxmin(dz, alpha[i : i + _CHUNK]) for i in range(0, n, _CHUNK)])
        if isinstance(dz, SumProdCog):
            area = alpha @ np.asarray(dz.areas)
            moment = alpha @ np.asarray(dz.moments)
            return _ratio(moment, area)
        if isinstance(dz, Singletons):
            return _singletons(dz, alpha)
        if isinstance(dz, Sampled):
            return _sampled(dz, [(k, alpha[:, k]) for k in range(nterms)], n)
        return _rows(dz, [tuple(row) for row in alpha])
    items = [(k, degrees[r]) for r, k in plan.sources]
    if isinstance(dz, Sampled):
        return _sampled(dz, items, n)
    return _rows(dz, [tuple((k, float(d[i])) for k, d in items) for i in range(n)])


def _fold(accu: str, acc: np.ndarray, d: np.ndarray) -> np.ndarray:
    if accu in ("SUM", "NSUM"):
        return acc + d
    return accumulate(accu, acc, d)


def _ratio(num: np.ndarray, den: np.ndarray) -> np.ndarray:
    out = np.full(num.shape, np.nan)
    ok = den > 0.0
    out[ok] = num[ok] / den[ok]
    return out


def _rows(dz, rows) -> np.ndarray:
    return np.array([np.nan if (v := dz(row)) is None else v for row in rows], dtype=float)


def _singletons(dz: Singletons, alpha: np.ndarray) -> np.ndarray:
    xs = np.asarray(dz.xs)
    total = alpha.sum(axis=1)
    if dz.method in ("COG", "COGS"):
        return _ratio(alpha @ xs, total)
    top = alpha.max(axis=1, keepdims=True)
    at = alpha >= top - 1e-12 * top  # relative: a set of height 1e-28 has a top too
    if dz.method == "LM":
        out = np.where(at, xs, np.inf).min(axis=1)
    elif dz.method == "RM":
        out = np.where(at, xs, -np.inf).max(axis=1)
    else:
        out = np.where(at, xs, 0.0).sum(axis=1) / at.sum(axis=1)
    return np.where(total > 0.0, out, np.nan)


def _sampled(dz: Sampled, items, n: int) -> np.ndarray:
    acc = np.zeros((n, dz.grid.size))
    first = True
    for k, lev in items:
        lev = lev[:, None]
        row = np.minimum(lev, dz.table[k]) if dz.act == "MIN" else lev * dz.table[k]
        acc = (
            row
            if first
            else (acc + row if dz.accu in ("SUM", "NSUM") else accumulate(dz.accu, acc, row))
        )
        first = False
    if dz.method == "COG":
        wm = acc * dz.weights
        return _ratio(wm @ dz.grid, wm.sum(axis=1))
    return np.array(
        [
            np.nan if (v := sampled_method(dz.grid, dz.weights, mu, dz.method)) is None else v
            for mu in acc
        ]
    )


def _maxmin_tables(dz: MaxMinCog):
    """Fixed pieces for the inclusion-exclusion form of the max-min centroid.

    max_i f_i = sum over non-empty subsets S of (-1)^(|S|+1) min_{i in S} f_i, and with
    f_i = min(level_i, line_i): min_S f_i = min(min_S level_i, lower envelope of the lines in S).
    That lower envelope is concave with kinks that do not depend on the levels, so every subset of
    every interval becomes a few fixed straight pieces, each clipped at one level per row."""
    cached = dz.batch_tables
    if cached is not None:
        return cached
    rows = []  # (sign, term indices, xa, ya, xb, yb)
    for x0, x1, lines in dz.intervals:
        n = len(lines)
        for mask in range(1, 1 << n):
            subset = [lines[i] for i in range(n) if mask >> i & 1]
            sign = 1.0 if len(subset) % 2 else -1.0
            us = {0.0, 1.0}
            for i, (_, p, q) in enumerate(subset):
                for _, pj, qj in subset[i + 1 :]:
                    den = (q - p) - (qj - pj)
                    if den != 0.0 and 0.0 < (u := (pj - p) / den) < 1.0:
                        us.add(u)
            pts = [
                (x0 + u * (x1 - x0), min(p + (q - p) * u for _, p, q in subset)) for u in sorted(us)
            ]
            terms = [t for t, _, _ in subset]
            for (xa, ya), (xb, yb) in itertools.pairwise(pts):
                if xb > xa:
                    rows.append((sign, terms, xa, ya, xb, yb))
    width = max((len(r[1]) for r in rows), default=1)
    idx = np.array([r[1] + [r[1][0]] * (width - len(r[1])) for r in rows], dtype=int).reshape(
        len(rows), width
    )
    sign, xa, ya, xb, yb = (np.array([r[i] for r in rows], dtype=float) for i in (0, 2, 3, 4, 5))
    cached = (idx, sign, xa, ya, xb, yb)
    dz.batch_tables = cached
    return cached


def _maxmin(dz: MaxMinCog, alpha: np.ndarray) -> np.ndarray:
    """The exact max-min centroid of each row (same value as MaxMinCog, all rows at once)."""
    idx, sign, xa, ya, xb, yb = _maxmin_tables(dz)
    if not len(sign):
        return np.full(len(alpha), np.nan)
    c = alpha[:, idx].min(axis=2)  # (rows, pieces): the clip level of each fixed piece
    w = xb - xa
    y0 = np.minimum(ya, c)
    y1 = np.minimum(yb, c)
    cross = (ya - c) * (yb - c) < 0.0
    with np.errstate(divide="ignore", invalid="ignore"):
        xc = np.where(cross, xa + (c - ya) / (yb - ya) * w, xb)
    ym = np.where(cross, c, y1)
    wa, wb = xc - xa, xb - xc
    area = (y0 + ym) * wa + (ym + y1) * wb
    moment = (
        wa * (y0 * (2.0 * xa + xc) + ym * (xa + 2.0 * xc))
        + wb * (ym * (2.0 * xc + xb) + y1 * (xc + 2.0 * xb))
    ) / 6.0
    return _ratio(moment @ sign, area @ sign * 0.5)
