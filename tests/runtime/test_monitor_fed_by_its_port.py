"""A monitor whose source is a port (``Component.Port``) sees the calls through that port: an
interceptor on that port's calls feeds it (the WebLab's control monitor intercepts the calls to the
locomotion service)."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from acordcs.runtime import events as ev
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.interceptors import Interceptor
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import async_port, sync_port


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (sync_port("LocomotionPort"), async_port("Commands"))

    def move(self, speed: float, turn: float) -> float:
        self.set("speed", speed)
        return speed

    def on_Commands(self, message: Any) -> None:
        pass


class FasterLocomotion(Locomotion):
    pass


class Navigator(CtxComponent):
    ports = (sync_port("Nav", role="required"), async_port("Out", role="required"))


class Control(Monitor):
    """Extracts the speed and the turn of each control action."""

    def __init__(self, name: str, **kw: Any) -> None:
        super().__init__(name, **kw)
        self.seen: list[ev.Event] = []

    def on_event(self, event: ev.Event) -> None:
        self.seen.append(event)
        if event.kind == ev.OPERATION_CALLED and event.attribute == "move":
            speed, turn = event.data["args"]
            self.update(speed=speed, angle=turn)


@pytest.fixture
def robot():
    with Container("robot", clock=VirtualClock()) as c:
        c.install_factory(ComponentFactory("Locomotion", Locomotion))
        c.install_factory(ComponentFactory("FasterLocomotion", FasterLocomotion))
        c.install_factory(ComponentFactory("Navigator", Navigator))
        c.create("Locomotion", "Locomotion")
        c.create("Navigator", "Navigator")
        c.connect("Navigator.Nav", "Locomotion.LocomotionPort")
        c.connect("Navigator.Out", "Locomotion.Commands")
        yield c


def test_calls_through_the_port_feed_the_monitor(robot):
    control = Control(
        "Control", sources=["Locomotion.LocomotionPort"], attributes={"speed": 0.0, "angle": 0.0}
    )
    robot.add_monitor(control)
    updates = []
    robot.subscribe(ev.MONITOR_UPDATED, updates.append, name="t", element="Control")
    nav = robot.find("Navigator").instance
    assert nav.port("Nav").call("move", 120.0, 5.0) == 120.0
    (seen,) = control.seen
    assert (seen.kind, seen.element, seen.attribute, seen.value) == (
        ev.OPERATION_CALLED,
        "Locomotion.LocomotionPort",
        "move",
        120.0,
    )
    assert seen.data["args"] == (120.0, 5.0) and seen.data["component"] == "Locomotion"
    assert control.attributes == {"speed": 120.0, "angle": 5.0}
    assert [u.data for u in updates] == [{"speed": 120.0, "angle": 5.0}]


def test_only_that_port_is_watched_and_the_tap_follows_replacement(robot):
    control = Control("Control", sources=["Locomotion.LocomotionPort"])
    robot.add_monitor(control)
    robot.find("Locomotion").move(10.0, 0.0)  # a handle's call: not through the port
    robot.find("Navigator").instance.port("Out").notify("hello")  # another port
    robot.clock.run_for(1.0)
    assert control.seen == []
    robot.replace("Locomotion", "FasterLocomotion")
    robot.find("Navigator").instance.port("Nav").call("move", 30.0, 1.0)
    assert [e.attribute for e in control.seen] == ["move"]


def test_removing_the_monitor_removes_its_tap(robot):
    control = Control("Control", sources=["Locomotion.LocomotionPort"])
    robot.add_monitor(control)
    robot.remove_monitor("Control")
    robot.find("Navigator").instance.port("Nav").call("move", 30.0, 1.0)
    assert control.seen == []


def test_interceptors_can_filter_by_port(robot):
    calls = []

    class Spy(Interceptor):
        def after(self, call):
            calls.append((call.component, call.port, call.operation))

    robot.add_interceptor(Spy(), port="Commands")
    robot.find("Navigator").instance.port("Nav").call("move", 30.0, 1.0)
    robot.find("Navigator").instance.port("Out").notify("go")
    robot.clock.run_for(1.0)
    assert calls == [("Locomotion", "Commands", "on_Commands")]
