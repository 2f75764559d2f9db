"""Membership functions of linguistic terms: validation, evaluation (scalar, numpy, generated code).

Shapes and parameters follow FCL order (``acordcs.rules.parser.TermDef``): ``triangle a b c``,
``trapezoid a b c d``, ``gaussian mean sigma``, ``bell a b mean``, ``sigmoid gain center``,
``points x1 y1 x2 y2 ...`` and ``singleton x``.

Triangles, trapezoids and point lists are piecewise linear (``pwl``); the engine integrates them in
closed form. Defined behaviour at the edges:

- a vertical edge (``trape 0 0 20 50``, or two points with the same x) belongs to the set: the
  membership AT that x is the larger of the two values, so a left shoulder is 1 at its corner;
- a triangle or trapezoid is 0 outside ``[a, d]``; a point list keeps its first and last y beyond
  its ends (jFuzzyLogic's behaviour).

Inverted points (``trian 50 20 80``) or a zero-width shape (``trian 5 5 5``) raise :class:`RuleError`.
"""

from __future__ import annotations

import math
from bisect import bisect_left, bisect_right
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from acordcs import vocabularies
from acordcs.engines.rule_engine import RuleError
from acordcs.rules.tree import MAX_POINTS

SHAPES = vocabularies.SHAPES  # the metamodel's MembershipShape
_ARITY = {"triangle": 3, "trapezoid": 4, "gaussian": 2, "bell": 3, "sigmoid": 2, "singleton": 1}
_EXP_LIMIT = 700.0  # math.exp overflows past ~709: a sigmoid that far out is exactly 0 or 1


def fmt_number(value: float) -> str:
    """Shortest text that reads back as the same float (``20`` rather than ``20.0``)."""
    text = repr(float(value))
    return text[:-2] if text.endswith(".0") else text


@dataclass(frozen=True, slots=True)
class Membership:
    """One validated membership function. Build it with :func:`make_membership`."""

    shape: str
    params: tuple[float, ...]
    # Piecewise-linear form (empty for gaussian, bell, sigmoid, singleton): breakpoints and the
    # values taken left of the first and right of the last breakpoint.
    xs: tuple[float, ...] = ()
    ys: tuple[float, ...] = ()
    left: float = 0.0
    right: float = 0.0
    # A FUNCTION term (jFuzzyLogic's): a singleton at the value of this expression of the inputs
    # (an acordcs.engines.fuzzy.fcl_function.Expression), computed at every firing.
    expr: object = None

    @property
    def linear(self) -> bool:
        """True for triangles, trapezoids and point lists (exact centroid in closed form)."""
        return bool(self.xs)

    @property
    def singleton(self) -> bool:
        """A single point: a number, or a FUNCTION term (its point computed when firing)."""
        return self.shape in ("singleton", "function")

    # ------------------------------------------------------------------------------ evaluation
    def __call__(self, x: float) -> float:
        shape, p = self.shape, self.params
        if shape == "function":
            raise RuleError("a FUNCTION term is an output's point: it has no degree to test")
        if self.xs:
            return _pwl_at(self.xs, self.ys, self.left, self.right, x)
        if shape == "gaussian":
            t = (x - p[0]) / p[1]
            return math.exp(-0.5 * t * t)
        if shape == "bell":
            return 1.0 / (1.0 + abs((x - p[2]) / p[0]) ** (2.0 * p[1]))
        if shape == "sigmoid":
            z = -p[0] * (x - p[1])
            return 0.0 if z > _EXP_LIMIT else 1.0 / (1.0 + math.exp(z))
        return 1.0 if x == p[0] else 0.0

    def evaluate(self, x: np.ndarray) -> np.ndarray:
        """Vectorised membership; equal to calling the function on each element."""
        x = np.asarray(x, dtype=float)
        shape, p = self.shape, self.params
        if self.xs:
            xs = np.asarray(self.xs)
            out = np.interp(x, xs, np.asarray(self.ys), left=self.left, right=self.right)
            for v in _vertical_xs(self.xs):
                out = np.where(
                    x == v, max(y for xx, y in zip(self.xs, self.ys, strict=False) if xx == v), out
                )
            return out
        if shape == "gaussian":
            t = (x - p[0]) / p[1]
            return np.exp(-0.5 * t * t)
        if shape == "bell":
            return 1.0 / (1.0 + np.abs((x - p[2]) / p[0]) ** (2.0 * p[1]))
        if shape == "sigmoid":
            z = -p[0] * (x - p[1])
            return np.where(z > _EXP_LIMIT, 0.0, 1.0 / (1.0 + np.exp(np.minimum(z, _EXP_LIMIT))))
        if shape == "function":
            return np.zeros_like(x)  # no width (see OutputShape)
        return np.where(x == p[0], 1.0, 0.0)

    def code(self, x: str, out: str) -> list[str]:
        """Python statements computing ``out`` from local ``x``: the rule set's generated code
        inlines memberships because a function call per term costs as much as the arithmetic."""
        shape, p = self.shape, self.params
        f = _lit
        if self.xs:
            return _pwl_code(self.xs, self.ys, self.left, self.right, x, out)
        if shape == "gaussian":
            return [f"{out} = _exp(-0.5 * (({x} - {f(p[0])}) / {f(p[1])}) ** 2)"]
        if shape == "bell":
            return [f"{out} = 1.0 / (1.0 + abs(({x} - {f(p[2])}) / {f(p[0])}) ** {f(2.0 * p[1])})"]
        if shape == "sigmoid":
            return [
                f"{out} = -{f(p[0])} * ({x} - {f(p[1])})",
                f"{out} = 0.0 if {out} > {_EXP_LIMIT} else 1.0 / (1.0 + _exp({out}))",
            ]
        return [f"{out} = 1.0 if {x} == {f(p[0])} else 0.0"]

    # ------------------------------------------------------------------------------ geometry
    def limits(self, u: float) -> tuple[float, float]:
        """(left limit, right limit) of a piecewise-linear membership at ``u``."""
        xs, ys = self.xs, self.ys
        if u < xs[0]:
            lo = hi = self.left
            return lo, hi
        if u > xs[-1]:
            return self.right, self.right
        i = bisect_left(xs, u)
        left = self.left if i == 0 else (ys[i] if xs[i] == u else _lerp(xs, ys, i - 1, u))
        j = bisect_right(xs, u) - 1
        right = self.right if j == len(xs) - 1 else (ys[j] if xs[j] == u else _lerp(xs, ys, j, u))
        return left, right

    def extent(self) -> tuple[float, float]:
        """Where the function is non-negligible: for estimating a universe FCL leaves out."""
        p = self.params
        if self.xs:
            return self.xs[0], self.xs[-1]
        if self.shape == "gaussian":
            return p[0] - 4.0 * p[1], p[0] + 4.0 * p[1]
        if self.shape == "bell":
            return p[2] - 4.0 * p[0], p[2] + 4.0 * p[0]
        if self.shape == "sigmoid":
            return p[1] - 8.0 / abs(p[0]), p[1] + 8.0 / abs(p[0])
        if self.shape == "function":
            return math.nan, math.nan  # known only when firing
        return p[0], p[0]

    def fcl(self) -> str:
        """The FCL text of this membership function (``trian 0 5 10``, ``(0, 1) (4, 0)``)."""
        f = fmt_number
        p = self.params
        if self.shape == "points":
            return " ".join(f"({f(p[i])}, {f(p[i + 1])})" for i in range(0, len(p), 2))
        if self.shape == "singleton":
            return f(p[0])
        if self.shape == "function":
            return f"FUNCTION {self.expr.text}"  # type: ignore[attr-defined]
        keyword = {"triangle": "trian", "trapezoid": "trape", "gaussian": "gauss", "bell": "gbell"}
        return " ".join([keyword.get(self.shape, "sigm"), *(f(v) for v in p)])


def _lit(value: float) -> str:
    """A float literal for generated code (always a float, so results stay floats)."""
    return repr(float(value))


def _lerp(xs: tuple[float, ...], ys: tuple[float, ...], i: int, u: float) -> float:
    return ys[i] + (u - xs[i]) * (ys[i + 1] - ys[i]) / (xs[i + 1] - xs[i])


def _vertical_xs(xs: tuple[float, ...]) -> list[float]:
    return sorted({xs[i] for i in range(len(xs) - 1) if xs[i] == xs[i + 1]})


def _pwl_at(xs, ys, left: float, right: float, x: float) -> float:
    if x < xs[0]:
        return left
    if x > xs[-1]:
        return right
    best = 0.0 if len(xs) > 1 else ys[0]
    for i in range(len(xs) - 1):
        x0, x1 = xs[i], xs[i + 1]
        if x0 <= x <= x1:
            v = (
                max(ys[i], ys[i + 1])
                if x0 == x1
                else ys[i] + (x - x0) * (ys[i + 1] - ys[i]) / (x1 - x0)
            )
            best = v if v > best else best
    return best


def _pwl_code(xs, ys, left: float, right: float, x: str, out: str) -> list[str]:
    f = _lit
    lines = [
        f"if {x} < {f(xs[0])}: {out} = {f(left)}",
        f"elif {x} > {f(xs[-1])}: {out} = {f(right)}",
    ]
    for v in _vertical_xs(xs):
        top = max(y for xx, y in zip(xs, ys, strict=False) if xx == v)
        lines.append(f"elif {x} == {f(v)}: {out} = {f(top)}")
    for i in range(len(xs) - 1):
        x0, x1, y0, y1 = xs[i], xs[i + 1], ys[i], ys[i + 1]
        if x0 == x1:
            continue
        slope = (y1 - y0) / (x1 - x0)
        expr = f(y0) if slope == 0.0 else f"{f(y0)} + ({x} - {f(x0)}) * {f(slope)}"
        lines.append(f"elif {x} <= {f(x1)}: {out} = {expr}")
    lines.append(f"else: {out} = {f(right)}")
    return lines


# ---------------------------------------------------------------------------------- building
def make_membership(shape: str, params: Iterable[float], *, where: str = "term") -> Membership:
    """Validate ``params`` for ``shape`` and build the function; errors say what to write instead.

    ``where`` names the term in messages, e.g. ``"term 'fast' of variable 'speed'"``.
    """
    shape = {
        "trape": "trapezoid",
        "trian": "triangle",
        "gauss": "gaussian",
        "gbell": "bell",
        "sigm": "sigmoid",
    }.get(shape, shape)
    if shape not in SHAPES:
        raise RuleError(
            f"{where}: unknown membership shape {shape!r}; use one of {', '.join(SHAPES)}"
        )
    try:
        p = tuple(float(v) for v in params)
    except (TypeError, ValueError):
        raise RuleError(f"{where}: parameters must be numbers, got {params!r}") from None
    if not all(math.isfinite(v) for v in p):
        raise RuleError(f"{where}: parameters must be finite numbers, got {' '.join(map(str, p))}")
    want = _ARITY.get(shape)
    if want is not None and len(p) != want:
        raise RuleError(f"{where}: a {shape} takes {want} parameters, got {len(p)}")
    shown = " ".join(fmt_number(v) for v in p)
    if shape in ("triangle", "trapezoid"):
        if any(p[i] > p[i + 1] for i in range(len(p) - 1)):
            raise RuleError(
                f"{where}: {shape} points {shown} are inverted; "
                f"write them in non-decreasing order (left foot, {'peak' if len(p) == 3 else 'shoulders'}, right foot)"
            )
        if p[0] == p[-1]:
            raise RuleError(
                f"{where}: {shape} {shown} has zero width; use a singleton for a single point"
            )
        ys = (0.0, 1.0, 0.0) if shape == "triangle" else (0.0, 1.0, 1.0, 0.0)
        return Membership(shape, p, p, ys, 0.0, 0.0)
    if shape == "points":
        return _points(p, where, shown)
    if shape == "gaussian" and p[1] <= 0.0:
        raise RuleError(f"{where}: gaussian sigma must be > 0 (got {fmt_number(p[1])})")
    if shape == "bell" and (p[0] <= 0.0 or p[1] <= 0.0):
        raise RuleError(f"{where}: bell width a and slope b must be > 0 (got gbell {shown})")
    if shape == "sigmoid" and p[0] == 0.0:
        raise RuleError(f"{where}: sigmoid gain must not be 0 (a flat 0.5 says nothing)")
    return Membership(shape, p)


def function_membership(expr: object) -> Membership:
    """A FUNCTION term: a singleton at ``expr``'s value (an ``fcl_function.Expression``)."""
    return Membership("function", (), expr=expr)


def _points(p: tuple[float, ...], where: str, shown: str) -> Membership:
    if len(p) % 2 or len(p) < 4:
        raise RuleError(
            f"{where}: a point list needs at least two (x, y) points, got {shown or 'none'}"
        )
    xs, ys = p[0::2], p[1::2]
    if len(xs) > MAX_POINTS:
        raise RuleError(
            f"{where}: a point list of {len(xs):,} points; the fuzzy engine takes at most "
            f"{MAX_POINTS} per term (its generated code has a branch per point); simplify the shape"
        )
    for i in range(len(xs) - 1):
        if xs[i] > xs[i + 1]:
            raise RuleError(
                f"{where}: point x values must not decrease ({fmt_number(xs[i])} then "
                f"{fmt_number(xs[i + 1])}); list points from left to right"
            )
        if i + 2 < len(xs) and xs[i] == xs[i + 2]:
            raise RuleError(
                f"{where}: three points share x = {fmt_number(xs[i])}; a vertical edge has two"
            )
    if xs[0] == xs[-1]:
        raise RuleError(f"{where}: point list has zero width; use a singleton for a single point")
    for y in ys:
        if not 0.0 <= y <= 1.0:
            raise RuleError(f"{where}: membership values must be within 0..1, got {fmt_number(y)}")
    return Membership("points", p, xs, ys, ys[0], ys[-1])
