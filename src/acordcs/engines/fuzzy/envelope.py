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

The result goes to :func:`acordcs.engines.fuzzy.defuzz.apply_method` as straight pieces. This is
the path of outputs whose terms overlap deeply (see ``DEEP`` in ``defuzz``): cutting such an output
into intervals between all breakpoints costs n lines per interval and every crossing of every pair
of lines on every firing (250 overlapping terms took seconds per firing).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from acordcs.engines.fuzzy.membership import Membership

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
    push_x, push_y = out_x.append, out_y.append
    rounded = False
    for i in range(1, len(xs)):
        x0, y0, x1, y1 = xs[i - 1], ys[i - 1], xs[i], ys[i]
        if (y0 - level) * (y1 - level) < 0.0 and x1 > x0:
            xc = x0 + (level - y0) / (y1 - y0) * (x1 - x0)
            # Rounding can put a crossing on an end (a level of 1e-28 on a steep edge): the point
            # then sits at that end's x and the piece stays flat at the level, as it should.
            if not x0 < xc < x1:
                xc = x1 if xc >= x1 else x0
                rounded = True
            push_x(xc)
            push_y(level)
        push_x(x1)
        push_y(y1 if y1 < level else level)
    return _tidy(out_x, out_y) if rounded else (out_x, out_y)


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


def merge_max(a: Polyline, b: Polyline) -> Polyline:
    """The upper envelope of two polylines over the same range, linear in their points.

    The walk visits the union of their breakpoints; at each one it takes both polylines' left and
    right values (their own points there, or their line through it). The hot loop of the deep
    path: written out flat, without helper calls."""
    ax, ay = a
    bx, by = b
    na, nb = len(ax), len(bx)
    out_x: list[float] = []
    out_y: list[float] = []
    push_x, push_y = out_x.append, out_y.append
    i = j = 0
    end = ax[-1]
    xp = ar = br = 0.0
    first = True
    while True:
        xa, xb = ax[i], bx[j]
        x = xa if xa < xb else xb
        if xa == x:  # a breakpoint of a: its value from the left, then to the right
            al = a_r = ay[i]
            i += 1
            if i < na and ax[i] == x:
                a_r = ay[i]
                i += 1
            own_a = True
        else:  # a goes straight through x
            x0, y0 = ax[i - 1], ay[i - 1]
            al = a_r = y0 + (x - x0) * (ay[i] - y0) / (xa - x0)
            own_a = False
        if xb == x:
            bl = b_r = by[j]
            j += 1
            if j < nb and bx[j] == x:
                b_r = by[j]
                j += 1
            own_b = True
        else:
            x0, y0 = bx[j - 1], by[j - 1]
            bl = b_r = y0 + (x - x0) * (by[j] - y0) / (xb - x0)
            own_b = False
        if not first:
            d0, d1 = ar - br, al - bl
            if (d0 < 0.0 < d1) or (d1 < 0.0 < d0):  # they cross between xp and x
                u = d0 / (d0 - d1)
                push_x(xp + u * (x - xp))
                push_y(ar + u * (al - ar))
        # A breakpoint of the lower polyline only, where the upper one goes straight through:
        # not a kink of the envelope.
        if (
            first
            or x == end
            or not ((al > bl and a_r > b_r and not own_a) or (bl > al and b_r > a_r and not own_b))
        ):
            left = al if al > bl else bl
            right = a_r if a_r > b_r else b_r
            push_x(x)
            push_y(left)
            if right != left:
                push_x(x)
                push_y(right)
        if x == end:
            return out_x, out_y
        first = False
        xp, ar, br = x, a_r, b_r


def merge_sum(a: Polyline, b: Polyline) -> Polyline:
    """The pointwise sum of two polylines over the same range, linear in their points."""
    ax, ay = a
    bx, by = b
    na, nb = len(ax), len(bx)
    out_x: list[float] = []
    out_y: list[float] = []
    i = j = 0
    end = ax[-1]
    while True:
        xa, xb = ax[i], bx[j]
        x = xa if xa < xb else xb
        if xa == x:
            al = a_r = ay[i]
            i += 1
            if i < na and ax[i] == x:
                a_r = ay[i]
                i += 1
        else:
            x0, y0 = ax[i - 1], ay[i - 1]
            al = a_r = y0 + (x - x0) * (ay[i] - y0) / (xa - x0)
        if xb == x:
            bl = b_r = by[j]
            j += 1
            if j < nb and bx[j] == x:
                b_r = by[j]
                j += 1
        else:
            x0, y0 = bx[j - 1], by[j - 1]
            bl = b_r = y0 + (x - x0) * (by[j] - y0) / (xb - x0)
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
