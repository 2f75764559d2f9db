"""The user's memory of the stripe's direction of travel, so that the Navigator never follows the
stripe backwards.

The camera alone cannot tell the two directions along a stripe apart when it sees the stripe
across its view, as after a recovery has backed the robot up and turned it, or when the robot has
overshot a corner: the stripe then crosses the look-ahead distance twice, once in each direction
(:class:`weblab_sim.detector.Sighting`). The Navigator knows more: the robot's heading, from the
telemetry the locomotion service pushes on its ``TelemetryPort`` (every 0.5 s, moving or not), and
the direction it was travelling in, the world bearing of the last point it steered at. So:

- with two or more crossings it steers at the one whose world bearing is closest to the direction
  of travel turned :data:`SIDE_BIAS_DEG` towards the side the robot was last turning to (the
  stripe goes on towards that side: at a sharp corner, the way on is up to about 120 degrees
  from the way the robot came, the way back along the new segment only 60 degrees on the other
  side);
- with one, it refuses a point more than :data:`BACKWARDS_DEG` from the direction of travel:
  that stripe runs back the way the robot came, and the Navigator reports no stripe (it stops,
  and the lab's recovery or its person acts);
- until it knows a heading it steers at the detector's usual point;
- when the heading jumps by more than :data:`CARRIED_DEG` between two readings (0.5 s apart:
  the wheels turn the robot at most about 55 degrees in that time), someone has carried the robot
  (the lab's person puts it back on the stripe facing along it): the direction of travel is
  forgotten, and the next stripe seen gives it again.

Headings are in degrees, counter-clockwise from east (as the telemetry gives them).
"""

from __future__ import annotations

import math

from weblab_sim.detector import Sighting, bearing

SIDE_BIAS_DEG = 45.0
BACKWARDS_DEG = 150.0
TURNING_DEG = 2.0  # a turn smaller than this says nothing about the side the stripe goes to
CARRIED_DEG = 75.0  # a heading change between two telemetry readings the wheels cannot make


def wrap(angle: float) -> float:
    """An angle in degrees, brought into [-180, 180)."""
    return (angle + 180.0) % 360.0 - 180.0


class Course:
    """The direction of travel (world bearing, degrees) and the robot's last known heading."""

    def __init__(self) -> None:
        self.heading: float | None = None
        self.travel: float | None = None
        self.side = 0.0  # +1 left, -1 right: the side of the last clear turn; 0 before one

    def observe(self, reading: object) -> None:
        """Take the heading of a telemetry reading (a mapping with ``heading`` in degrees); a
        malformed reading, without a finite heading, is ignored."""
        if not isinstance(reading, dict):
            return
        try:
            heading = float(reading.get("heading"))  # type: ignore[arg-type]
        except (TypeError, ValueError):
            return
        if not math.isfinite(heading):
            return
        if self.heading is not None and abs(wrap(heading - self.heading)) > CARRIED_DEG:
            self.travel, self.side = None, 0.0
        self.heading = heading

    def choose(self, seen: Sighting | None) -> float | None:
        """The turn (degrees, + left) to steer at in what the camera saw, or None: no stripe, or
        only a stripe that runs backwards."""
        if seen is None:
            return None
        if self.heading is None or self.travel is None:
            return self._take(bearing(seen.target))
        if len(seen.crossings) >= 2:
            preferred = self.travel + SIDE_BIAS_DEG * self.side
            return self._take(
                min(
                    (bearing(p) for p in seen.crossings),
                    key=lambda b: abs(wrap(self.heading + b - preferred)),  # type: ignore[operator]
                )
            )
        turn = bearing(seen.target)
        if abs(wrap(self.heading + turn - self.travel)) > BACKWARDS_DEG:
            return None
        return self._take(turn)

    def _take(self, turn: float) -> float:
        if self.heading is not None:
            self.travel = wrap(self.heading + turn)
        if abs(turn) > TURNING_DEG:
            self.side = math.copysign(1.0, turn)
        return turn
