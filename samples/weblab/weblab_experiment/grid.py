"""The experiment's runs: every condition on every network profile and path for every seed,
independent of each other, spread over the machine's cores, with a progress bar.

Each run is :func:`weblab_sim.experiment.run` in a worker process (the simulation is pure Python
and numpy: processes, not threads, use both cores). The first seed of each (path, condition,
profile) also returns its time series (trajectory, speed, speed limit, frame rate) for the plots.
A run that raises is recorded with its error and counted, not fatal: the table says how many runs
each cell has, and the report lists the failed runs.
"""

from __future__ import annotations

import os
import time
import traceback
from collections.abc import Iterable
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass, field
from typing import Any

from tqdm import tqdm
from weblab_sim import experiment, floor, network

PROFILES = tuple(network.PROFILES)
PATHS = tuple(floor.PATHS)
CONDITIONS = tuple(experiment.CONDITIONS)
"""The named conditions, in table order."""
SWEEP = (40.0, 60.0, 80.0, 100.0)
"""The fixed speeds (mm/s) of the sensitivity sweep, besides 50 and 150, in both fixed-speed
families (every policy off; only SpeedLimiting off)."""


def fixed_name(speed: float, prefix: str = experiment.FIXED) -> str:
    """The condition that drives at a fixed ``speed`` (mm/s) with every policy off (``prefix``
    :data:`weblab_sim.experiment.UNLIMITED`: with only SpeedLimiting off)."""
    return f"{prefix}{speed:g}"


@dataclass(frozen=True)
class Task:
    condition: str
    profile: str
    seed: int
    series: bool
    path: str = "default"
    time_cap: float = experiment.TIME_CAP


@dataclass
class Outcome:
    task: Task
    metrics: dict[str, Any] = field(default_factory=dict)
    error: str | None = None


def tasks(
    conditions: Iterable[str],
    profiles: Iterable[str],
    seeds: int,
    first_seed: int = 0,
    paths: Iterable[str] = ("default",),
    time_cap: float = experiment.TIME_CAP,
) -> list[Task]:
    """One task per (path, condition, profile, seed); the first seed of each keeps its series."""
    return [
        Task(condition, profile, seed, seed == first_seed, path, time_cap)
        for path in paths
        for condition in conditions
        for profile in profiles
        for seed in range(first_seed, first_seed + seeds)
    ]


def _run(task: Task) -> Outcome:
    from weblab_sim.experiment import run  # in the worker: its own simulator and application

    try:
        metrics = run(
            task.profile,
            task.seed,
            task.condition,
            series=task.series,
            path=task.path,
            time_cap=task.time_cap,
        )
    except Exception:  # a run's failure is a result, reported in the table
        return Outcome(task, error=traceback.format_exc(limit=8))
    return Outcome(task, metrics)


def run_all(
    todo: list[Task], jobs: int | None = None, progress: bool = True
) -> tuple[list[Outcome], float]:
    """Every task's outcome (in task order) and the wall time, on ``jobs`` processes (default:
    all cores); a progress bar on standard error while it runs."""
    jobs = jobs or os.cpu_count() or 1
    started = time.perf_counter()
    done: dict[Task, Outcome] = {}
    bar = tqdm(total=len(todo), desc="WebLab runs", unit="run", disable=not progress, leave=True)
    try:
        if jobs == 1:
            for task in todo:
                done[task] = _run(task)
                bar.update()
        else:
            # the longest runs first (series runs, then the slowest fixed speeds), so the last
            # ones to finish are short and both cores stay busy to the end
            order = sorted(
                todo, key=lambda t: (not t.series, experiment.fixed_speed(t.condition) or 1e9)
            )
            with ProcessPoolExecutor(max_workers=jobs) as pool:
                futures = {pool.submit(_run, task): task for task in order}
                for future in as_completed(futures):
                    done[futures[future]] = future.result()
                    bar.update()
    finally:
        bar.close()
    return [done[t] for t in todo], time.perf_counter() - started
