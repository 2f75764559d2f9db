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

The heading alone is not enough: after the robot overshoots a corner it may pick up another
segment of the stripe (on the right-angle path one runs 700 mm away) and follow it the wrong way,
and at every step the way it is going agrees with the way it went a step before. The lab knows
its floor: while the robot is on the stripe its telemetry also says where along the stripe
(``along``, mm) and which way the stripe runs there (``stripeHeading``). So, judging the readings
taken while the robot drove forward under the user's control:

- a robot on the stripe heading more than :data:`BACKWARDS_DEG` from the way the stripe runs
  there drives it backwards: the direction of travel becomes the stripe's there, and the next
  step reports no stripe (the robot stops before it goes farther);
- a robot on the stripe more than :data:`AHEAD_MM` past the farthest point the lab has seen it
  reach (``progress``) is on another segment: it is astray, and reports no stripe until a
  reading shows it back where it was (the lab's recovery or its person puts it there);
- the way the stripe ran where the robot was last on it (where it lost it, when it has) also
  bounds a single crossing: one more than :data:`BACKWARDS_DEG` from it runs backwards too;
- once a reading says the robot drove the stripe backwards (the lab stopped it,
  ``stoppedBackwards``, or it heads more than :data:`BACKWARDS_DEG` from the way the stripe runs),
  the way the stripe runs there is the way on, and a point more than :data:`AGAINST_DEG` from it
  lies back along the stripe: the Navigator takes none until a reading shows the robot on the
  stripe facing within :data:`AGAINST_DEG` of the way it runs there (or it is carried).
  :data:`BACKWARDS_DEG` is wide because a robot coming to a corner steers up to 120 degrees from
  the segment it is on; a robot the lab has just found driving back along the stripe is not
  coming to a corner, and with only that wide bound it took the same stripe the wrong way after
  each of the recovery's back-ups (on the right-angle path, past the fourth corner, heading 145
  degrees from the stripe: each time the lab stopped it 16 mm further back, 119 mm in all).

A stripe seen only from more than :data:`BEYOND_MM` ahead is not the one the robot follows: that
one enters the view at its near edge (150 mm ahead), and leaves it there when the robot is within
150 mm of a corner, before the new segment comes into view. At the right-angle path's second
corner the camera then sees only the fifth segment, 700 mm on (and 2 m further along the stripe);
steering at it took the robot there, too far from the corner for the recovery to bring it back,
and a person was needed in every run. The Navigator reports no stripe instead: the robot stops,
and the recovery backs it up turning towards the side it was turning to, where the new segment
comes into view.

Headings are in degrees, counter-clockwise from east (as the telemetry gives them).
"""

from __future__ import annotations

import math

from weblab_sim.detector import Sighting, bearing

SIDE_BIAS_DEG = 45.0
BACKWARDS_DEG = 150.0
AGAINST_DEG = 90.0  # a point farther than this from the way the stripe runs lies back along it
AHEAD_MM = 400.0  # as far past the farthest point reached as the next stretch of stripe starts
BEYOND_MM = 500.0  # a stripe that begins this far ahead is not the one the robot was following
TURNING_DEG = 2.0  # a turn smaller than this says nothing about the side the stripe goes to
CARRIED_DEG = 75.0  # a heading change between two telemetry readings the wheels cannot make


def wrap(angle: float) -> float:
    """An angle in degrees, brought into [-180, 180)."""
    return (angle + 180.0) % 360.0 - 180.0


def _number(value: object) -> float | None:
    """A finite float, or None (missing or malformed)."""
    try:
        number = float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        return None
    return number if math.isfinite(number) else None


def judge(reading: object) -> tuple[bool, bool] | None:
    """Of a telemetry reading of a robot on the stripe: (it heads more than
    :data:`BACKWARDS_DEG` from the way the stripe runs there, it is more than :data:`AHEAD_MM` past
    the farthest point reached); None when the reading does not put the robot on the stripe."""
    if not isinstance(reading, dict):
        return None
    heading, runs = _number(reading.get("heading")), _number(reading.get("stripeHeading"))
    along, reached = _number(reading.get("along")), _number(reading.get("progress"))
    if heading is None or runs is None or along is None or reached is None:
        return None
    return abs(wrap(heading - runs)) > BACKWARDS_DEG, along > reached + AHEAD_MM


class Course:
    """The direction of travel (world bearing, degrees) and the robot's last known heading."""

    def __init__(self) -> None:
        self.heading: float | None = None
        self.travel: float | None = None
        self.side = 0.0  # +1 left, -1 right: the side of the last clear turn; 0 before one
        self.stripe: float | None = None  # the way the stripe ran where the robot last was on it
        self.halt = False  # the robot drove the stripe backwards: the next step stops it
        self.astray = False  # the robot is on another segment, far ahead
        # the way the stripe runs where the robot was found driving it backwards, until it faces
        # along the stripe again
        self.against: float | None = None

    def observe(self, reading: object, forward: bool = False) -> None:
        """Take the heading of a telemetry reading (a mapping with ``heading`` in degrees, and
        ``along``, ``progress`` and ``stripeHeading`` when the robot is on the stripe);
        ``forward``: the robot was driving forward under the user's control when it was taken.
        A malformed reading, without a finite heading, is ignored."""
        if not isinstance(reading, dict):
            return
        heading = _number(reading.get("heading"))
        if heading is None:
            return
        if self.heading is not None and abs(wrap(heading - self.heading)) > CARRIED_DEG:
            self.travel, self.side, self.stripe = None, 0.0, None
            self.against = None
        self.heading = heading
        stopped = forward and bool(reading.get("stoppedBackwards"))
        if stopped:
            self.halt = True  # the lab stopped it: it drove the stripe backwards
        judged = judge(reading)
        if judged is None:
            return
        backwards, elsewhere = judged
        runs = float(reading["stripeHeading"])  # judge() found it a number
        if not elsewhere:
            if stopped or (forward and backwards):
                self.against = runs
            elif abs(wrap(heading - runs)) <= AGAINST_DEG:
                self.against = None  # it faces along the stripe again
        if forward and elsewhere:
            self.astray = True
        elif not elsewhere and not backwards:
            self.astray = False
        if forward and backwards and not elsewhere:
            self.travel, self.side, self.halt = runs, 0.0, True
        if not backwards and not elsewhere:
            self.stripe = runs

    def choose(self, seen: Sighting | None) -> float | None:
        """The turn (degrees, + left) to steer at in what the camera saw, or None: no stripe, or
        only a stripe that runs backwards or begins more than :data:`BEYOND_MM` ahead, or the robot is
        astray."""
        if self.halt:
            self.halt = False
            return None
        if seen is None or self.astray:
            return None
        if self.heading is None:
            return self._take(bearing(seen.target))
        if self.against is not None:
            onward = [
                p
                for p in seen.crossings
                if abs(wrap(self.heading + bearing(p) - self.against)) <= AGAINST_DEG
            ]
            if not onward:
                return None
            seen = Sighting(onward[0], tuple(onward))
        if self.travel is None:
            return self._take(bearing(seen.target))
        if len(seen.crossings) >= 2:
            preferred = self.travel + SIDE_BIAS_DEG * self.side
            return self._take(
                min(
                    (bearing(p) for p in seen.crossings),
                    key=lambda b: abs(wrap(self.heading + b - preferred)),  # type: ignore[operator]
                )
            )
        if math.hypot(*seen.target) > BEYOND_MM:
            return None
        turn = bearing(seen.target)
        way = wrap(self.heading + turn)
        if abs(wrap(way - self.travel)) > BACKWARDS_DEG:
            return None
        if self.stripe is not None and abs(wrap(way - self.stripe)) > BACKWARDS_DEG:
            return None
        return self._take(turn)

    def _take(self, turn: float) -> float:
        if self.heading is not None:
            self.travel = wrap(self.heading + turn)
        if abs(turn) > TURNING_DEG:
            self.side = math.copysign(1.0, turn)
        return turn
