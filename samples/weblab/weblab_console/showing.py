"""What the WebLab's panel shows of a run, and how often, the same whether the experiment runs in
this process (:mod:`.session`) or the console is attached to the two-process application
(:mod:`.attached`): the robot's state with its trajectory, the WebLab's events (recoveries, user
requests, stripe losses, manual control, the finish) and the rates at which they go out. The
context, the policies' firings, the faults and the architecture are the console's page's
(:mod:`acordcs.console`), from the containers' observers.

Channels (see :mod:`acordcs.console.fanout`): ``state``, ``path``, ``frame:onboard`` and
``frame:panoramic`` keep their newest payload; ``event`` is queued.
"""

from __future__ import annotations

import math
import time
from collections.abc import Iterable, Mapping
from typing import Any

from acordcs.console.fanout import EVENT, ConsoleHub

PANEL = "weblab"
PUBLISH_HZ = 10.0  # the robot's state per wall second, at most
FRAME_HZ = 15.0  # camera pictures per wall second and camera, at most (policies set <= 15 fps)
TRAIL_STEP_MM = 20.0  # trajectory points closer than this to the last one are not sent
TRAIL_KEPT = 2000
EVENT_TEXT_MAX = 300

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

    def event(self, t: float, kind: str, text: str) -> None:
        """An event of the WebLab's (``kind``: ``start``, ``recovery``, ``driver``...) on the
        console's event channel, as a panel's (the page logs it with the containers')."""
        self.hub.publish(EVENT, {"kind": "panel", "panel": PANEL, "what": kind,
                                 "time": round(t, 2), "text": text[:EVENT_TEXT_MAX]})  # fmt: skip

    def counted(self, t: float, counts: Mapping[str, int]) -> None:
        """Events for the counts that grew since the last call (``recovery``, ``user_request``,
        ``stripe_loss``; the containers' faults are the console's events already)."""
        for kind, count in counts.items():
            seen = self.counts.get(kind, 0)
            if count > seen:
                text = TEXTS[kind]
                self.event(t, kind, text + (f" (×{count - seen})" if count - seen > 1 else ""))
            self.counts[kind] = count
