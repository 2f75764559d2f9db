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
from typing import Any

from Pyro5.callcontext import current_context

from acordcs.runtime.interceptors import Interceptor, Invocation


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
