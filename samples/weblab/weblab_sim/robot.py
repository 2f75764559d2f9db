"""The robot: a pymunk differential-drive body on the floor, advanced lazily in virtual time.

Top-down traction as in pymunk's ``examples/tank.py``: a kinematic control body carries the wanted
velocity and turn rate; a PivotJoint and a GearJoint (``max_bias=0``, limited ``max_force``) drag
the robot's dynamic body after it, so the robot accelerates with a finite force, and walls stop it.
Physics runs on a fixed grid of :data:`STEP` seconds, advanced up to the clock's time when someone
looks (:meth:`Robot.pose`) or commands (:meth:`Robot.command`); a command takes effect at its exact
time (a step is split in proportion), and a pose between grid points is extrapolated from the last
one, so delays are never rounded to the step. A fresh :class:`pymunk.Space` per robot: a space
keeps cached impulses between steps.

Fixed beforehand: a 330 mm wheel base (the model's ``Locomotion.wheelBase``), 300 x 260 mm
footprint, 4 kg, wheel speed at most 300 mm/s.
"""

from __future__ import annotations

import math

import pymunk

from weblab_sim import floor

STEP = 0.02  # s
MASS_KG = 4.0
SIZE_MM = (300.0, 260.0)
MAX_WHEEL_MM_S = 300.0
MAX_FORCE = 4.0 * 3000.0  # kg * mm/s^2: about 0.3 g of traction
MAX_TORQUE = 4.0e6


class Robot:
    """The robot's body in its own space; ``command(v, omega)`` sets the wanted motion (mm/s, rad/s)."""

    def __init__(self, x: float, y: float, heading: float, wheel_base: float = 330.0) -> None:
        self.wheel_base = wheel_base
        self.space = pymunk.Space()
        self.space.damping = 1.0
        self.control = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
        self.control.position = (x, y)
        self.body = pymunk.Body(MASS_KG, pymunk.moment_for_box(MASS_KG, SIZE_MM))
        self.body.position = (x, y)
        self.body.angle = heading
        shape = pymunk.Poly.create_box(self.body, SIZE_MM, radius=5.0)
        shape.friction = 0.6
        shape.filter = pymunk.ShapeFilter(group=1)  # the sonar's rays ignore the robot itself
        walls = []
        w, h = floor.WIDTH_MM, floor.HEIGHT_MM
        for a, b in (((0, 0), (w, 0)), ((w, 0), (w, h)), ((w, h), (0, h)), ((0, h), (0, 0))):
            seg = pymunk.Segment(self.space.static_body, a, b, 10.0)
            seg.friction = 0.6
            walls.append(seg)
        pivot = pymunk.PivotJoint(self.control, self.body, (0, 0), (0, 0))
        pivot.max_bias = 0.0
        pivot.max_force = MAX_FORCE
        gear = pymunk.GearJoint(self.control, self.body, 0.0, 1.0)
        gear.error_bias = 0.0
        gear.max_bias = 0.0
        gear.max_force = MAX_TORQUE
        self.space.add(self.control, self.body, shape, pivot, gear, *walls)
        self.t = 0.0  # the physics grid's time
        self.wanted = (0.0, 0.0)  # (v, omega) in force now
        self.pending: list[tuple[float, float, float]] = []  # (time, v, omega), time-ordered
        self.distance = 0.0  # mm travelled (odometry, both directions)

    def command(self, now: float, v: float, omega: float) -> None:
        """Wanted forward speed (mm/s) and turn rate (rad/s) from time ``now``, wheel-limited."""
        half = omega * self.wheel_base / 2.0
        worst = max(abs(v - half), abs(v + half))
        if worst > MAX_WHEEL_MM_S:
            scale = MAX_WHEEL_MM_S / worst
            v, omega = v * scale, omega * scale
        self.advance(now)
        self.pending.append((now, v, omega))

    def advance(self, now: float) -> None:
        """Run the physics grid up to the last step at or before ``now``."""
        while self.t + STEP <= now + 1e-12:
            self._step()

    def _step(self) -> None:
        end = self.t + STEP
        # The motion wanted over [t, end): commands in force, weighted by how long each is.
        v_sum = w_sum = 0.0
        at, (v, w) = self.t, self.wanted
        while self.pending and self.pending[0][0] < end:
            when, nv, nw = self.pending.pop(0)
            span = max(0.0, when - at)
            v_sum += v * span
            w_sum += w * span
            at, v, w = max(at, when), nv, nw
        v_sum += v * (end - at)
        w_sum += w * (end - at)
        self.wanted = (v, w)
        v_mean, w_mean = v_sum / STEP, w_sum / STEP
        angle = self.body.angle
        self.control.velocity = (v_mean * math.cos(angle), v_mean * math.sin(angle))
        self.control.angular_velocity = w_mean
        before = self.body.position
        self.space.step(STEP)
        self.distance += (self.body.position - before).length
        self.t = end

    def pose(self, now: float) -> tuple[float, float, float]:
        """(x mm, y mm, heading rad) at ``now``: the grid's last state, extrapolated."""
        self.advance(now)
        dt = now - self.t
        p, vel = self.body.position, self.body.velocity
        return p.x + vel.x * dt, p.y + vel.y * dt, self.body.angle + self.body.angular_velocity * dt

    def speed(self) -> float:
        """Forward speed now (mm/s, negative backwards), at the grid's last state."""
        angle = self.body.angle
        vel = self.body.velocity
        return vel.x * math.cos(angle) + vel.y * math.sin(angle)

    def place(self, now: float, x: float, y: float, heading: float) -> None:
        """Put the robot down at (x, y) facing ``heading``, at rest (a human carrying it)."""
        self.advance(now)
        self.pending.clear()
        self.wanted = (0.0, 0.0)
        for body in (self.body, self.control):
            body.velocity = (0.0, 0.0)
            body.angular_velocity = 0.0
        self.body.position = (x, y)
        self.body.angle = heading
        self.control.position = (x, y)
        self.space.reindex_shapes_for_body(self.body)

    def sonar(self, now: float, bearings_deg: tuple[float, ...], max_range: float) -> list[float]:
        """Ranges (mm) to the walls along each bearing from the robot's centre, at most ``max_range``."""
        x, y, heading = self.pose(now)
        ranges = []
        for b in bearings_deg:
            a = heading + math.radians(b)
            end = (x + max_range * math.cos(a), y + max_range * math.sin(a))
            hit = self.space.segment_query_first((x, y), end, 0.0, pymunk.ShapeFilter(group=1))
            ranges.append(max_range if hit is None else hit.alpha * max_range)
        return ranges
