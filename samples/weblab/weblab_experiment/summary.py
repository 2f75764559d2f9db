"""From runs to results: each metric's mean and spread per (condition, profile), the paper's
Table 1 beside ours, and the claims the reproduction must hold, each checked.

Spread is the sample standard deviation over the seeds (0 for one seed). The claims are the
issue's "what counts as success": orderings across profiles for the adaptive runs, no user request
with adaptation, user requests for the LAN-tuned fixed speed on the residential link, adaptation
faster than the slow fixed speed everywhere.
"""

from __future__ import annotations

import itertools
import statistics
from collections import defaultdict
from dataclasses import dataclass
from typing import Any

from weblab_experiment.grid import Outcome

METRICS = (
    "cycles_per_s",
    "speed_mm_s",
    "time_s",
    "recoveries",
    "stripe_losses",
    "user_requests",
    "fps",
    "mm_per_cycle",
    "finished",
    "faults",
)
"""The metrics summarised, in table order (plain names, as in results.json and results.csv)."""

PAPER = {
    # Table 1 of the paper (Dell D520 notebook, 2 GB RAM): cycles/s, speed mm/s, time s,
    # recoveries, fps.
    "residential": {
        "cycles_per_s": 0.90,
        "speed_mm_s": 69,
        "time_s": 124,
        "recoveries": 4,
        "fps": 4,
    },
    "campus": {"cycles_per_s": 1.46, "speed_mm_s": 127, "time_s": 99, "recoveries": 12, "fps": 12},
    "LAN": {"cycles_per_s": 1.72, "speed_mm_s": 143, "time_s": 84, "recoveries": 8, "fps": 12},
}


@dataclass(frozen=True)
class Stat:
    mean: float
    spread: float
    n: int


@dataclass(frozen=True)
class Claim:
    text: str
    holds: bool
    detail: str


def summarise(outcomes: list[Outcome]) -> dict[str, dict[str, dict[str, Stat]]]:
    """condition -> profile -> metric -> Stat, over the runs that did not fail."""
    values: dict[tuple[str, str], dict[str, list[float]]] = defaultdict(lambda: defaultdict(list))
    for o in outcomes:
        if o.error is None:
            for metric in METRICS:
                values[o.task.condition, o.task.profile][metric].append(float(o.metrics[metric]))
    out: dict[str, dict[str, dict[str, Stat]]] = defaultdict(dict)
    for (condition, profile), by_metric in values.items():
        out[condition][profile] = {
            m: Stat(
                statistics.fmean(v),
                statistics.stdev(v) if len(v) > 1 else 0.0,
                len(v),
            )
            for m, v in by_metric.items()
        }
    return dict(out)


def claims(table: dict[str, dict[str, dict[str, Stat]]], profiles: tuple[str, ...]) -> list[Claim]:
    """The reproduction's claims, each with whether it holds in ``table`` and the figures."""
    out: list[Claim] = []
    adaptive = table.get("adaptive", {})

    def series(condition: str, metric: str) -> list[float]:
        return [table[condition][p][metric].mean for p in profiles if p in table.get(condition, {})]

    def ordered(metric: str, rising: bool) -> Claim:
        got = series("adaptive", metric)
        holds = len(got) == len(profiles) and all(
            (a < b) if rising else (a > b) for a, b in itertools.pairwise(got)
        )
        sign = " < " if rising else " > "
        return Claim(
            f"adaptive: {metric} {'rises' if rising else 'falls'} from {' to '.join(profiles)}",
            holds,
            sign.join(f"{v:.2f}" for v in got),
        )

    if len(profiles) > 1 and adaptive:
        out += [
            ordered("cycles_per_s", True),
            ordered("speed_mm_s", True),
            ordered("time_s", False),
        ]
        fps = series("adaptive", "fps")
        out.append(
            Claim(
                f"adaptive: fps is lowest on {profiles[0]}",
                bool(fps) and fps[0] < min(fps[1:], default=float("inf")),
                ", ".join(f"{v:.1f}" for v in fps),
            )
        )
    if adaptive:
        requests = {p: adaptive[p]["user_requests"] for p in adaptive}
        out.append(
            Claim(
                "adaptive: every run finishes without a user request",
                all(s.mean == 0 for s in requests.values())
                and all(adaptive[p]["finished"].mean == 1 for p in adaptive),
                ", ".join(f"{p} {s.mean:.2f}" for p, s in requests.items()),
            )
        )
    lan_tuned = table.get("fixed_lan", {}).get("residential")
    if lan_tuned:
        out.append(
            Claim(
                "fixed speed tuned for the LAN: user requests on the residential link",
                lan_tuned["user_requests"].mean > 0,
                f"{lan_tuned['user_requests'].mean:.2f} per run",
            )
        )
    slow = table.get("fixed_slow", {})
    both = [p for p in profiles if p in slow and p in adaptive]
    if both:
        out.append(
            Claim(
                "adaptation finishes faster than the slow fixed speed on every profile",
                all(adaptive[p]["time_s"].mean < slow[p]["time_s"].mean for p in both),
                ", ".join(
                    f"{p} {adaptive[p]['time_s'].mean:.0f} vs {slow[p]['time_s'].mean:.0f} s"
                    for p in both
                ),
            )
        )
    return out


def as_json(
    table: dict[str, dict[str, dict[str, Stat]]],
    outcomes: list[Outcome],
    found: list[Claim],
    meta: dict[str, Any],
) -> dict[str, Any]:
    """results.json: per condition and profile each metric's mean and spread; the claims; the
    failed runs; how the experiment ran (``meta``)."""
    return {
        "meta": meta,
        "paper_table_1": PAPER,
        "results": {
            c: {
                p: {m: {"mean": s.mean, "spread": s.spread, "n": s.n} for m, s in cell.items()}
                for p, cell in by_profile.items()
            }
            for c, by_profile in table.items()
        },
        "claims": [{"claim": c.text, "holds": c.holds, "figures": c.detail} for c in found],
        "failed_runs": [
            {
                "condition": o.task.condition,
                "profile": o.task.profile,
                "seed": o.task.seed,
                "error": o.error.strip().splitlines()[-1],
            }
            for o in outcomes
            if o.error is not None
        ],
    }


def csv_rows(table: dict[str, dict[str, dict[str, Stat]]]) -> list[list[object]]:
    """results.csv: one row per (condition, profile, metric)."""
    rows: list[list[object]] = [["condition", "profile", "metric", "mean", "spread", "n"]]
    for condition, by_profile in table.items():
        for profile, cell in by_profile.items():
            for metric in METRICS:
                s = cell[metric]
                rows.append([condition, profile, metric, f"{s.mean:.6g}", f"{s.spread:.6g}", s.n])
    return rows


def text_table(table: dict[str, dict[str, dict[str, Stat]]], profiles: tuple[str, ...]) -> str:
    """The comparison printed at the end of ``make demo``: the paper's Table 1 beside ours."""
    lines = [
        "Table 1 (paper) beside this run (adaptive: mean ± spread over the seeds)",
        f"{'access':<12} {'cycles/s':>16} {'speed mm/s':>16} {'time s':>16} "
        f"{'recoveries':>14} {'fps':>14} {'mm/cycle':>9}",
    ]
    adaptive = table.get("adaptive", {})
    for p in profiles:
        paper = PAPER.get(p, {})
        cell = adaptive.get(p)
        if cell is None:
            continue

        def both(metric: str, digits: int, cell=cell, paper=paper) -> str:
            ours = cell[metric]
            theirs = paper.get(metric)
            shown = f"{ours.mean:.{digits}f}±{ours.spread:.{digits}f}"
            return f"{theirs:g} | {shown}" if theirs is not None else shown

        lines.append(
            f"{p:<12} {both('cycles_per_s', 2):>16} {both('speed_mm_s', 0):>16} "
            f"{both('time_s', 0):>16} {both('recoveries', 1):>14} {both('fps', 1):>14} "
            f"{cell['mm_per_cycle'].mean:>9.0f}"
        )
    lines.append("")
    lines.append(
        f"{'condition':<20} {'profile':<12} {'cycles/s':>9} {'speed':>7} {'time s':>7} "
        f"{'recov':>6} {'losses':>7} {'user req':>9} {'fps':>6} {'faults':>7} {'runs':>5}"
    )
    for condition, by_profile in table.items():
        for p in profiles:
            cell = by_profile.get(p)
            if cell is None:
                continue
            lines.append(
                f"{condition:<20} {p:<12} {cell['cycles_per_s'].mean:>9.2f} "
                f"{cell['speed_mm_s'].mean:>7.1f} {cell['time_s'].mean:>7.1f} "
                f"{cell['recoveries'].mean:>6.2f} {cell['stripe_losses'].mean:>7.2f} "
                f"{cell['user_requests'].mean:>9.2f} {cell['fps'].mean:>6.1f} "
                f"{cell['faults'].mean:>7.2f} {cell['time_s'].n:>5}"
            )
    return "\n".join(lines)
