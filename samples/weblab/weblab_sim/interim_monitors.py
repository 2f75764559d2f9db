"""Hand-written monitors for the WebLab, until the generator makes them from the model.

Passed to ``assemble_application(monitors=MONITORS)``. Each takes the constructor arguments the
assembly gives every monitor (name, frequency, sources, attributes).

- ``Control`` (event-driven, source ``Locomotion.LocomotionPort``): for each ``move(speed, turn)``
  of the user's control, ``speed`` (the speed set), ``angle`` = |turn| in degrees and ``cycleRate``
  = control actions per second over the last :data:`RATE_WINDOW` moves; ``stop()`` publishes speed
  0 and restarts the rate's window (the wait is not a control cycle). Calls made by a policy's
  action (the Recovery component backing the robot up) are not the user's control and are ignored:
  they are the calls made while the container's ``origin`` is set.
- ``Telemetry``: subscribes to the simulator's telemetry; a malformed reading is a fault (recorded,
  counted), not an update.
- ``Usage`` (1 Hz): polls ``Access.countUsers()``.
"""

from __future__ import annotations

import math
from collections import deque
from typing import Any

from acordcs.runtime.api import Event, Monitor
from weblab_sim import world

RATE_WINDOW = 5
TELEMETRY_FIELDS = ("positionX", "positionY", "heading", "sonarRange", "batteryVoltage")


class ControlMonitor(Monitor):
    def __init__(self, name: str, **kw: Any) -> None:
        super().__init__(name, **kw)
        self._times: deque[float] = deque(maxlen=RATE_WINDOW + 1)

    def on_event(self, event: Event) -> None:
        container = self.container
        if event.kind != "operation.called" or getattr(container, "origin", None) is not None:
            return
        if event.data.get("error") is not None:
            return
        if event.attribute == "move":
            args = event.data.get("args", ())
            speed, turn = float(args[0]), float(args[1])
            self._times.append(event.time)
            values: dict[str, object] = {"speed": speed, "angle": min(abs(turn), 90.0)}
            if len(self._times) >= 2:
                span = self._times[-1] - self._times[0]
                if span > 0:
                    values["cycleRate"] = (len(self._times) - 1) / span
            self.update(**values)
        elif event.attribute == "stop":
            self._times.clear()
            self.update(speed=0.0, angle=0.0)


class TelemetryMonitor(Monitor):
    def attach(self, container: Any) -> None:
        super().attach(container)
        world.current(container.clock).subscribe_telemetry(self._reading)

    def _reading(self, reading: dict) -> None:
        container = self.container
        if container is None:
            return
        try:
            values = {k: float(reading[k]) for k in TELEMETRY_FIELDS}
            if not all(math.isfinite(v) for v in values.values()):
                raise ValueError("a telemetry field is not a finite number")
        except (KeyError, TypeError, ValueError) as exc:
            container.faults.record(
                "monitor",
                self.name,
                ValueError(f"malformed telemetry {reading!r}: {exc}"),
                container.clock.now(),
            )
            return
        self.update(**values)


class UsageMonitor(Monitor):
    def acquire(self) -> dict[str, object]:
        return {"numUsers": int(self.container.invoke("Access", "countUsers"))}


MONITORS: dict[str, type[Monitor]] = {
    "Control": ControlMonitor,
    "Telemetry": TelemetryMonitor,
    "Usage": UsageMonitor,
}
