"""A hold on the calls other processes make to a component (the management interface's ``hold``,
:mod:`.management`): an interceptor on the component's calls that makes a call arriving from
another process wait while the hold lasts, ``patience`` seconds at most, then lets it go on.

Only calls that arrive over Pyro5 (a request from another process, :mod:`Pyro5.callcontext` names
its connection) and that no policy set or monitor makes (``call.origin``) wait: a call of the
container's own chain of events is never held, or the container's events would wait with it.
Waiting is in wall seconds, whatever the container's clock.
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from typing import Any

from Pyro5.callcontext import current_context

from acordcs.runtime import events as ev
from acordcs.runtime.interceptors import Interceptor, Invocation

EXPIRY_SLACK = 0.05
"""Seconds after a hold's end its expiry is looked at (a renewal just in time is no end)."""


class CallHold(Interceptor):
    """The interceptor of a hold: a call from another process into its component waits while the
    hold lasts, ``patience`` seconds at most."""

    def __init__(self, component: str, patience: float) -> None:
        self.name = f"hold:{component}"
        self.component = component
        self.patience = patience
        self._cond = threading.Condition()
        self._until = 0.0  # time.monotonic() at which the hold ends
        self.waiting = 0

    def extend(self, seconds: float) -> None:
        with self._cond:
            self._until = time.monotonic() + seconds

    def end(self) -> None:
        with self._cond:
            self._until = 0.0
            self._cond.notify_all()

    def state(self) -> dict[str, Any]:
        with self._cond:
            left = max(0.0, self._until - time.monotonic())
            return {
                "component": self.component,
                "left": left,
                "waiting": self.waiting,
                "patience": self.patience,
            }

    def before(self, call: Invocation) -> None:
        # Only a call from another process, and not one a policy set or monitor makes (a call
        # chain of the container's own: holding it would hold the container's events).
        if current_context.client is None or call.origin is not None:
            return
        deadline = time.monotonic() + self.patience
        with self._cond:
            self.waiting += 1
            try:
                while (left := min(self._until, deadline) - time.monotonic()) > 0:
                    self._cond.wait(left)
            finally:
                self.waiting -= 1


class HoldNotices:
    """Tells watchers when a hold starts (``component.held``) and ends (``component.released``:
    released, or expired, seen by a timer at its end), through ``notice(kind, component, value,
    data)`` (the observer's :meth:`~acordcs.runtime.live.observer.Observer.notice`); a renewal
    while it lasts is no new hold."""

    def __init__(self, notice: Callable[[str, str, object, dict[str, object]], None]) -> None:
        self.notice = notice
        self._lock = threading.Lock()
        self._on: dict[str, tuple[CallHold, threading.Timer]] = {}

    def held(self, hold: CallHold, seconds: float) -> None:
        timer = threading.Timer(seconds + EXPIRY_SLACK, self._expired, (hold,))
        timer.daemon = True
        with self._lock:
            found = self._on.get(hold.component)
            if found is not None:
                found[1].cancel()
            self._on[hold.component] = (hold, timer)
        timer.start()
        if found is None or found[0] is not hold:
            state = hold.state()
            self.notice(ev.COMPONENT_HELD, hold.component, state["left"],
                        {"waiting": state["waiting"], "patience": state["patience"]})  # fmt: skip

    def ended(self, hold: CallHold, why: str) -> None:
        with self._lock:
            found = self._on.get(hold.component)
            if found is None or found[0] is not hold:
                return
            del self._on[hold.component]
        found[1].cancel()
        self.notice(ev.COMPONENT_RELEASED, hold.component, why, {})

    def _expired(self, hold: CallHold) -> None:
        if hold.state()["left"] <= 0:  # else renewed meanwhile: its own timer looks again
            self.ended(hold, "expired")

    def close(self) -> None:
        with self._lock:
            on, self._on = dict(self._on), {}
        for _hold, timer in on.values():
            timer.cancel()
