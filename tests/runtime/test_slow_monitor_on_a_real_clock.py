"""A monitor blocking in ``acquire()`` on a real-time clock (issue 14): the other monitors keep
their ticks; the slow one skips its own, counted."""

from __future__ import annotations

import threading

from acordcs.runtime.clock import RealClock
from acordcs.runtime.container import Container
from acordcs.runtime.monitor import Monitor
from tests.support.services import wait_for


class Stuck(Monitor):
    def __init__(self, release: threading.Event) -> None:
        super().__init__("stuck", frequency=20.0, attributes={"x": 0})
        self.release = release
        self.acquired = 0

    def acquire(self):
        self.acquired += 1
        self.release.wait(30)  # blocks, like a sensor read without a timeout
        return {"x": self.acquired}


class Quick(Monitor):
    def __init__(self) -> None:
        super().__init__("quick", frequency=20.0, attributes={"n": 0})
        self.thread_names: set[str] = set()

    def acquire(self):
        self.thread_names.add(threading.current_thread().name)
        return {"n": self.ticks}


def test_one_blocking_monitor_does_not_starve_the_others():
    release = threading.Event()
    container = Container("lab", clock=RealClock())
    stuck, quick = Stuck(release), Quick()
    try:
        container.add_monitor(stuck)
        container.add_monitor(quick)
        # 20 Hz: 40 ticks take 2 s when nothing holds the clock up (bounded wait, not a timing test)
        assert wait_for(lambda: container.monitor("quick").attributes["n"] >= 40, timeout=20)
        assert stuck.acquired == 1  # its own later ticks were skipped while it blocked
        assert stuck.overruns >= 1
        release.set()
        assert wait_for(lambda: container.monitor("stuck").attributes["x"] >= 1, timeout=10)
        assert "acordcs-clock" not in quick.thread_names  # acquired off the clock's thread
    finally:
        release.set()
        container.close()
