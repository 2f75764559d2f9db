"""The WebLab's panel over the two-process application (``make live-console``), on the console of
:mod:`acordcs.console.live_session`, which attaches to the running containers and watches them
(the architecture, context, policies, faults and hands are its page's); this panel shows the
cameras, the map and the robot's state, and lets viewers holding the token drive the robot (a
:class:`acordcs.console.panels.PanelSession`).

Nothing runs in this process but the console. The console's watches give this panel what the
containers' observers say (:mod:`acordcs.runtime.live.observer`, with the application's token):
the properties the policies set, and the calls of a few operations it asks for: the frames
``Vision.grab`` returns to the Navigator (the on-board camera, with the stripe the console's
detector finds in it, as the Navigator's does), ``Recovery.recover`` and ``askUser`` (recoveries and
user requests), the Navigator's ``Locomotion.move`` and ``stop`` (a stop after a move is a stripe
loss). The robot's pose, progress and finish come from ``Locomotion.odometry()``, called ten times a
second as any client of the WebLab would; the map's sonar rays are drawn from that pose (the room's
walls are fixed); the panoramic picture is drawn at the frame rate the Bandwidth limiting policy
sets (``PanoramicCamera.fps``: its stream goes to the user's process).

Driving: a viewer holding the token takes control; the console then holds the Vision component
(the management interface's ``hold``, renewed while it drives), so that the Navigator of the other
process waits for its next image, between two of its cycles, and sends the viewer's speed and turn
to ``Locomotion.move`` (``stop`` for a speed of 0) through its port, as the Navigator does: the
Control monitor and the policies see them as the Navigator's. Handing back releases the hold.
The hold keeps a call waiting at most 0.75 of the containers' remote-call timeout
(``ACORDCS_TIMEOUT``: 30 s in ``make live-console``); a viewer driving longer lets one cycle of the
Navigator through, then holds it again.

Who may drive is the application's decision, as in the simulation: the console reserves the user
``console`` in the Access component with its token, and asks ``Access.authenticate("console",
token)``. The application's processes are started and stopped by their scripts: Start and Stop are
refused here.
"""

from __future__ import annotations

import functools
import json
import math
import threading
import time
from collections import deque
from typing import Any

from weblab_sim import detector, floor, world
from weblab_sim.robot import Robot

from acordcs.console.attaching import AttachError
from acordcs.console.panels import PanelContext
from acordcs.runtime.connectors.remote import bytes_back
from acordcs.runtime.errors import RuntimeFailure
from weblab_console import pictures
from weblab_console.showing import FRAME_HZ, PUBLISH_HZ, Showing

MODE = "attached"
PROFILE = "two processes"
CONSOLE_USER = "console"
CALLS = [
    "Vision.grab",
    "Recovery.recover",
    "Recovery.askUser",
    "Locomotion.move",
    "Locomotion.stop",
]
TIMEOUT = 30.0  # seconds a call may take: a stop answered by a recovery takes several
JOIN = 35.0  # seconds the panel's threads may take to stop (a call in flight: TIMEOUT)
HOLD_SECONDS = 6.0  # a hold lasts this long unless renewed
HOLD_RENEW = 0.5  # seconds between renewals while a viewer drives (each says what waits)
MANUAL_RESEND = 1.0  # seconds between repeats of a manual forward move (a control cycle)
TICK = 1.0 / FRAME_HZ


HOW_TO_START = (
    "start the application first (make live-console starts it with the console; its "
    "bin/start-all, with the same ACORDCS_RUN_DIR and ports, without)"
)


class SessionError(RuntimeError):
    """A request the session cannot carry out; ``str()`` says why and what to do."""


class AttachedPanel:
    """The WebLab's panel over the application the console attached to (``context``: its hub,
    the console's token, the application)."""

    mode = MODE
    profiles: tuple[str, ...] = (PROFILE,)

    def __init__(self, context: PanelContext) -> None:
        self.hub = context.hub
        self.token = context.token
        self.app = context.app
        self.lab = self.app.host_of.get("Locomotion")
        if self.lab is None or "Vision" not in self.app.host_of:
            raise AttachError(
                f"{self.app.name}: not the WebLab application (no Locomotion or Vision)"
            )
        self.show = Showing(self.hub, PROFILE, 0)
        self.hub.publish("path", pictures.path())
        self.closing = threading.Event()
        self.wake = threading.Event()  # the loop's
        self.steer = threading.Event()  # the driver's: a viewer's command
        self.inbox: deque[tuple[str, str, Any]] = deque()
        self.mirror: dict[str, dict[str, Any]] = {}
        self.counts = {"recovery": 0, "user_request": 0, "stripe_loss": 0}
        self.faults = self.faults_shown = 0
        self.last_fault = "fault"
        self.reachable = False  # the lab's container, as its watch last said
        self.clock = (0.0, time.monotonic())  # the lab's clock time, when it was read
        self.pose: dict[str, Any] | None = None
        self.read_at = 0.0  # time.monotonic() of the last odometry
        self.speed = 0.0  # mm/s, from the last two odometry readings
        self.frame: bytes | None = None
        self.frame_new = False
        self.look_ahead = 300.0
        self.forward = False  # the Navigator's last locomotion call was a forward move
        self.finished = False
        self.manual: tuple[float, float] | None = None
        self.driving: tuple[float, float] | None = None  # what the driver last sent
        self.held = 0  # calls of the Navigator waiting at the held Vision component
        self.held_at = 0.0  # time.monotonic() of the last hold (0: not held)
        self.sonar = Robot(0.0, 0.0, 0.0)  # a model of the robot among the room's walls
        self.threads: list[threading.Thread] = []

    # ------------------------------------------------------------------------ the panel
    def calls(self) -> dict[str, list[str]]:
        return {self.lab: list(CALLS)}

    def begin(self) -> None:
        """Reserve the console's user (AttachError: the Access component refuses) and run."""
        try:
            self.app.call("Access", "AccessPort", "reserve", CONSOLE_USER, self.token)
        except RuntimeFailure as err:
            raise AttachError(f"the Access component refused the console: {err.message}") from None
        self._take()  # the snapshots: the lab's clock and seed
        self.show.event(
            self.sim_time, "start", f"attached to {self.app.name}: {self.app.describe()}"
        )
        self.threads = [
            threading.Thread(target=self._loop, name="weblab-console-attached", daemon=True),
            threading.Thread(target=self._reader, name="weblab-console-odometry", daemon=True),
            threading.Thread(target=self._driver, name="weblab-console-driver", daemon=True),
        ]
        for thread in self.threads:
            thread.start()

    def describe(self) -> dict[str, Any]:
        """What a viewer is told first (the page's ``hello``)."""
        return {"profiles": list(self.profiles), "mode": self.mode}

    def start(self, profile: str, seed: int) -> None:
        raise SessionError(
            "the console is attached to the application its scripts started: stop it with "
            "Ctrl-C where make live-console runs, or with its bin/stop-all"
        )

    def stop(self) -> None:
        self.start("", 0)

    def drive(self, speed: float, turn: float) -> None:
        if not self.reachable:
            raise SessionError(f"container {self.lab} does not answer: the robot cannot be driven")
        self.manual = (float(speed), float(turn))
        self.steer.set()
        self.wake.set()

    def release(self) -> None:
        self.manual = None
        self.steer.set()
        self.wake.set()

    @property
    def sim_time(self) -> float:
        """The lab container's clock now (seconds since it started)."""
        t, at = self.clock
        return t + (time.monotonic() - at)

    def close(self) -> None:
        self.closing.set()
        self.wake.set()
        self.steer.set()
        for thread in self.threads:
            thread.join(JOIN)

    # -------------------------------------------------------------- what the containers say
    def deliver(self, kind: str, container: str, data: Any) -> None:  # watchers' threads
        if container == self.lab:
            self.reachable = kind != "down"
        self.inbox.append((kind, container, data))

    def _take(self) -> None:
        while self.inbox:
            kind, container, data = self.inbox.popleft()
            if kind == "snapshot":
                for element, values in data["elements"].items():
                    self.mirror[element] = dict(values)
                if container == self.lab:
                    self.clock = (data["time"], time.monotonic())
                    self.show.seed = data["seed"]
                self.look_ahead = float(
                    self.mirror.get("Navigator", {}).get("lookAhead", self.look_ahead)
                )
            elif kind == "events":
                if container == self.lab:
                    self.clock = (data["time"], time.monotonic())
                for event in data["events"]:
                    self._event(event)

    def _event(self, event: dict[str, Any]) -> None:
        kind, element, attribute = event["kind"], event["element"], event["attribute"]
        if kind == "property.changed":
            self.mirror.setdefault(element, {})[attribute] = event["value"]
        elif kind == "monitor.updated":
            self.mirror.setdefault(element, {}).update(event["values"])
        elif kind == "operation.called":
            self._call(element, attribute, event)

    def _call(self, component: str, operation: str, event: dict[str, Any]) -> None:
        if event["error"] is not None:
            return
        if (component, operation) == ("Vision", "grab"):
            frame = bytes_back(event["value"])
            if isinstance(frame, bytes):
                self.frame, self.frame_new = frame, True
        elif component == "Recovery":
            key = "recovery" if operation == "recover" else "user_request"
            self.counts[key] += 1
        elif component == "Locomotion" and event["origin"] is None and self.manual is None:
            if operation == "move":
                self.forward = float(event["args"][0]) > 0
            elif self.forward:  # the Navigator stopped after a move: it lost the stripe
                self.forward = False
                self.counts["stripe_loss"] += 1

    def _fault(self, text: str) -> None:
        self.faults += 1
        self.last_fault = text

    # -------------------------------------------------------------------------- the loop
    def _loop(self) -> None:
        """Take what the watchers delivered, read the robot's odometry, publish."""
        show = self.show
        while not self.closing.is_set():
            self._take()
            now = self.sim_time
            if show.due("state"):
                show.sent("state", PUBLISH_HZ)
                self._publish_state(now)
            if self.frame_new and show.due("frame:onboard"):
                show.sent("frame:onboard", FRAME_HZ)
                self.frame_new = False
                frame = self.frame or b""
                turn = detector.find_stripe(frame, self.look_ahead)
                self.hub.publish("frame:onboard", pictures.onboard(frame, turn))
            fps = self.mirror.get("PanoramicCamera", {}).get("fps")
            streaming = isinstance(fps, int | float) and fps > 0 and self.pose is not None
            if streaming and show.due("frame:panoramic"):  # at the rate the policy sets
                show.sent("frame:panoramic", min(float(fps), FRAME_HZ))
                x, y, heading = self._xyh()
                self.hub.publish("frame:panoramic", pictures.panoramic(x, y, heading, show.trail))
            self._hold()
            self.wake.wait(TICK)
            self.wake.clear()
        self.manual = None
        self._hold()  # closing while a viewer drives: the Navigator goes on
        show.stopped()

    def _xyh(self) -> tuple[float, float, float]:
        pose = self.pose or {}
        return pose.get("x", 0.0), pose.get("y", 0.0), math.radians(pose.get("heading", 0.0))

    def _reader(self) -> None:
        """Read the robot's odometry :data:`PUBLISH_HZ` times a second, in its own thread: the
        WebLab's process answers it only once the events it is handling are handled (a recovery
        takes seconds), and the console's loop must go on meanwhile."""
        while not self.closing.is_set():
            began = time.monotonic()
            if self.reachable:
                try:
                    pose = json.loads(self.app.call("Locomotion", "LocomotionPort", "odometry"))
                    now = time.monotonic()
                    if self.pose is not None and now > self.read_at:
                        travelled = float(pose["distance"]) - float(self.pose["distance"])
                        self.speed = max(0.0, travelled) / (now - self.read_at)
                    self.pose, self.read_at = pose, now
                except (RuntimeFailure, ValueError, TypeError, KeyError) as err:
                    self._fault(f"fault: odometry: {err}")
            self.closing.wait(max(0.0, began + 1.0 / PUBLISH_HZ - time.monotonic()))

    def _publish_state(self, now: float) -> None:
        show = self.show
        if self.pose is not None:
            x, y, heading = self._xyh()
            self.sonar.place(0.0, x, y, heading)
            ranges = self.sonar.sonar(0.0, world.SONAR_BEARINGS, world.SONAR_RANGE_MM)
            if self.pose.get("finished") and not self.finished:
                self.finished = True
                show.event(now, "finish", f"finish line crossed at about {now:.1f} s")
            fps = self.mirror.get("PanoramicCamera", {}).get("fps", 0)
            show.state(
                t=now,
                pose=(x, y, heading),
                sonar=zip(world.SONAR_BEARINGS, ranges, strict=True),
                speed=self.speed,
                fps=int(fps) if isinstance(fps, int | float) else 0,
                driver="manual" if self.manual is not None else "navigator",
                running=self.reachable,
                progress=float(self.pose.get("progress", 0.0)) / path_length() * 100.0,
                mode=MODE,
                held=self.held,
            )
        show.counted(now, self.counts)
        if self.faults > self.faults_shown:  # the panel's own: odometry, driving, holding
            more = self.faults - self.faults_shown
            self.faults_shown = self.faults
            show.event(now, "fault", self.last_fault + (f" (×{more})" if more > 1 else ""))

    # ------------------------------------------------------------------------ driving
    def _hold(self) -> None:
        """While a viewer drives, hold the Vision component (renewed every :data:`HOLD_RENEW`
        seconds: the reply says whether the Navigator waits); release it once they hand back.
        In the loop's thread: the management interface answers at once, whatever the container
        is busy with."""
        vision = self.app.host_of["Vision"]
        try:
            if self.manual is not None and time.monotonic() - self.held_at >= HOLD_RENEW:
                self.held = int(self.app.manage(vision, "hold", "Vision", HOLD_SECONDS)["waiting"])
                self.held_at = time.monotonic()
            elif self.manual is None and self.held_at:
                self.held, self.held_at = 0, 0.0
                self.app.manage(vision, "release", "Vision")
        except RuntimeFailure as err:
            self._fault(f"fault: holding the Navigator: {err.message}")

    def _driver(self) -> None:
        """Send the viewers' manual control to Locomotion, in its own thread: a stop answered by
        a recovery returns only once the recovery is done."""
        sent_at = 0.0
        while not self.closing.is_set():
            manual = self.manual
            now = time.monotonic()
            try:
                if manual is None:
                    if self.driving is not None:
                        self.driving = None
                        self.show.event(
                            self.sim_time, "driver", "control handed back to the Navigator"
                        )
                elif manual != self.driving or (manual[0] > 0 and now - sent_at >= MANUAL_RESEND):
                    if self.driving is None:
                        self.show.event(self.sim_time, "driver", "manual control taken")
                    self.driving, sent_at = manual, now
                    speed, turn = manual
                    if speed > 0:
                        self.app.call("Locomotion", "LocomotionPort", "move", speed, turn)
                    else:
                        self.app.call("Locomotion", "LocomotionPort", "stop")
            except RuntimeFailure as err:
                self._fault(f"fault: manual control: {err.message}")
                self.closing.wait(1.0)
            self.steer.wait(0.1)
            self.steer.clear()


@functools.cache
def path_length() -> float:
    """The stripe's length (mm): what the odometry's progress is a part of."""
    return float(floor.make_path().length)
