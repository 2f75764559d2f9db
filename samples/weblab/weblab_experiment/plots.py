"""The experiment's figures, as PNG files (matplotlib, no display): the stripe and the robot's
trajectories per profile, the speed and the speed limit over time, the panoramic frame rate over
time, and the time to the finish line per condition with its spread."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")  # files only: no display on a server or in CI

import matplotlib.pyplot as plt

from weblab_experiment.grid import Outcome
from weblab_experiment.summary import Stat

COLOURS = {
    "adaptive": "#1f77b4",
    "fixed_slow": "#7f7f7f",
    "fixed_lan": "#d62728",
    "no_speed_policy": "#9467bd",
    "no_recovery_policy": "#8c564b",
    "no_bandwidth_policy": "#ff7f0e",
}


def _series(outcomes: list[Outcome]) -> dict[tuple[str, str], dict[str, Any]]:
    return {
        (o.task.condition, o.task.profile): o.metrics["series"]
        for o in outcomes
        if o.error is None and "series" in o.metrics
    }


def trajectories(outcomes: list[Outcome], profiles: tuple[str, ...], out: Path) -> Path:
    from weblab_sim.floor import HEIGHT_MM, WIDTH_MM, make_path

    stripe = make_path().points
    series = _series(outcomes)
    fig, axes = plt.subplots(1, len(profiles), figsize=(5.2 * len(profiles), 4.4), squeeze=False)
    for ax, profile in zip(axes[0], profiles, strict=True):
        ax.plot(stripe[:, 0], stripe[:, 1], color="#f0a040", linewidth=6, alpha=0.6, label="stripe")
        for condition in ("fixed_slow", "fixed_lan", "adaptive"):
            s = series.get((condition, profile))
            if not s:
                continue
            xs = [p[1] for p in s["trajectory"]]
            ys = [p[2] for p in s["trajectory"]]
            ax.plot(xs, ys, color=COLOURS[condition], linewidth=1.2, label=condition)
        ax.plot(*stripe[-1], marker="s", color="green", markersize=8)
        ax.set_xlim(0, WIDTH_MM)
        ax.set_ylim(0, HEIGHT_MM)
        ax.set_aspect("equal")
        ax.set_title(f"{profile}: path (seed of the first run)")
        ax.set_xlabel("x, mm")
        ax.set_ylabel("y, mm")
        ax.legend(loc="lower right", fontsize=8)
    return _save(fig, out / "trajectories.png")


def speed_over_time(outcomes: list[Outcome], profiles: tuple[str, ...], out: Path) -> Path:
    series = _series(outcomes)
    fig, axes = plt.subplots(len(profiles), 1, figsize=(10, 2.4 * len(profiles)), squeeze=False)
    for ax, profile in zip(axes[:, 0], profiles, strict=True):
        s = series.get(("adaptive", profile))
        if s:
            ax.plot(*zip(*s["speed"], strict=True), color="#1f77b4", linewidth=0.8, label="speed")
            ax.step(
                *zip(*s["max_speed"], strict=True),
                where="post",
                color="#d62728",
                linewidth=1.2,
                label="speed limit (SpeedLimiting)",
            )
        ax.set_title(f"{profile}, adaptive: speed over time", fontsize=10)
        ax.set_ylabel("mm/s")
        ax.legend(loc="upper right", fontsize=8)
    axes[-1, 0].set_xlabel("simulated time, s")
    return _save(fig, out / "speed.png")


def fps_over_time(outcomes: list[Outcome], profiles: tuple[str, ...], out: Path) -> Path:
    series = _series(outcomes)
    fig, ax = plt.subplots(figsize=(10, 3.4))
    for profile, colour in zip(profiles, ("#d62728", "#ff7f0e", "#2ca02c"), strict=False):
        s = series.get(("adaptive", profile))
        if s:
            ax.step(*zip(*s["fps"], strict=True), where="post", color=colour, label=profile)
    ax.set_title("Panoramic camera frame rate set by BandwidthLimiting (adaptive)", fontsize=10)
    ax.set_xlabel("simulated time, s")
    ax.set_ylabel("fps")
    ax.legend(fontsize=8)
    return _save(fig, out / "fps.png")


def time_by_condition(
    table: dict[str, dict[str, dict[str, Stat]]], profiles: tuple[str, ...], out: Path
) -> Path:
    conditions = list(table)
    fig, ax = plt.subplots(figsize=(10, 3.8))
    width = 0.8 / max(len(conditions), 1)
    for i, condition in enumerate(conditions):
        cells = [table[condition].get(p) for p in profiles]
        xs = [j + i * width for j in range(len(profiles))]
        ax.bar(
            xs,
            [c["time_s"].mean if c else 0 for c in cells],
            width,
            yerr=[c["time_s"].spread if c else 0 for c in cells],
            color=COLOURS.get(condition, "#333333"),
            label=condition,
            capsize=2,
        )
    ax.set_xticks([j + 0.4 - width / 2 for j in range(len(profiles))], profiles)
    ax.set_ylabel("time to the finish line, s")
    ax.set_title("Time to the finish line (mean and spread over the seeds)", fontsize=10)
    ax.legend(fontsize=8, ncols=3)
    return _save(fig, out / "time.png")


def _save(fig: Any, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def all_plots(
    outcomes: list[Outcome],
    table: dict[str, dict[str, dict[str, Stat]]],
    profiles: tuple[str, ...],
    out: Path,
) -> list[Path]:
    out.mkdir(parents=True, exist_ok=True)
    return [
        trajectories(outcomes, profiles, out),
        speed_over_time(outcomes, profiles, out),
        fps_over_time(outcomes, profiles, out),
        time_by_condition(table, profiles, out),
    ]
