"""What the console shows of a run, and how often, the same whether the experiment runs in this
process (:mod:`.session`) or the console is attached to the two-process application
(:mod:`.attached`): the payloads of the hub's channels (the robot's state with its trajectory, the
context values, a policy set's last firing, an event of the timeline, the series of the speed
limit and the frame rate) and the rates at which they go out.

Channels (see :mod:`.hub`): ``state``, ``context``, ``policy:<set>``, ``series``, ``stats``,
``frame:onboard`` and ``frame:panoramic`` keep their newest payload; ``event`` is queued.
"""

from __future__ import annotations

import math
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from typing import Any

from acordcs.console.fanout import EVENT, ConsoleHub

PUBLISH_HZ = 10.0  # state, context and policies per wall second, at most
FRAME_HZ = 15.0  # camera pictures per wall second and camera, at most (policies set <= 15 fps)
SERIES_PERIOD = 0.5  # seconds of the run's clock between points of the live plots
SERIES_HZ = 2.0  # the plots and the viewer statistics per wall second, at most
SERIES_KEPT = 600
TRAIL_STEP_MM = 20.0  # trajectory points closer than this to the last one are not sent
TRAIL_KEPT = 2000
EVENT_TEXT_MAX = 300

CONTEXT = (
    ("cycle rate (cycles/s)", "Control", "cycleRate"),
    ("trajectory angle (°)", "Control", "angle"),
    ("speed set (mm/s)", "Control", "speed"),
    ("users", "Usage", "numUsers"),
    ("battery (V)", "Telemetry", "batteryVoltage"),
    ("nearest sonar (mm)", "Telemetry", "sonarRange"),
    ("speed limit (mm/s)", "Locomotion", "maxSpeed"),
    ("panoramic fps", "PanoramicCamera", "fps"),
    ("recovery retries", "Recovery", "retries"),
    ("recoveries", "Recovery", "recoveries"),
)
"""The context panel's rows: label, element, attribute."""

TEXTS = {
    "recovery": "recovery: backed up and turned towards the stripe",
    "user_request": "user request: a person puts the robot back on the stripe",
    "stripe_loss": "stripe lost",
}
"""The timeline's text for the events counted from the application's state."""


class Showing:
    """One run as the console shows it: its hub, the trajectory so far, the series, what was
    counted for the timeline, and when each channel may go out again (wall clock)."""

    def __init__(self, hub: ConsoleHub, profile: str, seed: int) -> None:
        self.hub = hub
        self.profile = profile
        self.seed = seed
        self.trail: list[list[float]] = []
        self.series: dict[str, deque] = {
            k: deque(maxlen=SERIES_KEPT) for k in ("t", "max_speed", "fps")
        }
        self.counts: dict[str, int] = {}
        self.last_state: dict[str, Any] | None = None
        self._next: dict[str, float] = {}  # when each channel may go out again (wall clock)

    def due(self, channel: str, *, force: bool = False) -> bool:
        """Whether ``channel`` may go out now; say :meth:`sent` when it went."""
        return force or time.perf_counter() >= self._next.get(channel, 0.0)

    def sent(self, channel: str, hz: float) -> None:
        """``channel`` went out: the next may go ``1/hz`` seconds after the slot this one took,
        so that ``hz`` a second go out on average whatever the phase of the checks (a camera at
        11 frames a second, checked every 50 ms, sends 11 a second under a cap of 15, not 10)."""
        now = time.perf_counter()
        self._next[channel] = max(self._next.get(channel, now), now - 1.0 / hz) + 1.0 / hz

    # ----------------------------------------------------------------------------- payloads
    def state(
        self,
        *,
        t: float,
        pose: tuple[float, float, float],
        sonar: Iterable[tuple[float, float]],
        speed: float,
        fps: int,
        driver: str,
        running: bool,
        progress: float,
        **extra: Any,
    ) -> dict[str, Any]:
        """Publish the robot's state (``pose``: x, y in mm, heading in radians; ``sonar``:
        bearing in degrees, range in mm; ``progress``: % of the path) and note the trajectory."""
        x, y, heading = pose
        if not self.trail or math.dist(self.trail[-1], (x, y)) >= TRAIL_STEP_MM:
            self.trail.append([round(x, 1), round(y, 1)])
            if len(self.trail) > TRAIL_KEPT:
                del self.trail[::2]  # keep the whole run, coarser
        self.last_state = {
            "t": round(t, 2),
            "pose": [round(x, 1), round(y, 1), round(math.degrees(heading), 1)],
            "trajectory": list(self.trail),
            "sonar": [[a, round(float(d), 0)] for a, d in sonar],
            "speed": round(speed, 1),
            "fps": int(fps),
            "driver": driver,
            "running": running,
            "profile": self.profile,
            "seed": self.seed,
            "progress": round(progress, 1),
            **extra,
        }
        self.hub.publish("state", self.last_state)
        return self.last_state

    def stopped(self, **extra: Any) -> None:
        """Publish the last state shown, marked as not running (the run has ended)."""
        last = dict(self.last_state or {"t": 0.0, "pose": [0, 0, 0], "trajectory": [], "sonar": []})
        last.update(running=False, driver="navigator", profile=self.profile, seed=self.seed)
        last.setdefault("speed", 0.0)
        last.setdefault("fps", 0)
        last.update(extra)
        self.hub.publish("state", last)

    def context(self, read: Callable[[str, str], object]) -> None:
        """Publish the context panel's values, ``read(element, attribute)`` each (a value that is
        not a number, or one that cannot be read, shows as a dash)."""
        values: dict[str, object] = {}
        for label, element, attribute in CONTEXT:
            try:
                value = read(element, attribute)
            except Exception:  # a monitor without a value yet, an element gone
                value = None
            values[label] = value if isinstance(value, int | float) else "–"
        self.hub.publish("context", values)

    def policy(
        self,
        name: str,
        engine: str,
        t: float,
        fires: int,
        rules: Iterable[tuple[str, str, float]],
        inputs: Mapping[str, object],
        outputs: Mapping[str, object],
    ) -> None:
        """Publish a policy set's last firing (``rules``: policy, rule label, degree)."""
        self.hub.publish(
            f"policy:{name}",
            {
                "set": name,
                "engine": engine,
                "t": round(t, 2),
                "fires": fires,
                "rules": [
                    {"label": label, "policy": policy, "degree": round(float(degree), 3)}
                    for policy, label, degree in rules
                ],
                "inputs": {k: plain(v) for k, v in inputs.items()},
                "outputs": {k: plain(v) for k, v in outputs.items()},
            },
        )

    def sample(self, t: float, max_speed: object, fps: object) -> None:
        """A point of the live plots (the speed limit and the frame rate at ``t``)."""
        if not isinstance(max_speed, int | float) or not isinstance(fps, int | float):
            return
        self.series["t"].append(round(t, 2))
        self.series["max_speed"].append(round(float(max_speed), 1))
        self.series["fps"].append(float(fps))

    def plots(self, *, force: bool = False) -> None:
        """Publish the series and the viewer statistics, at most :data:`SERIES_HZ` a second."""
        if self.due("series", force=force):
            self.sent("series", SERIES_HZ)
            self.hub.publish("series", {k: list(v) for k, v in self.series.items()})
            self.hub.publish("stats", self.hub.stats())

    def event(self, t: float, kind: str, text: str) -> None:
        self.hub.publish(EVENT, {"t": round(t, 2), "kind": kind, "text": text[:EVENT_TEXT_MAX]})

    def counted(self, t: float, counts: Mapping[str, int], fault: Callable[[], str]) -> None:
        """Timeline events for the counts that grew since the last call (``recovery``,
        ``user_request``, ``stripe_loss``, ``fault``: its text from ``fault()``)."""
        for kind, count in counts.items():
            seen = self.counts.get(kind, 0)
            if count > seen:
                text = fault() if kind == "fault" else TEXTS[kind]
                self.event(t, kind, text + (f" (×{count - seen})" if count - seen > 1 else ""))
            self.counts[kind] = count


def plain(value: object) -> object:
    """A value as the page shows it: numbers (floats to 3 decimals), text, booleans, None;
    anything else as text."""
    if isinstance(value, float):
        return round(value, 3)
    return value if isinstance(value, int | str | bool) or value is None else str(value)
