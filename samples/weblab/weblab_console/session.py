"""The WebLab's panel over the experiment run in this process (``make console``): one experiment at
a time, run in a background thread and shown through the hub (a
:class:`acordcs.console.panels.PanelSession`; what it publishes is made by
:mod:`weblab_console.showing`, as for the panel over the two-process application). The console's
page around it watches the running experiment's containers through :mod:`.in_process`.

The experiment is :func:`weblab_sim.experiment.rig`: the generated application assembled in one
process on a :class:`~acordcs.runtime.clock.VirtualClock`. A pacing timer on that clock (every
:data:`PACE` simulated seconds) keeps it to ``speed`` times real time (``speed=0``: as fast as
it runs), serves the requests of viewers (everything that touches the application runs on the
experiment's thread) and publishes, at most :data:`PUBLISH_HZ` times per wall second: the robot's
state and the WebLab's events (recoveries, user requests, stripe losses, the finish); the
Navigator's last on-board frame with the detected stripe drawn, and a panoramic picture for each
frame the panoramic camera sends (so at the rate the bandwidth policy sets).

Manual control (:meth:`ConsoleSession.drive`) pauses the Navigator between cycles; the speed and
turn go to Locomotion through the Navigator's own port, so the Control monitor and the policies
see them as they see the Navigator's (a speed of 0 is a stop, which the Recovering policy answers
as it answers the Navigator's). :meth:`release` hands control back.

Who may drive: a viewer holding the console's token (the console checks it; the page's
commands that change the experiment need it).
"""

from __future__ import annotations

import concurrent.futures
import logging
import math
import secrets
import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

from weblab_sim import experiment, world
from weblab_sim.network import PROFILES

from acordcs.console.fanout import ConsoleHub
from weblab_console import pictures
from weblab_console.in_process import InProcess, weblab_descriptor
from weblab_console.showing import FRAME_HZ, PUBLISH_HZ, Showing

log = logging.getLogger("weblab.console")

PACE = 0.05  # simulated seconds between pacing ticks
MANUAL_PERIOD = 0.2  # simulated seconds the Navigator waits between looks while paused
MANUAL_RESEND = 1.0  # simulated seconds between repeats of a manual forward move
TIME_CAP = 900.0  # simulated seconds before a run is ended (the finish is usually at 100-250)
REQUEST_TIMEOUT = 5.0  # wall seconds a viewer's request may wait for the experiment's thread


class SessionError(RuntimeError):
    """A request the session cannot carry out now; ``str()`` says why and what to do."""


class ConsoleSession:
    """Runs experiments for the console, whose page watches them through ``in_process``;
    ``token`` is the one the console's link carries."""

    mode = "simulation"
    profiles: tuple[str, ...] = tuple(PROFILES)

    def __init__(
        self, hub: ConsoleHub, token: str, *, speed: float = 1.0, time_cap: float = TIME_CAP
    ) -> None:
        if not speed >= 0 or not math.isfinite(speed):
            raise ValueError(f"speed must be a finite factor >= 0 (0: unthrottled), not {speed}")
        self.hub = hub
        self.token = token
        self.in_process = InProcess(weblab_descriptor())
        self.speed = float(speed)
        self.time_cap = time_cap
        self._lock = threading.Lock()
        self._thread: threading.Thread | None = None
        self._run: _Run | None = None
        hub.publish("path", pictures.path())

    # ------------------------------------------------------------------ server.Session
    def describe(self) -> dict[str, Any]:
        """What a viewer is told first and the console's ``/status`` shows."""
        return {"profiles": list(self.profiles), "mode": self.mode}

    def authorize(self, token: str) -> bool:
        return secrets.compare_digest(token.encode(), self.token.encode())

    def calls(self) -> dict[str, list[str]]:
        return {}  # what it shows it reads from the experiment itself

    def begin(self) -> None:
        pass

    def deliver(self, kind: str, container: str, data: Any) -> None:
        pass  # the console's page shows what the watches say

    def start(self, profile: str, seed: int) -> None:
        if profile not in self.profiles:
            raise SessionError(f"no network profile {profile!r}: one of {', '.join(self.profiles)}")
        self.stop()
        with self._lock:
            run = _Run(self, profile, int(seed))
            self._run = run
            self._thread = threading.Thread(target=run.main, name="weblab-experiment", daemon=True)
            self._thread.start()
        if not run.ready.wait(30.0):
            raise SessionError("the experiment did not start within 30 s")
        if run.failure is not None:
            raise SessionError(f"the experiment could not start: {run.failure}")

    def stop(self) -> None:
        """Stop the running experiment (if any) and wait for its thread."""
        with self._lock:
            run, thread = self._run, self._thread
        if run is None or thread is None:
            return
        run.stopping = True
        run.wake.set()
        thread.join(30.0)
        if thread.is_alive():  # never expected: the run races to its end once stopping
            log.error("the experiment's thread did not stop within 30 s")

    def drive(self, speed: float, turn: float) -> None:
        run = self._running()
        run.manual = (float(speed), float(turn))
        run.wake.set()

    def release(self) -> None:
        run = self._running()
        run.manual = None
        run.wake.set()

    def set_speed(self, speed: float) -> None:
        """Change the speed factor (0: unthrottled), also for the running experiment."""
        self.speed = float(speed)
        run = self._current()
        if run is not None:
            run.anchor()

    @property
    def sim_time(self) -> float:
        """The simulated time of the running (or the last) experiment, seconds; 0 before any."""
        run = self._current()
        return run.rig.clock.now() if run is not None and run.rig is not None else 0.0

    @property
    def application(self) -> Any:
        """The running experiment's application (a ``RunningApplication``), or None."""
        run = self._current()
        return run.rig.app if run is not None and run.rig is not None and not run.ended else None

    @property
    def running(self) -> bool:
        run = self._current()
        return run is not None and not run.ended

    def close(self) -> None:
        self.stop()

    # -------------------------------------------------------------------------- internals
    def _current(self) -> _Run | None:
        with self._lock:
            return self._run

    def _running(self) -> _Run:
        run = self._current()
        if run is None or run.ended:
            raise SessionError("no experiment is running: start one first")
        return run


class _Run:
    """One experiment on its own thread (:meth:`main`), and what it has shown so far."""

    def __init__(self, session: ConsoleSession, profile: str, seed: int) -> None:
        self.session = session
        self.show = Showing(session.hub, profile, seed)
        self.profile = profile
        self.seed = seed
        self.stopping = False
        self.ended = False
        self.failure: str | None = None
        self.ready = threading.Event()
        self.wake = threading.Event()
        self.manual: tuple[float, float] | None = None
        self.applied: tuple[float, float] | None = None
        self.sent_at = 0.0
        self.requests: deque[tuple[Callable[[], Any], concurrent.futures.Future]] = deque()
        self.rig: Any = None
        self.frames_shown = -1
        self.panorama_shown = 0
        self.sim0 = self.wall0 = 0.0

    # ------------------------------------------------------------------ viewers' side
    def request(self, fn: Callable[[], Any]) -> Any:
        """Run ``fn`` on the experiment's thread and return its result (SessionError: ended)."""
        if self.ended:
            raise SessionError("the experiment has ended")
        future: concurrent.futures.Future = concurrent.futures.Future()
        self.requests.append((fn, future))
        self.wake.set()
        try:
            return future.result(REQUEST_TIMEOUT)
        except concurrent.futures.TimeoutError:
            raise SessionError("the experiment did not answer in time; try again") from None

    def anchor(self) -> None:
        """Pace from now on: the current simulated time matches the current wall time."""
        self.wall0 = time.perf_counter()
        self.sim0 = self.rig.clock.now() if self.rig is not None else 0.0

    # --------------------------------------------------------------- experiment's side
    def main(self) -> None:
        try:
            with experiment.rig(self.profile, self.seed, time_cap=self.session.time_cap) as r:
                self.rig = r
                self.session.in_process.running(r.app.containers, self.request)
                try:
                    r.clock.call_every(PACE, self._pace, start=0.0)
                    self.anchor()
                    self._event("start", f"{self.profile} network, seed {self.seed}")
                    self.ready.set()
                    self._drive(r)
                    self._publish(force=True)
                finally:
                    self.ended = True
                    self._fail_requests()
                    self.session.in_process.ended()
                lab = r.lab
                if lab.finish_time is not None:
                    self._event("finish", f"finish line crossed at {lab.finish_time:.1f} s")
                elif self.stopping:
                    self._event("stop", "stopped from the console")
                else:
                    self._event("stop", f"time cap of {self.session.time_cap:.0f} s reached")
        except Exception as exc:  # the experiment failing is shown, never a crash of the server
            log.exception("the experiment failed")
            self.failure = f"{type(exc).__name__}: {exc}"
            self._event("fault", f"the experiment stopped: {self.failure}")
        finally:
            self.ended = True
            self.ready.set()
            self._fail_requests()
            self.show.stopped()  # the application is closed now: the last state, not running

    def _drive(self, r: Any) -> None:
        """The Navigator's loop (as its ``run``), paused while a viewer drives."""
        nav = r.navigator.instance
        r.navigator.port("NavAccessPort").call("authenticate", "navigator", "token")
        locomotion = nav.port("NavLocomotionPort")
        while not r.lab.done and not self.stopping:
            manual = self.manual
            if manual is None:
                if self.applied is not None:
                    self.applied = None
                    self._event("driver", "control handed back to the Navigator")
                nav.step()
                continue
            now = r.clock.now()
            speed, turn = manual
            # A change is sent at once; a forward move again every MANUAL_RESEND s, a control
            # cycle as the policies know it (a stop is sent once: each one is a retry to them).
            if manual != self.applied or (speed > 0 and now - self.sent_at >= MANUAL_RESEND):
                if self.applied is None:
                    self._event("driver", "manual control taken")
                self.applied, self.sent_at = manual, now
                if speed > 0:
                    locomotion.call("move", speed, turn)
                else:
                    locomotion.call("stop")
            r.clock.sleep(MANUAL_PERIOD)

    def _pace(self) -> None:
        """Every PACE simulated seconds: serve requests, keep to real time, publish."""
        self._serve()
        if self.stopping:
            self.rig.lab.done = True
            return
        speed = self.session.speed
        if speed > 0:
            while True:
                ahead = (
                    self.wall0 + (self.rig.clock.now() - self.sim0) / speed - time.perf_counter()
                )
                if ahead <= 0 or self.stopping:
                    break
                self.wake.wait(min(ahead, 0.05))
                self.wake.clear()
                self._serve()
            if ahead < -1.0:  # far behind (a slow step): do not burst to catch up
                self.anchor()
        self._publish()

    def _serve(self) -> None:
        while self.requests:
            fn, future = self.requests.popleft()
            try:
                future.set_result(fn())
            except Exception as exc:
                future.set_exception(exc)

    def _fail_requests(self) -> None:
        while self.requests:
            _fn, future = self.requests.popleft()
            future.set_exception(SessionError("the experiment has ended"))

    # ---------------------------------------------------------------------- publishing
    def _publish(self, *, force: bool = False) -> None:
        show = self.show
        for channel, publish in (
            ("frame:onboard", self._publish_onboard),
            ("frame:panoramic", self._publish_panorama),
        ):
            if show.due(channel, force=force) and publish():
                show.sent(channel, FRAME_HZ)
        if not show.due("state", force=force):
            return
        show.sent("state", PUBLISH_HZ)
        r = self.rig
        lab, now = r.lab, r.clock.now()
        x, y, heading = lab.robot.pose(now)
        ranges = lab.robot.sonar(now, world.SONAR_BEARINGS, world.SONAR_RANGE_MM)
        show.state(
            t=now,
            pose=(x, y, heading),
            sonar=zip(world.SONAR_BEARINGS, ranges, strict=True),
            speed=lab.commanded,
            fps=int(r.weblab.get_property("PanoramicCamera", "fps")),
            driver="manual" if self.manual is not None else "navigator",
            running=not self.ended,
            progress=lab.progress / lab.path.length * 100.0,
        )
        self._publish_events()

    def _publish_events(self) -> None:
        r = self.rig
        nav, recovery = r.navigator.instance, r.recovery.instance
        counts = {
            "recovery": int(recovery.actions),
            "user_request": int(recovery.user_requests),
            "stripe_loss": int(nav.losses),
        }
        self.show.counted(r.clock.now(), counts)

    def _event(self, kind: str, text: str) -> None:
        self.show.event(self.rig.clock.now() if self.rig is not None else 0.0, kind, text)

    def _publish_onboard(self) -> bool:
        nav = self.rig.navigator.instance
        frames = len(nav.cycles)
        if nav.last_frame is None or frames == self.frames_shown:
            return False
        self.frames_shown = frames
        self.show.hub.publish(
            "frame:onboard", pictures.onboard(bytes(nav.last_frame), nav.last_turn)
        )
        return True

    def _publish_panorama(self) -> bool:
        sent = int(self.rig.weblab.find("PanoramicCamera").instance.sent)
        if sent == self.panorama_shown:
            return False
        self.panorama_shown = sent
        x, y, heading = self.rig.lab.pose()
        self.show.hub.publish("frame:panoramic", pictures.panoramic(x, y, heading, self.show.trail))
        return True
