"""Aggregated output sets as polylines: exact, in O(N log n) for n activated terms of N breakpoints.

An output term over the range ``[lo, hi]`` is a polyline: points ``(x, y)`` with x not decreasing,
the first at ``lo`` and the last at ``hi``; a vertical edge is two points with the same x (the
value coming from the left, then the value going on to the right). Activation keeps it a polyline
(MIN: clipped at the level, with a point where an edge crosses it; PROD: scaled). Accumulation
merges the activated polylines pairwise, in a balanced tree of merges:

- MAX: the upper envelope. Merging two polylines walks their breakpoints once, adds a point where
  they cross and drops a breakpoint of the lower one, so a merge is linear in its inputs and the
  tree costs O(N log n) (the envelope of straight pieces has near-linear size);
- SUM, NSUM, BSUM: the pointwise sum, merged the same way (BSUM is then bounded at 1, with a point
  where the sum crosses 1).

The result goes to :func:`acordcs.runtime.fuzzy.defuzz.apply_method` as straight pieces. This is
the path of outputs whose terms overlap deeply (see ``DEEP`` in ``defuzz``): cutting such an output
into intervals between all breakpoints costs n lines per interval and every crossing of every pair
of lines on every firing (250 overlapping terms took seconds per firing).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from acordcs.runtime.fuzzy.membership import Membership

Polyline = tuple[list[float], list[float]]


def term_polyline(term: Membership, lo: float, hi: float) -> Polyline:
    """A piecewise-linear term over ``[lo, hi]``: its right limit at ``lo``, both limits at every
    breakpoint inside (one point when they agree), its left limit at ``hi``."""
    xs, ys = [lo], [term.limits(lo)[1]]
    last = lo
    for x in term.xs:
        if lo < x < hi and x != last:
            left, right = term.limits(x)
            xs.append(x)
            ys.append(left)
            if right != left:
                xs.append(x)
                ys.append(right)
            last = x
    xs.append(hi)
    ys.append(term.limits(hi)[0])
    return xs, ys


def clip(poly: Polyline, level: float) -> Polyline:
    """``min(level, poly)``, with a point wherever a sloping piece crosses ``level``."""
    xs, ys = poly
    out_x, out_y = [xs[0]], [ys[0] if ys[0] < level else level]
    for i in range(1, len(xs)):
        x0, y0, x1, y1 = xs[i - 1], ys[i - 1], xs[i], ys[i]
        if (y0 - level) * (y1 - level) < 0.0 and x1 > x0:
            xc = x0 + (level - y0) / (y1 - y0) * (x1 - x0)
            # Rounding can put a crossing on an end (a level of 1e-28 on a steep edge): the point
            # then sits at that end's x and the piece stays flat at the level, as it should.
            out_x.append(xc if xc < x1 else x1)
            out_y.append(level)
        out_x.append(x1)
        out_y.append(y1 if y1 < level else level)
    return _tidy(out_x, out_y)


def scale(poly: Polyline, level: float) -> Polyline:
    """``level * poly`` (activation PROD)."""
    return poly[0], [level * y for y in poly[1]]


def _tidy(xs: list[float], ys: list[float]) -> Polyline:
    """At most two points per x (the first and the last value there): what the merges expect."""
    out_x, out_y = [], []
    n = len(xs)
    for i in range(n):
        x = xs[i]
        if 0 < i < n - 1 and xs[i - 1] == x == xs[i + 1]:
            continue
        out_x.append(x)
        out_y.append(ys[i])
    return out_x, out_y


def _limits(xs: list[float], ys: list[float], p: int, x: float) -> tuple[float, float, int, bool]:
    """Left and right value of a polyline at ``x`` (its own breakpoint, or between ``p - 1`` and
    ``p``), the index of its next point after ``x``, and whether ``x`` is its breakpoint."""
    if xs[p] == x:
        left = ys[p]
        if p + 1 < len(xs) and xs[p + 1] == x:
            return left, ys[p + 1], p + 2, True
        return left, left, p + 1, True
    x0, y0 = xs[p - 1], ys[p - 1]
    v = y0 + (x - x0) * (ys[p] - y0) / (xs[p] - x0)
    return v, v, p, False


def merge_max(a: Polyline, b: Polyline) -> Polyline:
    """The upper envelope of two polylines over the same range, linear in their points."""
    ax, ay = a
    bx, by = b
    out_x: list[float] = []
    out_y: list[float] = []
    i = j = 0
    end = ax[-1]
    xp = ar = br = 0.0
    first = True
    while True:
        x = ax[i] if ax[i] < bx[j] else bx[j]
        al, a_r, i, own_a = _limits(ax, ay, i, x)
        bl, b_r, j, own_b = _limits(bx, by, j, x)
        if not first:
            d0, d1 = ar - br, al - bl
            if (d0 < 0.0 < d1) or (d1 < 0.0 < d0):  # they cross between xp and x
                u = d0 / (d0 - d1)
                out_x.append(xp + u * (x - xp))
                out_y.append(ar + u * (al - ar))
        left = al if al > bl else bl
        right = a_r if a_r > b_r else b_r
        # A breakpoint of the lower polyline only, where the upper one goes straight through:
        # not a kink of the envelope.
        through = (al > bl and a_r > b_r and not own_a) or (bl > al and b_r > a_r and not own_b)
        if first or x == end or not through:
            out_x.append(x)
            out_y.append(left)
            if right != left:
                out_x.append(x)
                out_y.append(right)
        if x == end:
            return out_x, out_y
        first = False
        xp, ar, br = x, a_r, b_r


def merge_sum(a: Polyline, b: Polyline) -> Polyline:
    """The pointwise sum of two polylines over the same range, linear in their points."""
    ax, ay = a
    bx, by = b
    out_x: list[float] = []
    out_y: list[float] = []
    i = j = 0
    end = ax[-1]
    while True:
        x = ax[i] if ax[i] < bx[j] else bx[j]
        al, a_r, i, _ = _limits(ax, ay, i, x)
        bl, b_r, j, _ = _limits(bx, by, j, x)
        out_x.append(x)
        out_y.append(al + bl)
        if a_r + b_r != al + bl:
            out_x.append(x)
            out_y.append(a_r + b_r)
        if x == end:
            return out_x, out_y


def bound_at_one(poly: Polyline) -> Polyline:
    """``min(1, poly)``: BSUM's bound, with a point where the sum crosses 1."""
    return clip(poly, 1.0)


def merge_all(
    polys: Sequence[Polyline], merge: Callable[[Polyline, Polyline], Polyline]
) -> Polyline:
    """Merge polylines pairwise in a balanced tree: each point takes part in log2(n) merges."""
    level = list(polys)
    while len(level) > 1:
        merged = [merge(level[k], level[k + 1]) for k in range(0, len(level) - 1, 2)]
        if len(level) % 2:
            merged.append(level[-1])
        level = merged
    return level[0]


def pieces(poly: Polyline) -> list[tuple[float, float, float, float]]:
    """The polyline as straight pieces (xa, ya, xb, yb), in order (vertical ones included)."""
    xs, ys = poly
    return [(xs[i], ys[i], xs[i + 1], ys[i + 1]) for i in range(len(xs) - 1)]
