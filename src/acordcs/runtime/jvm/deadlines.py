"""A call's timeout for the operations of hosted Java components: a Java operation still running
when its call's time is up has its Java thread interrupted (``Thread.interrupt``), and its call
ends in a timeout fault, whatever the operation then returns.

One watchdog thread per process (started with the first call) looks at the calls running every
:data:`RESOLUTION` seconds at most. An operation interrupted in ``Thread.sleep``, ``wait``, a
blocking queue or interruptible I/O, or one that checks ``Thread.interrupted()``, ends at once;
a loop that ignores interrupts is not stopped (the JVM has no safe way to stop a thread): its
thread stays busy with it, and the call ends only if the loop does. The container still answers
its other calls meanwhile (JPype releases the GIL while Java runs), and a remote caller gets its
own timeout. A call ending after its interrupt clears its thread's interrupt status, so that the
thread's next Java call starts clean.
"""

from __future__ import annotations

import threading
import time
from dataclasses import dataclass
from typing import Any

RESOLUTION = 0.05
"""Seconds between the watchdog's looks (a call runs up to this much longer than its timeout)."""


@dataclass(slots=True, eq=False)
class RunningCall:
    """One Java operation running: until when, on which Java thread; ``interrupted`` once the
    watchdog interrupted it."""

    deadline: float
    thread: Any
    interrupted: bool = False
    done: bool = False


class Deadlines:
    """The Java operations running in this process and their deadlines."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._running: set[RunningCall] = set()
        self._local = threading.local()
        self._watchdog: threading.Thread | None = None
        self._java_thread: Any = None  # java.lang.Thread, once a call needed it

    def enter(self, seconds: float) -> RunningCall:
        """A call starting now on this thread, to end within ``seconds``."""
        thread = getattr(self._local, "thread", None)
        if thread is None:
            import jpype

            self._java_thread = jpype.JClass("java.lang.Thread")
            thread = self._local.thread = self._java_thread.currentThread()
        call = RunningCall(time.monotonic() + seconds, thread)
        self._running.add(call)  # one operation under the GIL: no lock on a call's way
        if self._watchdog is None:
            with self._lock:
                if self._watchdog is None:
                    self._watchdog = threading.Thread(
                        target=self._watch, name="acordcs-java-deadlines", daemon=True
                    )
                    self._watchdog.start()
        return call

    def leave(self, call: RunningCall) -> bool:
        """The call ended; whether it was interrupted (its thread's interrupt status cleared).
        ``done`` is set before ``interrupted`` is read, and the watchdog sets ``interrupted``
        before it reads ``done``: one of the two sees the other's, so a call the watchdog
        interrupts always knows it, and waits (the lock) until the interrupt is made before
        clearing it."""
        call.done = True
        self._running.discard(call)
        if not call.interrupted:
            return False
        with self._lock:  # the watchdog's interrupt of this call is complete
            self._java_thread.interrupted()  # clears this thread's interrupt status
        return True

    def _watch(self) -> None:
        while True:
            time.sleep(RESOLUTION)
            now = time.monotonic()
            for call in tuple(self._running):  # a copy: calls come and go meanwhile
                if call.interrupted or call.deadline > now:
                    continue
                with self._lock:
                    call.interrupted = True
                    if not call.done:
                        call.thread.interrupt()


deadlines = Deadlines()
"""The process's one record of running Java operations."""
