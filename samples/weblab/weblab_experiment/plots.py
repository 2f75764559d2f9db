"""The experiment's figures (matplotlib, no display), each as PNG (for the page), SVG and PDF (for a
paper), one set per path: the stripe and the robot's trajectories per profile, the speed and the
speed limit over time, the panoramic frame rate over time, the time to the finish line per
condition (mean with its 95% t interval), and the fixed-speed sweep against adaptation.

Panels of one figure share their axes; legends sit outside the data; every axis says its unit;
every figure says which statistic it shows and over how many runs."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display on a server or in CI

import matplotlib.pyplot as plt
from weblab_sim.experiment import fixed_speed

from weblab_experiment.grid import Outcome
from weblab_experiment.summary import FAMILIES, Table, fixed_conditions

FORMATS = ("png", "svg", "pdf")
COLOURS = {
    "adaptive": "#1f77b4",
    "fixed_50": "#7f7f7f",
    "fixed_150": "#d62728",
    "no_speed_policy": "#9467bd",
    "no_recovery_policy": "#8c564b",
    "no_bandwidth_policy": "#ff7f0e",
}
PROFILE_COLOURS = {"residential": "#d62728", "campus": "#ff7f0e", "LAN": "#2ca02c"}
TRAJECTORIES = ("fixed_50", "fixed_150", "adaptive")
SWEEP_COLOURS = {  # family -> (no run needed the user, some did)
    "fixed_": ("#444444", "#d62728"),
    "no_speed_policy_": ("#2ca02c", "#9467bd"),
}


def label(condition: str) -> str:
    """A condition as a legend shows it: fixed speeds with their unit."""
    speed = fixed_speed(condition)
    if speed is None:
        return condition
    return f"fixed {speed:g} mm/s" + ("" if condition.startswith("fixed_") else ", recovering")


def _series(outcomes: list[Outcome], path: str) -> dict[tuple[str, str], tuple[int, dict]]:
    return {
        (o.task.condition, o.task.profile): (o.task.seed, o.metrics["series"])
        for o in outcomes
        if o.error is None and o.task.path == path and "series" in o.metrics
    }


def trajectories(outcomes: list[Outcome], path: str, profiles: tuple[str, ...], out: Path) -> Path:
    from weblab_sim.floor import HEIGHT_MM, WIDTH_MM, make_path

    stripe = make_path(path).points
    series = _series(outcomes, path)
    fig, axes = plt.subplots(
        1,
        len(profiles),
        figsize=(4.6 * len(profiles), 4.2),
        sharex=True,
        sharey=True,
        squeeze=False,
        layout="constrained",
    )
    seeds = set()
    for ax, profile in zip(axes[0], profiles, strict=True):
        ax.plot(*stripe.T, color="#f0a040", linewidth=6, alpha=0.6, label="stripe")
        ax.plot(*stripe[-1], marker="s", color="green", markersize=7, linestyle="", label="finish")
        for condition in TRAJECTORIES:
            if (condition, profile) not in series:
                continue
            seed, s = series[condition, profile]
            seeds.add(seed)
            xs = [p[1] for p in s["trajectory"]]
            ys = [p[2] for p in s["trajectory"]]
            ax.plot(xs, ys, color=COLOURS[condition], linewidth=1.1, label=label(condition))
        ax.set_xlim(0, WIDTH_MM)
        ax.set_ylim(0, HEIGHT_MM)
        ax.set_aspect("equal")
        ax.set_title(profile, fontsize=10)
        ax.set_xlabel("x (mm)")
    axes[0, 0].set_ylabel("y (mm)")
    _legend_below(fig)
    seed = f"seed {min(seeds)}" if len(seeds) == 1 else "first seed of each cell"
    fig.suptitle(f"Path {path}: the stripe and one run's trajectory per condition ({seed})")
    return _save(fig, out / f"trajectories-{path}")


def speed_over_time(
    outcomes: list[Outcome], path: str, profiles: tuple[str, ...], out: Path
) -> Path:
    series = _series(outcomes, path)
    fig, axes = plt.subplots(
        len(profiles),
        1,
        figsize=(10, 2.3 * len(profiles) + 0.8),
        sharex=True,
        sharey=True,
        squeeze=False,
        layout="constrained",
    )
    for ax, profile in zip(axes[:, 0], profiles, strict=True):
        if ("adaptive", profile) in series:
            _, s = series["adaptive", profile]
            ax.plot(
                *zip(*s["speed"], strict=True),
                color="#1f77b4",
                linewidth=0.8,
                label="speed commanded (capped by the limit; below 0: a recovery backing up)",
            )
            ax.step(
                *zip(*s["max_speed"], strict=True),
                where="post",
                color="#d62728",
                linewidth=1.2,
                label="speed limit set by SpeedLimiting",
            )
        ax.set_title(profile, fontsize=10, loc="left")
        ax.set_ylabel("speed (mm/s)")
    axes[-1, 0].set_xlabel("simulated time (s)")
    _legend_below(fig, columns=2)
    fig.suptitle(f"Path {path}, adaptive: the speed and its limit over one run")
    return _save(fig, out / f"speed-{path}")


def fps_over_time(outcomes: list[Outcome], path: str, profiles: tuple[str, ...], out: Path) -> Path:
    series = _series(outcomes, path)
    fig, ax = plt.subplots(figsize=(10, 3.4), layout="constrained")
    for profile in profiles:
        if ("adaptive", profile) in series:
            _, s = series["adaptive", profile]
            ax.step(
                *zip(*s["fps"], strict=True),
                where="post",
                color=PROFILE_COLOURS.get(profile, "#333333"),
                label=profile,
            )
    ax.set_xlabel("simulated time (s)")
    ax.set_ylabel("frame rate (frames/s)")
    ax.set_ylim(bottom=0)
    _legend_right(fig)
    fig.suptitle(
        f"Path {path}, adaptive: the panoramic camera's frame rate set by BandwidthLimiting"
    )
    return _save(fig, out / f"fps-{path}")


def time_by_condition(table: Table, path: str, profiles: tuple[str, ...], out: Path) -> Path:
    by_condition = table[path]
    conditions = [c for c in by_condition if fixed_speed(c) is None or c in COLOURS]
    fig, ax = plt.subplots(figsize=(10, 3.8), layout="constrained")
    width = 0.8 / max(len(conditions), 1)
    n = set()
    for i, condition in enumerate(conditions):
        cells = [by_condition[condition].get(p) for p in profiles]
        xs = [j + i * width for j in range(len(profiles))]
        stats = [c["time_s"] if c else None for c in cells]
        n |= {s.n for s in stats if s}
        ax.bar(
            xs,
            [s.mean if s else 0 for s in stats],
            width,
            yerr=[(s.half_width() or 0) if s else 0 for s in stats],
            color=COLOURS.get(condition, "#333333"),
            label=label(condition),
            capsize=2,
        )
    ax.set_xticks([j + 0.4 - width / 2 for j in range(len(profiles))], profiles)
    ax.set_xlabel("access network")
    ax.set_ylabel("time to the finish line (s)")
    _legend_right(fig)
    runs = ", ".join(str(k) for k in sorted(n))
    fig.suptitle(
        f"Path {path}: time to the finish line, mean and 95% t interval (n = {runs} runs per bar)"
    )
    return _save(fig, out / f"time-{path}")


def sweep(table: Table, path: str, profiles: tuple[str, ...], out: Path) -> Path | None:
    by_condition = table[path]
    fixed = fixed_conditions(by_condition)
    adaptive = by_condition.get("adaptive", {})
    if len(fixed) < 2:
        return None
    fig, axes = plt.subplots(
        1,
        len(profiles),
        figsize=(4.4 * len(profiles), 3.8),
        sharex=True,
        sharey=True,
        squeeze=False,
        layout="constrained",
    )
    n = set()
    for ax, profile in zip(axes[0], profiles, strict=True):
        if profile in adaptive:
            a = adaptive[profile]["time_s"]
            half = a.half_width() or 0.0
            ax.axhspan(
                a.mean - half,
                a.mean + half,
                color=COLOURS["adaptive"],
                alpha=0.15,
                label="adaptive: 95% t interval",
            )
            ax.axhline(a.mean, color=COLOURS["adaptive"], linewidth=1.2, label="adaptive: mean")
            n.add(a.n)
        for prefix, what in FAMILIES.items():
            cells = [
                (fixed_speed(c), by_condition[c][profile])
                for c in fixed_conditions(by_condition, prefix)
                if profile in by_condition[c]
            ]
            for needs_user, style in ((False, "o"), (True, "x")):
                chosen = [(v, c) for v, c in cells if (c["user_requests"].mean > 0) == needs_user]
                if not chosen:
                    continue
                ax.errorbar(
                    [v for v, _ in chosen],
                    [c["time_s"].mean for _, c in chosen],
                    yerr=[c["time_s"].half_width() or 0 for _, c in chosen],
                    fmt=style,
                    color=SWEEP_COLOURS[prefix][needs_user],
                    capsize=3,
                    label=f"fixed speed, {what.split(',')[0]}"
                    + (": some runs needed the user" if needs_user else ": no run needed the user"),
                )
                n |= {c["time_s"].n for _, c in chosen}
        ax.set_title(profile, fontsize=10)
        ax.set_xlabel("fixed speed asked for (mm/s)")
    axes[0, 0].set_ylabel("time to the finish line (s)")
    _legend_below(fig, columns=2)
    runs = ", ".join(str(k) for k in sorted(n))
    fig.suptitle(f"Path {path}: fixed speeds against adaptation (n = {runs} runs per point)")
    return _save(fig, out / f"sweep-{path}")


def _legend_below(fig: Any, columns: int = 6) -> None:
    handles, labels = _unique(fig)
    fig.legend(
        handles,
        labels,
        loc="outside lower center",
        ncols=min(columns, len(labels)),
        fontsize=8,
        frameon=False,
    )


def _legend_right(fig: Any) -> None:
    handles, labels = _unique(fig)
    fig.legend(handles, labels, loc="outside right center", fontsize=8, frameon=False)


def _unique(fig: Any) -> tuple[list, list]:
    seen: dict[str, Any] = {}
    for ax in fig.axes:
        for handle, text in zip(*ax.get_legend_handles_labels(), strict=True):
            seen.setdefault(text, handle)
    return list(seen.values()), list(seen)


def _save(fig: Any, stem: Path) -> Path:
    for fmt in FORMATS:
        fig.savefig(stem.with_suffix(f".{fmt}"), dpi=110)
    plt.close(fig)
    return stem.with_suffix(".png")


def all_plots(
    outcomes: list[Outcome], table: Table, profiles: tuple[str, ...], out: Path
) -> list[Path]:
    """Every figure of every path, as PNG paths (an SVG and a PDF beside each)."""
    out.mkdir(parents=True, exist_ok=True)
    made = []
    for path in table:
        made += [
            trajectories(outcomes, path, profiles, out),
            speed_over_time(outcomes, path, profiles, out),
            fps_over_time(outcomes, path, profiles, out),
            time_by_condition(table, path, profiles, out),
        ]
        swept = sweep(table, path, profiles, out)
        if swept is not None:
            made.append(swept)
    return made
