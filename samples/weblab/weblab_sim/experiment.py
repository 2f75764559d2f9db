"""One run of the WebLab experiment: ``run(profile, seed, condition) -> metrics``.

Assembles the application generated from ``samples/weblab/weblab.xmi`` (``weblab_app``, built into
``samples/weblab/app``) in one process on a :class:`~acordcs.runtime.clock.VirtualClock` seeded
with ``seed``: both containers, the user<->WebLab connections put on one :class:`AccessLink` with
the profile's QoS. The Navigator runs until the robot crosses the finish line or ``time_cap``
simulated seconds pass. A person at the lab (:class:`_Person`) puts the robot back on the stripe
when the control has found no stripe :data:`PATIENCE` cycles in a row: with the Recovering policy
on, the policy asks first (after 4); without it, the person is the only help (a user request).

Conditions switch policies off from outside, through the public runtime API
(``container.remove_policy_set``), and set the Navigator's ``forwardSpeed``.

Metrics (plain names, all numbers): ``cycles_per_s`` (control cycles that found the stripe, per
second of those cycles: stops, retries and recoveries do not count), ``speed_mm_s`` (distance
travelled during those cycles over their time), ``time_s`` (to the finish line, everything
included; ``time_cap`` if not reached), ``finished`` (1 or 0), ``recoveries`` (successful: the
control found the stripe again after the Recovery component acted), ``recovery_actions``,
``stripe_losses`` (cycles without stripe after one with it), ``user_requests``, ``fps`` (the
panoramic camera's rate, time-weighted mean), ``mm_per_cycle``, ``faults`` (runtime faults
recorded by both containers), ``frames_dropped`` (panorama frames the link could not carry),
``cycles`` (all control cycles), ``users_max`` (the most users the Usage monitor saw),
``progress_mm`` (along the stripe), ``sim_s``, ``wall_s`` and ``sim_per_wall``.
"""

from __future__ import annotations

import importlib
import itertools
import sys
import time
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from acordcs.runtime.api import VirtualClock
from weblab_sim import world
from weblab_sim.network import AccessLink, profile
from weblab_sim.world import Script, World

APP_DIR = Path(__file__).resolve().parents[1] / "app"
USER_LINKS = ("VisionLink", "LocomotionLink", "AccessLink", "TelemetryLink", "PanoramaLink")
POLICY_SETS = ("SpeedLimiting", "Recovering", "BandwidthLimiting")
PATIENCE = 6  # cycles in a row without stripe before the person at the lab steps in
RECORD_PERIOD = 0.5  # s between samples of fps, maxSpeed and cycleRate
TIME_CAP = 400.0


@dataclass(frozen=True)
class Condition:
    """Which policy sets are off, and the speed the user's program asks for (mm/s)."""

    off: tuple[str, ...]
    forward_speed: float


CONDITIONS: dict[str, Condition] = {
    "adaptive": Condition((), 200.0),
    "fixed_slow": Condition(POLICY_SETS, 50.0),
    "fixed_lan": Condition(POLICY_SETS, 150.0),
    "no_speed_policy": Condition(("SpeedLimiting",), 200.0),
    "no_recovery_policy": Condition(("Recovering",), 200.0),
    "no_bandwidth_policy": Condition(("BandwidthLimiting",), 200.0),
}


def _registry() -> Any:
    """``weblab_app.registry`` of :data:`APP_DIR` (a package of that name imported from elsewhere,
    such as another build, is forgotten first)."""
    if not sys.path or sys.path[0] != str(APP_DIR):
        sys.path.insert(0, str(APP_DIR))
    loaded = sys.modules.get("weblab_app")
    if loaded is not None and APP_DIR not in Path(loaded.__file__ or "").resolve().parents:
        for name in [m for m in sys.modules if m == "weblab_app" or m.startswith("weblab_app.")]:
            del sys.modules[name]
    try:
        registry = importlib.import_module("weblab_app.registry")
    except ImportError as exc:
        raise RuntimeError(
            f"the generated WebLab application is not in {APP_DIR} ({exc}): build it with "
            "`acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app`"
        ) from None
    return registry


@dataclass
class Rig:
    """One assembled run: the clock, the lab, the running application and what :func:`run`
    reads from them (``record``: (t, fps, maxSpeed, cycleRate, numUsers) every RECORD_PERIOD s)."""

    clock: VirtualClock
    lab: World
    app: Any
    user: Any
    weblab: Any
    link: AccessLink
    navigator: Any
    recovery: Any
    record: list[tuple[float, float, float, float, int]]


@contextmanager
def rig(
    profile_name: str,
    seed: int,
    condition: str = "adaptive",
    *,
    time_cap: float = TIME_CAP,
    script: Script | None = None,
) -> Iterator[Rig]:
    """The generated application assembled for one run, as :func:`run` uses it: the lab installed
    (:func:`weblab_sim.world.install`), the user's links shaped by the profile, the condition's
    policy sets removed, the person at the lab watching, the finish forced at ``time_cap``.
    Nothing has run yet; leaving the block closes the application and uninstalls the lab."""
    if condition not in CONDITIONS:
        raise ValueError(f"no condition {condition!r} (conditions: {', '.join(CONDITIONS)})")
    cond = CONDITIONS[condition]
    net = profile(profile_name)
    registry = _registry()
    clock = VirtualClock(seed)
    lab = World(clock, net, script)
    world.install(lab)
    try:
        app = registry.assemble_application(clock=clock)
        with app:
            user, weblab = app.container("UserSide"), app.container("WebLabSide")
            link = AccessLink(clock)
            for name in USER_LINKS:
                conn = user.connection(name)
                conn.connector = link
                conn.qos.update(net.qos())
            for name in cond.off:
                weblab.remove_policy_set(name)
            navigator = user.find("Navigator")
            navigator.set("forwardSpeed", cond.forward_speed)
            recovery = weblab.find("Recovery")
            record: list[tuple[float, float, float, float, int]] = []

            def sample() -> None:
                record.append(
                    (
                        clock.now(),
                        float(weblab.get_property("PanoramicCamera", "fps")),
                        float(weblab.get_property("Locomotion", "maxSpeed")),
                        float(weblab.get_property("Control", "cycleRate")),
                        int(weblab.get_property("Usage", "numUsers")),
                    )
                )

            clock.call_every(RECORD_PERIOD, sample, start=0.0)
            clock.call_every(1.0, _Person(navigator, recovery).look)
            clock.call_at(time_cap, lambda: setattr(lab, "done", True))
            yield Rig(clock, lab, app, user, weblab, link, navigator, recovery, record)
    finally:
        world.install(None)
        lab.close()


def run(
    profile_name: str,
    seed: int,
    condition: str = "adaptive",
    *,
    time_cap: float = TIME_CAP,
    script: Script | None = None,
    series: bool = False,
) -> dict[str, Any]:
    """One run; the metrics (see the module docstring), plus ``series`` (trajectory, speed, fps
    over time) when asked."""
    wall0 = time.perf_counter()  # the harness's own timing, outside the simulation
    with rig(profile_name, seed, condition, time_cap=time_cap, script=script) as r:
        r.navigator.run()
        metrics = _metrics(r.lab, r.navigator.instance, r.recovery, r.record, time_cap)
        metrics["faults"] = sum(c.faults.counts["total"] for c in r.app.containers.values())
        metrics["frames_dropped"] = r.link.dropped_frames
        metrics["sim_s"] = r.clock.now()
        if series:
            metrics["series"] = _series(r.lab, r.record)
    metrics["wall_s"] = time.perf_counter() - wall0
    metrics["sim_per_wall"] = metrics["sim_s"] / metrics["wall_s"]
    return metrics


class _Person:
    """The person at the lab: steps in (``Recovery.askUser``) after PATIENCE control cycles in a
    row without stripe, once per PATIENCE such cycles (not again while busy or just done)."""

    def __init__(self, navigator: Any, recovery: Any) -> None:
        self.navigator = navigator
        self.recovery = recovery
        self.busy = False
        self.after_cycle = -1  # no help before this cycle count

    def look(self) -> None:
        nav = self.navigator.instance
        if self.busy or nav.misses_in_row < PATIENCE or len(nav.cycles) < self.after_cycle:
            return
        self.busy = True
        try:
            self.recovery.askUser()
        finally:
            self.busy = False
            self.after_cycle = len(nav.cycles) + PATIENCE


def _metrics(lab: World, nav: Any, recovery: Any, record: list, cap: float) -> dict[str, Any]:
    cycles = nav.cycles
    starts = [c[0] for c in cycles] + [cycles[-1][1] if cycles else 0.0]
    moving_time = moving_dist = 0.0
    moving = 0
    for i, (start, _end, turn) in enumerate(cycles):
        if turn is None:
            continue
        stop = starts[i + 1]
        moving += 1
        moving_time += stop - start
        moving_dist += lab.distance_at(stop) - lab.distance_at(start)
    rate = moving / moving_time if moving_time > 0 else 0.0
    speed = moving_dist / moving_time if moving_time > 0 else 0.0
    fps = 0.0
    if len(record) >= 2:
        total = record[-1][0] - record[0][0]
        fps = sum((b[0] - a[0]) * a[1] for a, b in itertools.pairwise(record)) / total
    return {
        "cycles_per_s": rate,
        "speed_mm_s": speed,
        "time_s": lab.finish_time if lab.finish_time is not None else cap,
        "finished": int(lab.finish_time is not None),
        "recoveries": int(recovery.get("recoveries")),
        "recovery_actions": int(recovery.instance.actions),
        "stripe_losses": int(nav.losses),
        "user_requests": int(recovery.instance.user_requests),
        "fps": fps,
        "mm_per_cycle": speed / rate if rate > 0 else 0.0,
        "cycles": len(cycles),
        "users_max": max((r[4] for r in record), default=0),
        "progress_mm": lab.progress,
    }


def _series(lab: World, record: list) -> dict[str, list]:
    return {
        "trajectory": [(s.t, s.x, s.y) for s in lab.samples],
        "speed": [(s.t, s.speed) for s in lab.samples],
        "fps": [(r[0], r[1]) for r in record],
        "max_speed": [(r[0], r[2]) for r in record],
        "cycle_rate": [(r[0], r[3]) for r in record],
        "users": [(r[0], r[4]) for r in record],
    }
