"""A monitor that cannot read is an event of the console's page: the container's ``monitor.stale``
(its source's call fails; the runtime keeps the monitor's last values) reaches the page's events
as ``stale`` with the failure's cause, and its next reading as ``stale`` false with how long it
was stale. The container is real (a virtual clock), its observer interface the one a served
container has; only the network between them is left out (the console reaches it in process)."""

from __future__ import annotations

import threading
from typing import Any

import pytest

from acordcs.console.fanout import ConsoleHub
from acordcs.console.live_session import LiveSession
from acordcs.runtime.acquisition import PollingMonitor
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import RemoteTimeoutError
from acordcs.runtime.live.observer import Observer
from tests.support.descriptors import application, component, container, monitor, op, prop, ref

WAIT = 30.0  # seconds an event may take to reach the page (a loaded host)


class Sensor(CtxComponent):
    down = False

    def readTemperature(self) -> float:
        if self.down:
            raise RemoteTimeoutError("readTemperature() took longer than 2 s", where="ThermoLink")
        return 21.5


class InProcess:
    """The application as the console reaches it, the container in this process: its observer
    answers ``observe`` as the container's observer interface would."""

    mode = "attached"
    app_dir = None
    how_to_start = "the test's container is gone"

    def __init__(self, house: Container) -> None:
        self.descriptor = application(
            "Greenhouse",
            containers=(container("House", ref("component", "Sensor"), ref("monitor", "Climate")),),
            components=(component("Sensor", operations=(op("readTemperature", returns="double"),)),),
            monitors=(monitor("Climate", prop("temperature", 0.0), frequency=1.0,
                              sources=(ref("component", "Sensor"),),
                              operation="readTemperature"),),
        )  # fmt: skip
        self.name = "Greenhouse"
        self.places = {"House": "House"}
        self.host_of = {"Sensor": "House"}
        self.observer = Observer(house)

    def observe(self, container: str, method: str, *args: Any) -> Any:
        return getattr(self.observer, method)(*args)

    def describe(self) -> str:
        return "House in this process"

    def close(self) -> None:
        self.observer.close()


@pytest.fixture
def page():
    """The container, the console's session over it, and what a page holding the token gets."""
    with Container("House", clock=VirtualClock(7)) as house:
        house.install_factory(ComponentFactory("Sensor", Sensor))
        house.create("Sensor", "Sensor")
        house.add_monitor(
            PollingMonitor("Climate", frequency=1.0, sources=["Sensor"],
                           operation="readTemperature", attributes={"temperature": 0.0})
        )  # fmt: skip
        hub = ConsoleHub()
        woken = threading.Event()
        joined = hub.join(woken.set, holder=True)
        assert joined is not None
        _, box = joined
        session = LiveSession(hub, "token", InProcess(house))
        session.attach()
        seen: list[dict[str, Any]] = []

        def events_until(found) -> list[dict[str, Any]]:
            deadline = threading.Event()
            timer = threading.Timer(WAIT, deadline.set)
            timer.start()
            try:
                while not deadline.is_set():
                    seen.extend(e for e in hub.take(box)[1] if e["kind"] == "stale")
                    if found(seen):
                        return seen
                    woken.wait(0.5)
                    woken.clear()
            finally:
                timer.cancel()
            raise AssertionError(f"not on the page within {WAIT:g} s: {seen}")

        try:
            yield house, events_until
        finally:
            session.close()


def test_a_monitor_whose_source_fails_is_stale_on_the_page_then_reads_again(page):
    house, events_until = page
    house.clock.sleep(1.5)  # it read once
    house.find("Sensor").instance.down = True
    house.clock.sleep(3.0)  # three readings fail: one stale event
    (stale,) = events_until(lambda s: len(s) >= 1)
    assert stale["container"] == "House" and stale["element"] == "Climate"
    assert stale["stale"] is True
    assert "readTemperature() took longer than 2 s" in stale["cause"]
    house.find("Sensor").instance.down = False
    house.clock.sleep(1.0)
    _, fresh = events_until(lambda s: len(s) >= 2)
    assert fresh["stale"] is False and fresh["element"] == "Climate"
    assert fresh["stale_for"] == pytest.approx(3.0)
    assert house.monitor("Climate").attributes == {"temperature": 21.5}
