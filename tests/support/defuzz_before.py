"""PINNED COPY (do not edit): src/acordcs/engines/fuzzy/defuzz.py as it was at commit 1bc763a,
before outputs with deeply overlapping terms got the polyline path. The oracle of
tests/engines/test_fuzzy_deep_overlap.py and the "before" of benchmarks/bench_fuzzy_deep.py: every
defuzzifier here is the former exact one, cubic in the lines of an interval.

The original module docstring follows.

Accumulation and defuzzification of one output variable, exact for piecewise-linear terms.

The output's terms are cut at every breakpoint of every term (:class:`OutputShape`): inside one such
interval every term is a straight line. An activated term is then ``min(level, line)`` (activation
MIN) or ``level * line`` (PROD); their max, sum or bounded sum is piecewise linear again, with kinks
only where a line meets a clip level or another line. Evaluating the aggregated set at those kinks
and integrating each straight piece gives the centroid in closed form (no sampling error).

Non-linear output terms (gaussian, bell, sigmoid) and PROBOR accumulation are not piecewise linear:
they are sampled on :data:`acordcs.engines.fuzzy.sampled.FALLBACK_SAMPLES` evenly spaced points over the range and integrated with
trapezoid weights (error well under 1e-4 of the range for the shapes we tested).
A semantics with ``samples`` (the paper's engine) uses plain sums over that many samples instead.

Each defuzzifier returns None when nothing was activated (the caller applies DEFAULT).
"""

from __future__ import annotations

import itertools
import math
from bisect import bisect_left, bisect_right

from acordcs.engines.fuzzy.membership import Membership
from acordcs.engines.fuzzy.sampled import Sampled
from acordcs.engines.fuzzy.semantics import SUMS, Semantics, collapses
from acordcs.engines.rule_engine import RuleError


class OutputShape:
    """The terms of an output variable over its range ``[lo, hi]``, cut into linear intervals."""

    def __init__(self, lo: float, hi: float, terms: list[Membership]) -> None:
        self.lo, self.hi, self.terms = lo, hi, terms
        self.linear = all(t.linear for t in terms)
        self.singletons = bool(terms) and all(t.singleton for t in terms)
        self.mixed = not self.singletons and any(t.singleton for t in terms)
        # intervals: (x0, x1, ((term, v0, v1), ...)) with v0/v1 the line's values at the ends
        self.intervals: list[tuple[float, float, tuple[tuple[int, float, float], ...]]] = []
        if self.linear:
            cuts = {lo, hi} | {x for t in terms for x in t.xs if lo < x < hi}
            us = sorted(cuts)
            found: list[list[tuple[int, float, float]]] = [[] for _ in range(len(us) - 1)]
            for k, t in enumerate(terms):
                # Outside its breakpoints a term is constant (its left or right value): a term
                # that is 0 there only visits the intervals between them. Visiting every interval
                # for every term made an output of n terms cost n**2 (250 terms: 0.1 s).
                first = max(0, bisect_right(us, t.xs[0]) - 1) if t.left == 0 else 0
                stop = bisect_left(us, t.xs[-1]) if t.right == 0 else len(found)
                for i in range(first, min(stop, len(found))):
                    v0, v1 = t.limits(us[i])[1], t.limits(us[i + 1])[0]
                    if v0 or v1:
                        found[i].append((k, v0, v1))
            self.intervals = [
                (x0, x1, tuple(lines))
                for (x0, x1), lines in zip(itertools.pairwise(us), found, strict=True)
            ]

    def area_moment(self) -> tuple[list[float], list[float]]:
        """Exact area and first moment of each (unactivated) term over the range."""
        areas = [0.0] * len(self.terms)
        moments = [0.0] * len(self.terms)
        for x0, x1, lines in self.intervals:
            for k, v0, v1 in lines:
                a, m = _piece(x0, v0, x1, v1)
                areas[k] += a
                moments[k] += m
        return areas, moments


def _piece(xa: float, ya: float, xb: float, yb: float) -> tuple[float, float]:
    """Area and first moment of the straight piece from (xa, ya) to (xb, yb)."""
    w = xb - xa
    return (ya + yb) * w * 0.5, w * (ya * (2.0 * xa + xb) + yb * (xa + 2.0 * xb)) / 6.0


# ---------------------------------------------------------------------------------- choosing
def make_defuzzifier(
    shape: OutputShape, sem: Semantics, method: str, *, where: str
) -> Singletons | Sampled | MaxMinCog | SumProdCog | ExactGeneric:
    """The defuzzifier for one output of one rule set; configuration errors name ``where``."""
    if shape.mixed:
        raise RuleError(
            f"{where}: an output cannot mix singleton terms with shaped terms; use one kind"
        )
    if shape.singletons:
        if method == "COA":
            raise RuleError(f"{where}: METHOD COA needs shaped terms; use COGS with singletons")
        return Singletons(shape, method)
    if method == "COGS":
        raise RuleError(f"{where}: METHOD COGS needs singleton terms; use COG for shaped terms")
    if sem.samples or not shape.linear or sem.accu == "PROBOR":
        return Sampled(shape, sem, method)
    if method == "COG" and sem.act == "MIN" and sem.accu == "MAX":
        return MaxMinCog(shape)
    if method == "COG" and sem.act == "PROD" and sem.accu in SUMS:
        return SumProdCog(shape)
    return ExactGeneric(shape, sem, method)


# ---------------------------------------------------------------------------------- exact paths
class MaxMinCog:
    """Mamdani's min activation, max accumulation, exact centroid: the fast path."""

    collapsed = True
    kind = "maxmin"

    def __init__(self, shape: OutputShape) -> None:
        self.shape = shape
        self.intervals = [(x0, x1, lines) for x0, x1, lines in shape.intervals if lines]
        # The batch form's fixed pieces: fuzzy.batch builds them on first use and keeps them here.
        self.batch_tables: tuple | None = None

    def __call__(self, alpha) -> float | None:
        area = moment = 0.0
        for x0, x1, lines in self.intervals:
            live = [(alpha[k], v0, v1) for k, v0, v1 in lines if alpha[k] > 0.0]
            if not live:
                continue
            if len(live) > 1:
                a, m = _max_of_clipped(x0, x1, live)
                area += a
                moment += m
                continue
            lev, v0, v1 = live[0]
            w = x1 - x0
            if v0 <= lev and v1 <= lev:
                area += (v0 + v1) * w * 0.5
                moment += w * (v0 * (2.0 * x0 + x1) + v1 * (x0 + 2.0 * x1)) / 6.0
            elif v0 >= lev and v1 >= lev:
                area += lev * w
                moment += lev * w * (x0 + x1) * 0.5
            else:
                xc = x0 + (lev - v0) / (v1 - v0) * w
                y0 = v0 if v0 < lev else lev
                y1 = v1 if v1 < lev else lev
                wa, wb = xc - x0, x1 - xc
                area += (y0 + lev) * wa * 0.5 + (lev + y1) * wb * 0.5
                moment += wa * (y0 * (2.0 * x0 + xc) + lev * (x0 + 2.0 * xc)) / 6.0
                moment += wb * (lev * (2.0 * xc + x1) + y1 * (xc + 2.0 * x1)) / 6.0
        return moment / area if area > 0.0 else None


_U_FIRST, _U_LAST = math.nextafter(0.0, 1.0), math.nextafter(1.0, 0.0)


def _crossing(lev: float, p: float, q: float) -> float | None:
    """Where (0..1) the line from p to q crosses the clip level ``lev``, if it does inside.

    Kept strictly inside even when rounding puts it on an end: a tiny level clipping a steep line
    (a rule firing at 1e-28) crosses within 1e-16 of the end, and losing that kink would turn the
    flat clipped band into a slope and move the centroid or bisector by a third of the interval.
    """
    if not (p < lev < q or q < lev < p):
        return None
    u = (lev - p) / (q - p)
    return min(max(u, _U_FIRST), _U_LAST)


def _max_of_clipped(x0: float, x1: float, live) -> tuple[float, float]:
    """Exact integral of max_i min(level_i, line_i) over [x0, x1] with two or more lines."""
    us = [0.0, 1.0]
    n = len(live)
    for i in range(n):
        _, p, q = live[i]
        s = q - p
        if s != 0.0:
            for lev, _, _ in live:
                if p < lev < q or q < lev < p:  # _crossing, inlined: this loop is the hot path
                    u = (lev - p) / s
                    us.append(_U_FIRST if u <= 0.0 else _U_LAST if u >= 1.0 else u)
        for j in range(i + 1, n):
            _, pj, qj = live[j]
            sj = qj - pj
            if s != sj:
                u = (pj - p) / (s - sj)
                if 0.0 < u < 1.0:
                    us.append(u)
    us.sort()
    w = x1 - x0
    pts = []
    for u in us:
        best = 0.0
        for lev, p, q in live:
            v = p + (q - p) * u
            v = v if v < lev else lev
            best = v if v > best else best
        pts.append((x0 + u * w, best))
    area = moment = 0.0
    for (xa, ya), (xb, yb) in itertools.pairwise(pts):
        a, m = _piece(xa, ya, xb, yb)
        area += a
        moment += m
    return area, moment


class SumProdCog:
    """Product activation with (normalised) sum accumulation: the centroid is a weighted mean of
    the terms' own centroids, exact and independent of overlaps."""

    collapsed = True
    kind = "sumprod"

    def __init__(self, shape: OutputShape) -> None:
        self.shape = shape
        self.areas, self.moments = shape.area_moment()

    def __call__(self, alpha) -> float | None:
        area = moment = 0.0
        for a, ar, mo in zip(alpha, self.areas, self.moments, strict=False):
            if a > 0.0:
                area += a * ar
                moment += a * mo
        return moment / area if area > 0.0 else None


class ExactGeneric:
    """Any exact combination (ACCU MAX/SUM/NSUM/BSUM, ACT MIN/PROD, METHOD COG/COA/LM/RM/MM)."""

    kind = "exact"

    def __init__(self, shape: OutputShape, sem: Semantics, method: str) -> None:
        self.shape, self.act, self.accu, self.method = shape, sem.act, sem.accu, method
        self.collapsed = collapses(sem, False)
        self.lines = [
            (x0, x1, {k: (v0, v1) for k, v0, v1 in lines}) for x0, x1, lines in shape.intervals
        ]

    def __call__(self, data) -> float | None:
        items = list(enumerate(data)) if self.collapsed else list(data)
        items = [(k, lev) for k, lev in items if lev > 0.0]
        if not items:
            return None
        return apply_method(self.pieces(items), self.method)

    def pieces(self, items: list[tuple[int, float]]) -> list[tuple[float, float, float, float]]:
        """The aggregated set as straight pieces (xa, ya, xb, yb), in order."""
        out = []
        mn, accu = self.act == "MIN", self.accu
        for x0, x1, lines in self.lines:
            fs = []
            for k, lev in items:
                vv = lines.get(k)
                if vv is not None:
                    fs.append((lev, vv[0], vv[1]) if mn else (math.inf, lev * vv[0], lev * vv[1]))
            if not fs:
                continue
            us = {0.0, 1.0}
            for i, (own, p, q) in enumerate(fs):
                s = q - p
                levels = [f[0] for f in fs] if accu == "MAX" else [own]
                if s != 0.0:
                    for lev in levels:
                        u = _crossing(lev, p, q)
                        if u is not None:
                            us.add(u)
                if accu == "MAX":
                    for _, pj, qj in fs[i + 1 :]:
                        sj = qj - pj
                        if s != sj:
                            u = (pj - p) / (s - sj)
                            if 0.0 < u < 1.0:
                                us.add(u)
            ordered = sorted(us)
            vals = [self._agg(fs, u) for u in ordered]
            if accu == "BSUM":
                ordered, vals = self._bsum_kinks(ordered, vals)
                vals = [v if v < 1.0 else 1.0 for v in vals]
            w = x1 - x0
            xs = [x0 + u * w for u in ordered]
            out.extend((xs[i], vals[i], xs[i + 1], vals[i + 1]) for i in range(len(xs) - 1))
        return out

    def _agg(self, fs, u: float) -> float:
        vals = [min(lev, p + (q - p) * u) for lev, p, q in fs]
        return max(vals) if self.accu == "MAX" else sum(vals)

    def _bsum_kinks(self, us, vals):
        # between consecutive kinks the raw sum is linear; the bound at 1 adds one more kink
        new_us, new_vals = [us[0]], [vals[0]]
        for i in range(len(us) - 1):
            a, b = vals[i], vals[i + 1]
            if (a - 1.0) * (b - 1.0) < 0.0:
                u = us[i] + (1.0 - a) / (b - a) * (us[i + 1] - us[i])
                new_us.append(u)
                new_vals.append(1.0)
            new_us.append(us[i + 1])
            new_vals.append(b)
        return new_us, new_vals


def apply_method(pieces: list[tuple[float, float, float, float]], method: str) -> float | None:
    """COG, COA, LM, RM or MM of a piecewise-linear set given as straight pieces."""
    if method in ("COG", "COA"):
        areas = [_piece(*p) for p in pieces]
        total = sum(a for a, _ in areas)
        if total <= 0.0:
            return None
        if method == "COG":
            return sum(m for _, m in areas) / total
        half, acc = total * 0.5, 0.0
        for (xa, ya, xb, yb), (a, _) in zip(pieces, areas, strict=False):
            if a > 0.0 and acc + a >= half:
                r, w = half - acc, xb - xa
                k = (yb - ya) / w
                t = 2.0 * r / (ya + math.sqrt(max(ya * ya + 2.0 * k * r, 0.0)))
                return xa + min(max(t, 0.0), w)
            acc += a
        return pieces[-1][2]
    top = max((max(p[1], p[3]) for p in pieces), default=0.0)
    if top <= 0.0:
        return None
    tol = 1e-12 * max(1.0, top)
    at = [x for xa, ya, xb, yb in pieces for x, y in ((xa, ya), (xb, yb)) if y >= top - tol]
    if method == "LM":
        return min(at)
    if method == "RM":
        return max(at)
    flats = [
        (xa, xb) for xa, ya, xb, yb in pieces if ya >= top - tol and yb >= top - tol and xb > xa
    ]
    length = sum(xb - xa for xa, xb in flats)
    if length > 0.0:
        return sum((xa + xb) * 0.5 * (xb - xa) for xa, xb in flats) / length
    unique = sorted(set(at))
    return sum(unique) / len(unique)


# ---------------------------------------------------------------------------------- singletons
class Singletons:
    """Singleton outputs: COGS (COG means the same), LM, RM, MM on the accumulated heights."""

    collapsed = True
    kind = "singletons"

    def __init__(self, shape: OutputShape, method: str) -> None:
        self.xs = [t.params[0] for t in shape.terms]
        self.method = method

    def __call__(self, alpha) -> float | None:
        total = sum(alpha)
        if total <= 0.0:
            return None
        if self.method in ("COG", "COGS"):
            return sum(a * x for a, x in zip(alpha, self.xs, strict=False)) / total
        top = max(alpha)
        at = [x for a, x in zip(alpha, self.xs, strict=False) if a >= top - 1e-12 * max(1.0, top)]
        if self.method == "LM":
            return min(at)
        if self.method == "RM":
            return max(at)
        return sum(at) / len(at)
