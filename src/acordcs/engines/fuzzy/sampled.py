"""Discrete defuzzification over evenly spaced samples of an output's range.

Two uses: the paper's engine (``Semantics.samples``, e.g. 100: plain sums of y*mu over mu, as
Sazonov's engine does), and the fallback for sets that are not piecewise linear (gaussian, bell or
sigmoid output terms, PROBOR accumulation): :data:`FALLBACK_SAMPLES` points with trapezoid weights.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from acordcs.engines.fuzzy.semantics import SUMS, Semantics, collapses

FALLBACK_SAMPLES = 2001
ArrayOrFloat = np.ndarray | float


class Sampled:
    """Discrete defuzzification over evenly spaced samples of the range (see module doc)."""

    kind = "sampled"

    def __init__(self, shape, sem: Semantics, method: str) -> None:
        n = sem.samples or FALLBACK_SAMPLES
        self.grid = np.linspace(shape.lo, shape.hi, n)
        self.weights = np.ones(n)
        if not sem.samples:
            self.weights[0] = self.weights[-1] = 0.5
        # a singleton beside shaped terms has no width: a row of zeros (see OutputShape)
        rows = [
            np.zeros(n) if shape.mixed and t.singleton else t.evaluate(self.grid)
            for t in shape.terms
        ]
        self.table = np.array(rows).reshape(len(shape.terms), n)
        self.act, self.accu, self.method = sem.act, sem.accu, method
        self.collapsed = collapses(sem, False)

    def mu(self, data: Iterable[float] | Iterable[tuple[int, float]]) -> np.ndarray | None:
        """The aggregated set on the grid (None when nothing is active)."""
        items = list(enumerate(data)) if self.collapsed else list(data)
        items = [(k, lev) for k, lev in items if lev > 0.0]
        if not items:
            return None
        if self.collapsed and self.act == "PROD" and self.accu in SUMS:
            ks = [k for k, _ in items]
            return np.asarray([lev for _, lev in items]) @ self.table[ks]
        acc = None
        for k, lev in items:
            row = np.minimum(lev, self.table[k]) if self.act == "MIN" else lev * self.table[k]
            acc = row if acc is None else accumulate(self.accu, acc, row)
        return acc

    def __call__(self, data) -> float | None:
        mu = self.mu(data)
        return None if mu is None else sampled_method(self.grid, self.weights, mu, self.method)


def accumulate(accu: str, acc: ArrayOrFloat, row: ArrayOrFloat) -> ArrayOrFloat:
    """Fold one activated set into the accumulated one (numpy arrays or floats)."""
    if accu == "MAX":
        return np.maximum(acc, row)
    if accu == "BSUM":
        return np.minimum(acc + row, 1.0)
    if accu == "PROBOR":
        return acc + row - acc * row
    return acc + row


def sampled_method(
    grid: np.ndarray, weights: np.ndarray, mu: np.ndarray, method: str
) -> float | None:
    wm = weights * mu
    total = float(wm.sum())
    if total <= 0.0:
        return None
    if method == "COG":
        return float(wm @ grid) / total
    if method == "COA":
        cum = np.concatenate(([0.0], np.cumsum((mu[1:] + mu[:-1]) * 0.5 * np.diff(grid))))
        half = cum[-1] * 0.5
        i = int(np.searchsorted(cum, half))
        if i == 0:
            return float(grid[0])
        span = cum[i] - cum[i - 1]
        frac = (half - cum[i - 1]) / span if span > 0 else 0.0
        return float(grid[i - 1] + frac * (grid[i] - grid[i - 1]))
    top = float(mu.max())
    at = grid[mu >= top - 1e-12 * top]
    if method == "LM":
        return float(at[0])
    if method == "RM":
        return float(at[-1])
    return float(at.mean())
