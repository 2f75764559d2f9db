"""The simulated lab: floor, robot, cameras, sensors and users, on the runtime's clock.

Components reach the simulator through one explicit hook: :func:`current` returns the installed
:class:`World` (the experiment installs one per run with :func:`install`); a component started
without one (a container run on its own) gets a default world on its own clock
(:attr:`World.standalone`; on a real clock in live mode, where the physics advances to the clock's
time when someone looks, and sleeps are real). Everything happens in the clock's time; randomness comes from ``clock.rng(purpose)``, one stream per purpose
(start pose, motors, camera noise), so a run is deterministic for the clock's seed.
"""

from __future__ import annotations

import copy
import math
import threading
from dataclasses import dataclass, field

import numpy as np

from acordcs.runtime.api import Clock
from weblab_sim import camera, floor
from weblab_sim.network import Profile, profile
from weblab_sim.robot import Robot

SONAR_BEARINGS = (0.0, 45.0, -45.0, 90.0, -90.0, 180.0)
SONAR_RANGE_MM = 3000.0
BATTERY_FULL_V = 12.6
SAMPLE_PERIOD = 0.1  # s between trajectory samples (and finish-line checks)
PLACE_AHEAD_MM = 50.0  # how far past the farthest point reached the person puts the robot
HUMAN_DELAY = 10.0  # s a person takes to walk over and put the robot back on the stripe
MOTOR_SPEED_SIGMA = 0.03  # relative error of the speed the wheels give
MOTOR_TURN_SIGMA = 0.02  # rad/s error of the turn rate
ON_STRIPE_MM = 150.0  # the robot's centre this close to the centre line: it is on the stripe
AHEAD_MM = (
    400.0  # a stripe point farther than this past the farthest point reached: another segment
)
SLIP_MM = 100.0  # a change of the nearest point's arc length in one sample this big: a jump
STOP_MM = 40.0  # driven back along the stripe this far, the lab stops the robot


@dataclass
class Sample:
    t: float
    x: float
    y: float
    heading: float
    distance: float
    speed: float  # the commanded forward speed, mm/s
    progress: float = 0.0  # how far along the stripe the robot has got, mm


@dataclass
class Script:
    """Scripted disturbances: user-count spikes ``(start, end, extra users)``, times at which a
    malformed telemetry reading is published, and times from which the next recovery action
    fails (raises: a faulty policy action)."""

    user_spikes: list[tuple[float, float, int]] = field(default_factory=list)
    malformed_telemetry: list[float] = field(default_factory=list)
    failing_recoveries: list[float] = field(default_factory=list)


class World:
    """One run's lab. ``profile``: the user's network (its grab and CPU times are used here);
    ``path``: the stripe on the floor (:data:`weblab_sim.floor.PATHS`)."""

    def __init__(
        self,
        clock: Clock,
        net: Profile | None = None,
        script: Script | None = None,
        path: str = floor.DEFAULT_PATH,
    ) -> None:
        self.clock = clock
        self.standalone = False  # True for the default world of a container run on its own
        # On a real clock the robot is touched from several threads at once (remote calls, the
        # clock's timers): the physics advances under this lock. Uncontended on a virtual clock.
        self._lock = threading.RLock()
        self.profile = net or profile("LAN")
        self.script = copy.deepcopy(script) if script is not None else Script()  # consumed
        self.path_name = path
        self.path = floor.make_path(path)
        rng = clock.rng("start")
        x, y = floor.START
        y += float(rng.uniform(-15.0, 15.0))
        heading = floor.START_HEADING + math.radians(float(rng.uniform(-3.0, 3.0)))
        self.robot = Robot(x, y, heading)
        self.samples: list[Sample] = []
        # the samples' times, distances and progress, as arrays (rebuilt when samples were added)
        self._arrays: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.commanded = 0.0
        self.progress = 0.0  # arc length along the stripe reached so far, mm
        # Driving the stripe backwards (mm): see _track_backwards.
        self.backwards_mm = 0.0
        # set by the lab's safety stop, cleared once a telemetry reading has said so
        self.stopped_backwards = False
        self._driven = self._driven_peak = 0.0
        self._last_along: float | None = None
        self._receding = False
        self.done = False
        self.finish_time: float | None = None
        self.sessions: set[str] = set()
        self.placements = 0
        self._timer = clock.call_every(SAMPLE_PERIOD, self._sample, start=clock.now())

    # ------------------------------------------------------------------------------ robot
    def drive(self, speed: float, turn_rate: float) -> None:
        """Command the wheels: forward ``speed`` mm/s and ``turn_rate`` rad/s, from now."""
        with self._lock:
            rng = self.clock.rng("motor")
            err_v, err_w = rng.normal(0.0, MOTOR_SPEED_SIGMA), rng.normal(0.0, MOTOR_TURN_SIGMA)
            moving = speed != 0.0 or turn_rate != 0.0
            self.robot.command(
                self.clock.now(),
                speed * (1.0 + err_v),
                turn_rate + (err_w if moving else 0.0),
            )
            self.commanded = speed

    def pose(self) -> tuple[float, float, float]:
        with self._lock:
            return self.robot.pose(self.clock.now())

    def grab_frame(self) -> np.ndarray:
        """The on-board camera's frame now."""
        return camera.render(*self.pose(), noise=self.clock.rng("camera"), path=self.path_name)

    def place_on_stripe(self) -> None:
        """A person puts the robot back on the stripe, a little past the farthest point it reached,
        facing along it; just past the next corner if that is nearer than the camera sees."""
        s = self.progress + PLACE_AHEAD_MM
        corner = next((c for c in self.path.corners() if c >= s), None)
        if corner is not None and corner - s < camera.NEAR_MM + PLACE_AHEAD_MM:
            s = corner + PLACE_AHEAD_MM
        x, y, heading = self.path.pose_at(s)
        with self._lock:
            self.robot.place(self.clock.now(), x, y, heading)
            self.commanded = 0.0
            self._driven_peak = self._driven  # carried: a fresh start
            self._last_along = None
            self.placements += 1

    # --------------------------------------------------------------------------- sensors
    def telemetry(self) -> dict[str, float]:
        """Position, heading, sonar ranges, battery voltage and progress along the stripe now (the
        Telemetry monitor's fields); when the robot is on the stripe, also ``along`` (mm, the arc
        length of the stripe's point nearest the robot) and ``stripeHeading`` (degrees, the way
        the stripe runs there)."""
        with self._lock:
            now = self.clock.now()
            x, y, heading = self.robot.pose(now)
            ranges = self.robot.sonar(now, SONAR_BEARINGS, SONAR_RANGE_MM)
        volts = BATTERY_FULL_V - 0.002 * now - 0.05 * self.robot.distance / 1000.0
        noise = self.clock.rng("telemetry").normal(0.0, 0.01)
        reading = {
            "positionX": x,
            "positionY": y,
            "heading": math.degrees(heading),
            "sonarRange": min(ranges),
            "batteryVoltage": volts + noise,
            "progress": self.progress,
        }
        reading.update(self._where(x, y))
        if self.stopped_backwards:
            reading["stoppedBackwards"] = 1.0
        return reading

    def on_stripe(self) -> dict[str, float]:
        """The robot's heading and progress now, and :meth:`telemetry`'s ``along`` and
        ``stripeHeading`` when it is on the stripe (what the lab's safety stop looks at)."""
        with self._lock:
            x, y, heading = self.robot.pose(self.clock.now())
        return {"heading": math.degrees(heading), "progress": self.progress, **self._where(x, y)}

    def _where(self, x: float, y: float) -> dict[str, float]:
        # Where on the stripe the lab sees the robot, and which way the stripe runs there: the
        # lab knows its floor (its panoramic camera watches the robot), the user does not.
        dist, along, direction = self.path.nearest(x, y)
        if dist >= ON_STRIPE_MM:
            return {}
        return {"along": along, "stripeHeading": direction}

    def telemetry_reading(self) -> dict[str, object]:
        """The reading the Locomotion publishes now: :meth:`telemetry`, or a malformed one (a
        sensor's garbage) when the script has one due."""
        if self.malformed_due():
            return {"positionX": "n/a", "batteryVoltage": "", "heading": "NaN"}
        return dict(self.telemetry())

    def malformed_due(self) -> bool:
        """True when the script has a malformed telemetry reading due now (within 0.25 s)."""
        now = self.clock.now()
        return any(abs(now - t) < 0.25 for t in self.script.malformed_telemetry)

    def recovery_fails(self) -> bool:
        """True (once per scripted time already reached) when a recovery action should fail now."""
        now = self.clock.now()
        due = [t for t in self.script.failing_recoveries if t <= now]
        if due:
            self.script.failing_recoveries.remove(due[0])
        return bool(due)

    def users(self) -> int:
        """Users of the experiment now: the authenticated sessions plus any scripted spike."""
        now = self.clock.now()
        extra = sum(n for start, end, n in self.script.user_spikes if start <= now < end)
        return len(self.sessions) + extra

    # ---------------------------------------------------------------------------- progress
    def _sample(self) -> None:
        with self._lock:
            now = self.clock.now()
            x, y, heading = self.robot.pose(now)
        dist, s = self.path.closest(x, y)
        # Progress only along the stripe near where the robot is: a nearby other segment must
        # not count as reached.
        if dist < ON_STRIPE_MM and s <= self.progress + AHEAD_MM:
            self.progress = max(self.progress, s)
        self._track_backwards(dist, s)
        self.samples.append(
            Sample(now, x, y, heading, self.robot.distance, self.commanded, self.progress)
        )
        # The finish counts for a robot that got to the last stretch along the stripe, not for
        # one that took a short cut over to it.
        reached = self.progress >= self.path.length - AHEAD_MM
        if not self.done and reached and self.path.crossed_finish(x, y):
            self.done = True
            self.finish_time = now

    def _track_backwards(self, dist: float, s: float) -> None:
        """How far the robot drove the stripe backwards: the change of its place along the stripe
        summed over the samples in which it drove forward under the user's control, on the stripe
        (backing up, standing, jumps between two parts of the stripe and carrying do not count),
        and the most that sum fell below its peak."""
        last, self._last_along = self._last_along, (s if dist < ON_STRIPE_MM else None)
        self._receding = False
        if self._last_along is None or last is None or abs(s - last) > SLIP_MM:
            return
        if self.commanded <= 0.0:
            return
        self._driven += s - last
        self._driven_peak = max(self._driven_peak, self._driven)
        self.backwards_mm = max(self.backwards_mm, self._driven_peak - self._driven)
        self._receding = s < last

    def driving_backwards(self) -> bool:
        """True when the robot, driven forward, is moving back along the stripe and has already
        fallen :data:`STOP_MM` below the farthest it had driven (the lab's safety stop), or is
        on the stripe more than :data:`AHEAD_MM` past the farthest point reached."""
        if self.commanded <= 0.0:
            return False
        if self._receding and self._driven_peak - self._driven > STOP_MM:
            return True
        return self._last_along is not None and self._last_along > self.progress + AHEAD_MM

    def distance_at(self, t: float) -> float:
        """Distance travelled by time ``t`` (interpolated between samples)."""
        if not self.samples:
            return 0.0
        times, distances, _ = self._sampled()
        return float(np.interp(t, times, distances))

    def progress_at(self, t: float) -> float:
        """How far along the stripe the robot had got by time ``t`` (the last sample before)."""
        if not self.samples:
            return 0.0
        times, _, progress = self._sampled()
        return float(progress[max(0, int(np.searchsorted(times, t, side="right")) - 1)])

    def _sampled(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        if self._arrays is None or len(self._arrays[0]) != len(self.samples):
            self._arrays = (
                np.array([s.t for s in self.samples]),
                np.array([s.distance for s in self.samples]),
                np.array([s.progress for s in self.samples]),
            )
        return self._arrays

    def close(self) -> None:
        self._timer.cancel()


_current: World | None = None


def install(world: World | None) -> None:
    """Make ``world`` the one components find (None: none)."""
    global _current
    _current = world


def current(clock: Clock | None = None) -> World:
    """The installed world; without one, a default world on ``clock`` is installed and returned."""
    global _current
    if _current is None:
        if clock is None:
            raise RuntimeError(
                "no simulated WebLab is installed: call weblab_sim.world.install(World(clock))"
            )
        _current = World(clock)
        _current.standalone = True
    return _current


def installed() -> World | None:
    """The installed world, or None (then :func:`current` would make a default one)."""
    return _current
