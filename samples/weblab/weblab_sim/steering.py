"""Pure-pursuit steering: the turn towards a target point and the wheel motion it asks for.

``turn`` (degrees, + left) is the bearing of the target point on the stripe, as the Navigator
computes it and sends with ``move(speed, turn)``. The locomotion service drives the arc through
that point :data:`STEER_DISTANCE_MM` ahead: its angular rate is the speed times the arc's curvature
(``2 sin(turn) / distance``), so the turn scales with the speed, which keeps the loop stable with
a second of delay where a fixed turn rate is not.
"""

from __future__ import annotations

import math

STEER_DISTANCE_MM = 300.0
MAX_TURN_DEG = 90.0


def turn_towards(x: float, y: float) -> float:
    """The turn (degrees, + left) towards the robot-frame point (x forward, y left), clamped."""
    return max(-MAX_TURN_DEG, min(MAX_TURN_DEG, math.degrees(math.atan2(y, x))))


def angular_velocity(speed: float, turn: float) -> float:
    """Rad/s for a forward ``speed`` (mm/s) and a ``turn`` (degrees) on the pure-pursuit arc."""
    turn = max(-MAX_TURN_DEG, min(MAX_TURN_DEG, turn))
    return speed * 2.0 * math.sin(math.radians(turn)) / STEER_DISTANCE_MM
