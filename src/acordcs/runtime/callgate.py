"""The calls running in one hosted component, and a hold on new ones while it is replaced.

``Container.replace`` holds the gate: calls from other threads wait at :meth:`CallGate.enter`
until the new instance is in place (they then run on it), and the replacement waits until the
calls already running have returned, so their writes are in the state handed to the new instance.
A thread already running in the component may enter again (a call chain coming back to it), and
the replacing thread's own calls do not count, so neither can deadlock the replacement.
"""

from __future__ import annotations

import threading
import time


class CallGate:
    def __init__(self) -> None:
        # a plain lock (never taken twice by one thread here): cheaper than the default RLock;
        # calls take it directly (a C-level ``with``, not the condition's Python methods) and
        # wait on the condition only while a replacement holds the gate
        self._lock = threading.Lock()
        self._cond = threading.Condition(self._lock)
        self._running: dict[int, int] = {}  # thread ident -> calls running in it
        self._holder: int | None = None

    def enter(self) -> None:
        me = threading.get_ident()
        with self._lock:
            running = self._running
            # no replacement holding the gate (the usual case): one test, not the loop's
            if self._holder is not None:
                while self._holder not in (None, me) and not running.get(me):
                    self._cond.wait()
            running[me] = running.get(me, 0) + 1

    def leave(self) -> None:
        me = threading.get_ident()
        with self._lock:
            left = self._running[me] - 1
            if left:
                self._running[me] = left
            else:
                del self._running[me]
            # only a replacement waits (in hold), or callers kept out while one is held: without
            # a holder nobody is waiting, and a call need not pay for the notification
            if self._holder is not None:
                self._cond.notify_all()

    def hold(self, timeout: float) -> int:
        """Stop new calls from other threads and wait up to ``timeout`` seconds for the running
        ones; the number still running (0: drained). Always :meth:`release` afterwards."""
        me = threading.get_ident()
        deadline = time.monotonic() + timeout
        with self._cond:
            while self._holder not in (None, me):  # another replacement in progress
                self._cond.wait()
            self._holder = me
            while True:
                others = sum(n for thread, n in self._running.items() if thread != me)
                remaining = deadline - time.monotonic()
                if not others or remaining <= 0:
                    return others
                self._cond.wait(remaining)

    def release(self) -> None:
        with self._cond:
            self._holder = None
            self._cond.notify_all()
