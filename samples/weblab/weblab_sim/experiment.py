"""One run of the WebLab experiment: ``run(profile, seed, condition) -> metrics``.

Assembles the application generated from ``samples/weblab/weblab.xmi`` (``weblab_app``, built into
``samples/weblab/app``) in one process on a :class:`~acordcs.runtime.clock.VirtualClock` seeded
with ``seed``: both containers, the user<->WebLab connections put on one :class:`AccessLink` with
the profile's QoS, on the floor with the stripe ``path`` (:data:`weblab_sim.floor.PATHS`). The
Navigator runs until the robot crosses the finish line or ``time_cap`` simulated seconds pass (a
run that hits the cap has failed: ``finished`` is 0). A person at the lab (:class:`Person`) puts
the robot back on the stripe when the control has found no stripe :data:`PATIENCE` cycles in a
row, or when the lab has recovered the robot :data:`REPEATS` times without it getting
:data:`SAME_PLACE_MM` further along the stripe: with the Recovering policy on, the policy asks
first (after 3 recoveries that did not get the robot ahead of where it lost the stripe); without
it, the person is the only help (a user request).

Conditions (:func:`parse_condition`) switch policies off from outside, through the public runtime API
(``container.remove_policy_set``), and set the Navigator's ``forwardSpeed``: ``adaptive`` (every
policy on), ``fixed_<speed>`` (every policy off, the user asks for ``<speed>`` mm/s: ``fixed_50``,
``fixed_150``, and any other speed of a sweep), ``no_speed_policy_<speed>`` (only SpeedLimiting
off, Recovering and BandwidthLimiting on, the user asks for ``<speed>`` mm/s: what speed
adaptation alone buys), ``no_speed_policy`` (the same at the adaptive runs' 200 mm/s),
``no_recovery_policy`` and ``no_bandwidth_policy`` (that set off).

Metrics (plain names, all numbers): ``cycles_per_s`` (control cycles that found the stripe, per
second of those cycles: stops, retries and recoveries do not count), ``speed_mm_s`` (distance
travelled during those cycles over their time), ``time_s`` (to the finish line, everything
included; ``time_cap`` if not reached), ``finished`` (1 or 0), ``recoveries`` (successful: the
control found the stripe again after the Recovery component acted), ``recovery_actions``,
``stripe_losses`` (cycles without stripe after one with it), ``losses_near_corner`` (those
within :data:`CORNER_MM` of a corner, along the stripe), ``user_requests``, ``fps`` (the
panoramic camera's rate, time-weighted mean), ``fps_raw`` (the same of BandwidthLimiting's output
before the int attribute rounds it; the attribute where the policy is off or has not fired yet),
``fps_mode`` and ``fps_mode_share`` (the rate set longest, and its share of the time),
``mm_per_cycle``, ``moving_mm`` (distance travelled in the cycles that found the stripe),
``stopped_s`` (``time_s`` minus those cycles' time: stops, recoveries, help), ``faults`` (runtime
faults recorded by both containers), ``frames_dropped`` (panorama frames the link could not
carry), ``cycles`` (all control cycles), ``users_max`` (the most users the Usage monitor saw),
``progress_mm`` (along the stripe), ``backwards_mm`` (the most the robot drove back along the
stripe while driving forward under the user's control) and ``followed_backwards`` (1 when that
is more than :data:`BACKWARDS_MM`), ``sim_s``, ``wall_s`` and ``sim_per_wall``.
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
from weblab_sim.floor import DEFAULT_PATH, PATHS
from weblab_sim.network import AccessLink, profile
from weblab_sim.world import Script, World

APP_DIR = Path(__file__).resolve().parents[1] / "app"
USER_LINKS = ("VisionLink", "LocomotionLink", "AccessLink", "TelemetryLink", "PanoramaLink")
POLICY_SETS = ("SpeedLimiting", "Recovering", "BandwidthLimiting")
PATIENCE = 6  # cycles in a row without stripe before the person at the lab steps in
REPEATS = 4  # recoveries at the same place before the person at the lab steps in
SAME_PLACE_MM = 300.0  # progress along the stripe that makes the next recovery another place
RECORD_PERIOD = 0.5  # s between samples of fps, maxSpeed and cycleRate
CORNER_MM = 400.0  # a stripe loss this close to a corner (along the stripe) is counted at it
TIME_CAP = 400.0
BACKWARDS_MM = 100.0  # driving this far back along the stripe under the user's control: backwards
ADAPTIVE_SPEED = 200.0  # mm/s the user's program asks for when the policies may cap it
FIXED = "fixed_"  # prefix of the fixed-speed conditions with every policy off: fixed_<mm/s>
UNLIMITED = (
    "no_speed_policy_"  # prefix of those with only SpeedLimiting off: no_speed_policy_<mm/s>
)
FAMILIES = {FIXED: POLICY_SETS, UNLIMITED: ("SpeedLimiting",)}
"""The fixed-speed families: the prefix, and the policy sets it switches off."""
FIXED_RANGE = (10.0, 300.0)  # mm/s a fixed speed may be (300: the wheels' top speed)


@dataclass(frozen=True)
class Condition:
    """Which policy sets are off, and the speed the user's program asks for (mm/s)."""

    off: tuple[str, ...]
    forward_speed: float


CONDITIONS: dict[str, Condition] = {
    "adaptive": Condition((), ADAPTIVE_SPEED),
    "fixed_50": Condition(POLICY_SETS, 50.0),
    "fixed_150": Condition(POLICY_SETS, 150.0),
    "no_speed_policy": Condition(("SpeedLimiting",), ADAPTIVE_SPEED),
    "no_recovery_policy": Condition(("Recovering",), ADAPTIVE_SPEED),
    "no_bandwidth_policy": Condition(("BandwidthLimiting",), ADAPTIVE_SPEED),
    "no_speed_policy_50": Condition(("SpeedLimiting",), 50.0),
    "no_speed_policy_150": Condition(("SpeedLimiting",), 150.0),
}
"""The named conditions; :func:`parse_condition` also knows ``fixed_<speed>`` and
``no_speed_policy_<speed>`` for any other speed."""


def family(name: str) -> str | None:
    """The prefix of the fixed-speed family (:data:`FAMILIES`) of a condition name, or None."""
    return next((f for f in FAMILIES if name.startswith(f) and fixed_speed(name) is not None), None)


def fixed_speed(name: str) -> float | None:
    """The speed (mm/s) of a ``fixed_<speed>`` or ``no_speed_policy_<speed>`` condition name,
    None for any other name."""
    prefix = next((f for f in FAMILIES if name.startswith(f)), None)
    if prefix is None:
        return None
    try:
        speed = float(name[len(prefix) :])
    except ValueError:
        return None
    return speed if FIXED_RANGE[0] <= speed <= FIXED_RANGE[1] else None


def parse_condition(name: str) -> Condition:
    """The condition ``name``: one of :data:`CONDITIONS`, ``fixed_<speed>`` or
    ``no_speed_policy_<speed>`` (mm/s, 10-300)."""
    if name in CONDITIONS:
        return CONDITIONS[name]
    speed, prefix = fixed_speed(name), family(name)
    if speed is None or prefix is None:
        raise ValueError(
            f"no condition {name!r} (conditions: {', '.join(CONDITIONS)}, or fixed_<speed> or "
            f"no_speed_policy_<speed> with a speed of {FIXED_RANGE[0]:g} to {FIXED_RANGE[1]:g} "
            "mm/s)"
        )
    return Condition(FAMILIES[prefix], speed)


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
    path: str = DEFAULT_PATH,
) -> Iterator[Rig]:
    """The generated application assembled for one run, as :func:`run` uses it: the lab installed
    (:func:`weblab_sim.world.install`) with the stripe ``path``, the user's links shaped by the
    profile, the condition's policy sets removed, the person at the lab watching, the finish
    forced at ``time_cap``. Nothing has run yet; leaving the block closes the application and
    uninstalls the lab."""
    cond = parse_condition(condition)
    if path not in PATHS:
        raise ValueError(f"no path {path!r} (paths: {', '.join(PATHS)})")
    net = profile(profile_name)
    registry = _registry()
    clock = VirtualClock(seed)
    lab = World(clock, net, script, path)
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
            record: list[tuple[float, float, float, float, int, float]] = []
            bandwidth = (
                None if "BandwidthLimiting" in cond.off else weblab.policy_set("BandwidthLimiting")
            )

            def sample() -> None:
                fps = float(weblab.get_property("PanoramicCamera", "fps"))
                # the policy's own output, before the int attribute rounds it (the attribute
                # stands in for it until the policy's first firing)
                raw = None
                if bandwidth is not None and bandwidth.last_firing is not None:
                    raw = bandwidth.engine.get("PanoramicCamera.fps")
                record.append(
                    (
                        clock.now(),
                        fps,
                        float(weblab.get_property("Locomotion", "maxSpeed")),
                        float(weblab.get_property("Control", "cycleRate")),
                        int(weblab.get_property("Usage", "numUsers")),
                        fps if raw is None else float(raw),
                    )
                )

            clock.call_every(RECORD_PERIOD, sample, start=0.0)
            clock.call_every(1.0, Person(navigator, recovery, lab).look)
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
    path: str = DEFAULT_PATH,
) -> dict[str, Any]:
    """One run; the metrics (see the module docstring), plus ``series`` (trajectory, speed, fps
    over time) when asked."""
    wall0 = time.perf_counter()  # the harness's own timing, outside the simulation
    with rig(profile_name, seed, condition, time_cap=time_cap, script=script, path=path) as r:
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


class Person:
    """The person at the lab: steps in (``Recovery.askUser``) after PATIENCE control cycles in a
    row without stripe, once per PATIENCE such cycles (not again while busy or just done), and
    after REPEATS recovery actions at the same place (the robot got less than SAME_PLACE_MM
    further along the stripe since the first of them)."""

    def __init__(self, navigator: Any, recovery: Any, lab: World) -> None:
        self.navigator = navigator
        self.recovery = recovery
        self.lab = lab
        self.busy = False
        self.after_cycle = -1  # no help before this cycle count
        self.place = (lab.progress, 0)  # (progress, recovery actions) where this place began

    def look(self) -> None:
        if self.busy:
            return
        nav = self.navigator.instance
        actions = self.recovery.instance.actions
        if self.lab.progress >= self.place[0] + SAME_PLACE_MM:
            self.place = (self.lab.progress, actions)
        stuck = actions - self.place[1] >= REPEATS
        lost = nav.misses_in_row >= PATIENCE and len(nav.cycles) >= self.after_cycle
        if not (stuck or lost):
            return
        self.busy = True
        try:
            self.recovery.askUser()
        finally:
            self.busy = False
            self.after_cycle = len(nav.cycles) + PATIENCE
            self.place = (self.lab.progress, self.recovery.instance.actions)


def _metrics(lab: World, nav: Any, recovery: Any, record: list, cap: float) -> dict[str, Any]:
    cycles = nav.cycles
    starts = [c[0] for c in cycles] + [cycles[-1][1] if cycles else 0.0]
    moving_time = moving_dist = 0.0
    moving = 0
    losses_near_corner = 0
    corners = lab.path.corners()
    for i, (start, _end, turn) in enumerate(cycles):
        if turn is None:
            if i > 0 and cycles[i - 1][2] is not None:  # a stripe loss: where was the robot?
                at = lab.progress_at(start)
                losses_near_corner += any(abs(at - c) <= CORNER_MM for c in corners)
            continue
        stop = starts[i + 1]
        moving += 1
        moving_time += stop - start
        moving_dist += lab.distance_at(stop) - lab.distance_at(start)
    rate = moving / moving_time if moving_time > 0 else 0.0
    speed = moving_dist / moving_time if moving_time > 0 else 0.0
    time_s = lab.finish_time if lab.finish_time is not None else cap
    held: dict[float, float] = {}  # frame rate -> seconds it was set
    fps = fps_raw = 0.0
    if len(record) >= 2:
        total = record[-1][0] - record[0][0]
        for a, b in itertools.pairwise(record):
            held[a[1]] = held.get(a[1], 0.0) + b[0] - a[0]
            fps_raw += (b[0] - a[0]) * a[5] / total
        fps = sum(rate * span for rate, span in held.items()) / total
    mode = max(held, key=lambda k: held[k], default=0.0)
    return {
        "cycles_per_s": rate,
        "speed_mm_s": speed,
        "time_s": time_s,
        "finished": int(lab.finish_time is not None),
        "recoveries": int(recovery.get("recoveries")),
        "recovery_actions": int(recovery.instance.actions),
        "stripe_losses": int(nav.losses),
        "losses_near_corner": losses_near_corner,
        "user_requests": int(recovery.instance.user_requests),
        "fps": fps,
        "fps_raw": fps_raw,
        "fps_mode": mode,
        "fps_mode_share": held.get(mode, 0.0) / sum(held.values()) if held else 0.0,
        "mm_per_cycle": speed / rate if rate > 0 else 0.0,
        "moving_mm": moving_dist,
        "stopped_s": time_s - moving_time,
        "cycles": len(cycles),
        "users_max": max((r[4] for r in record), default=0),
        "progress_mm": lab.progress,
        "backwards_mm": lab.backwards_mm,
        "followed_backwards": int(lab.backwards_mm > BACKWARDS_MM),
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
