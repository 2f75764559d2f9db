"""The three acquisition kinds of the model's monitors (acordcs.runtime.acquisition): intercepting a
port's calls, subscribing to the context provider with an XPath, polling an operation; each hook's
result is published, a failing one is a fault and the monitor goes on; assembled from a descriptor,
each monitor gets its kind's class."""

from __future__ import annotations

import threading
from typing import Any, ClassVar

import pytest

from acordcs.runtime import events as ev
from acordcs.runtime.acquisition import (
    InterceptingMonitor,
    ObservedCall,
    PollingMonitor,
    SubscribingMonitor,
    convert,
)
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import RealClock, VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ConfigurationError
from acordcs.runtime.ports import sync_port
from tests.support import descriptors as d


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0, "heading": 0.0}
    ports = (sync_port("LocomotionPort"),)

    def move(self, speed: float, turn: float) -> float:
        self.set("speed", speed)
        self.publish_context(
            f"<telemetry><positionX>{speed * 2}</positionX><battery>11.5</battery>"
            f"<mode>{'moving' if speed else 'stopped'}</mode></telemetry>"
        )
        return speed


class Access(CtxComponent):
    users = 3

    def countUsers(self) -> int:
        return self.users

    def status(self) -> dict[str, object]:
        return {"numUsers": str(self.users), "load": 0.5, "unknown": 1}


class Navigator(CtxComponent):
    ports = (sync_port("Nav", role="required"),)


class Control(InterceptingMonitor):
    def __init__(self, name: str, **kw: Any) -> None:
        super().__init__(name, **kw)
        self.calls: list[ObservedCall] = []

    def on_call(self, call: ObservedCall):
        self.calls.append(call)
        speed, turn = call.args
        return {"speed": speed, "angle": abs(turn)}


@pytest.fixture
def lab():
    with Container("lab", clock=VirtualClock(7)) as c:
        for cls in (Locomotion, Access, Navigator):
            c.install_factory(ComponentFactory(cls.__name__, cls))
            c.create(cls.__name__, cls.__name__)
        c.connect("Navigator.Nav", "Locomotion.LocomotionPort")
        yield c


def move(lab: Container, speed: float, turn: float) -> None:
    lab.find("Navigator").instance.port("Nav").call("move", speed, turn)


# ------------------------------------------------------------------------------------ intercept
def test_intercepting_monitor_sees_each_call_through_its_port(lab):
    control = Control(
        "Control", sources=["Locomotion.LocomotionPort"], attributes={"speed": 0.0, "angle": 0.0}
    )
    lab.add_monitor(control)
    lab.clock.sleep(1.5)
    move(lab, 120.0, -7.0)
    (call,) = control.calls
    assert (call.element, call.operation, call.args, call.result, call.error, call.time) == (
        "Locomotion.LocomotionPort",
        "move",
        (120.0, -7.0),
        120.0,
        None,
        1.5,
    )
    assert control.attributes == {"speed": 120.0, "angle": 7.0}


def test_intercepting_monitor_takes_a_source_property_of_its_own_name(lab):
    control = InterceptingMonitor("Watch", sources=["Locomotion"], attributes={"speed": 0.0})
    lab.add_monitor(control)
    lab.set_property("Locomotion", "heading", 90.0)  # not an attribute of the monitor: ignored
    lab.set_property("Locomotion", "speed", 55.0)
    assert control.attributes == {"speed": 55.0}


def test_a_raising_hook_is_a_fault_and_the_next_call_is_seen(lab):
    class Fragile(Control):
        def on_call(self, call):
            if call.args[0] < 0:
                raise ValueError("negative speed")
            return super().on_call(call)

    control = Fragile("Control", sources=["Locomotion.LocomotionPort"], attributes={"speed": 0.0})
    lab.add_monitor(control)
    move(lab, -1.0, 0.0)
    move(lab, 80.0, 0.0)
    assert lab.faults.counts["monitor"] == 1
    assert control.attributes["speed"] == 80.0


# ------------------------------------------------------------------------------------ subscribe
def test_subscribing_monitor_reads_typed_values_from_the_documents_it_selects(lab):
    telemetry = SubscribingMonitor(
        "Telemetry",
        xpath="/telemetry",
        attributes={"positionX": 0.0, "battery": 0.0, "mode": "", "missing": 1},
    )
    lab.add_monitor(telemetry)
    updates = []
    lab.subscribe(ev.MONITOR_UPDATED, updates.append, name="t", element="Telemetry")
    move(lab, 40.0, 0.0)  # Locomotion publishes during the call: delivered inline, at once
    assert telemetry.attributes == {
        "positionX": 80.0,
        "battery": 11.5,
        "mode": "moving",
        "missing": 1,  # not in the document: kept
    }
    assert [u.data for u in updates] == [{"positionX": 80.0, "battery": 11.5, "mode": "moving"}]
    assert telemetry.documents == 1


def test_a_document_the_xpath_does_not_select_is_not_seen(lab):
    other = SubscribingMonitor("Other", xpath="/robot[battery < 10]", attributes={"battery": 0.0})
    lab.add_monitor(other)
    lab.publish_context("robot1", "<robot><battery>50</battery></robot>")
    lab.publish_context("robot1", "<robot><battery>9.5</battery></robot>")
    assert other.documents == 1 and other.attributes == {"battery": 9.5}


def test_a_malformed_value_is_a_fault_and_the_other_values_are_taken(lab):
    telemetry = SubscribingMonitor(
        "Telemetry", xpath="/telemetry", attributes={"positionX": 0.0, "battery": 0.0}
    )
    lab.add_monitor(telemetry)
    lab.publish_context(
        "robot", "<telemetry><positionX>NaN</positionX><battery>12</battery></telemetry>"
    )
    assert telemetry.attributes == {"positionX": 0.0, "battery": 12.0}
    assert lab.faults.counts["monitor"] == 1
    (fault,) = lab.faults.of_kind("monitor")
    assert "positionX='NaN' not of the attribute's type" in fault.error
    lab.publish_context("robot", "<telemetry><positionX>3</positionX></telemetry>")
    assert telemetry.attributes["positionX"] == 3.0  # it goes on


def test_a_detached_subscribing_monitor_is_unsubscribed(lab):
    telemetry = SubscribingMonitor("Telemetry", xpath="/telemetry", attributes={"battery": 0.0})
    lab.add_monitor(telemetry)
    assert len(lab.context.subscriptions()) == 1
    lab.remove_monitor("Telemetry")
    assert lab.context.subscriptions() == []


def test_on_a_real_clock_documents_reach_the_monitor_on_the_clock_thread():
    with Container("live", clock=RealClock()) as live:
        seen = threading.Event()
        threads = []

        class Telemetry(SubscribingMonitor):
            def on_document(self, note):
                threads.append(threading.current_thread().name)
                seen.set()
                return super().on_document(note)

        live.add_monitor(Telemetry("Telemetry", xpath="/t", attributes={"v": 0}))
        assert not live.context.inline
        live.publish_context("p", "<t><v>4</v></t>")
        assert seen.wait(5.0)
        live.clock.sleep(0.05)
        assert live.monitor("Telemetry").attributes == {"v": 4}
        assert threads and "ctx" not in threads[0]  # not a delivery thread of the provider


def test_a_subscribing_monitor_needs_an_xpath():
    with pytest.raises(ConfigurationError, match="needs an xpath"):
        SubscribingMonitor("T", xpath=" ")


# ------------------------------------------------------------------------------------------ poll
def test_polling_monitor_calls_the_operation_at_its_frequency(lab):
    usage = PollingMonitor(
        "Usage",
        frequency=2.0,
        sources=["Access"],
        operation="countUsers",
        attributes={"numUsers": 1},
    )
    calls = []
    lab.subscribe(ev.OPERATION_CALLED, calls.append, name="t", element="Access")
    lab.add_monitor(usage)
    lab.clock.sleep(1.0)
    assert usage.attributes == {"numUsers": 3}
    assert [c.time for c in calls] == [0.5, 1.0]  # through the container: events see the calls
    lab.find("Access").instance.users = 9
    lab.clock.sleep(0.5)
    assert usage.attributes == {"numUsers": 9}


def test_a_mapping_reading_fills_the_attributes_it_names(lab):
    usage = PollingMonitor(
        "Usage",
        frequency=1.0,
        sources=["Access"],
        operation="status",
        attributes={"numUsers": 0, "load": 0.0},
    )
    lab.add_monitor(usage)
    lab.clock.sleep(1.0)
    assert usage.attributes == {"numUsers": 3, "load": 0.5}


def test_a_failing_poll_is_a_fault_and_polling_goes_on(lab):
    usage = PollingMonitor(
        "Usage", frequency=1.0, sources=["Access"], operation="nothing", attributes={"n": 0}
    )
    lab.add_monitor(usage)
    lab.clock.sleep(3.0)
    assert usage.ticks == 3
    assert lab.faults.counts["monitor"] == 3


@pytest.mark.parametrize(
    ("kwargs", "says"),
    [
        ({"frequency": None, "sources": ["Access"], "operation": "countUsers"}, "frequency > 0"),
        ({"frequency": 1.0, "sources": [], "operation": "countUsers"}, "one source component"),
        ({"frequency": 1.0, "sources": ["Access"], "operation": ""}, "and an operation"),
    ],
)
def test_a_polling_monitor_needs_what_it_polls(kwargs, says):
    with pytest.raises(ConfigurationError, match=says):
        PollingMonitor("Usage", **kwargs)


# ------------------------------------------------------------------------------------ conversion
@pytest.mark.parametrize(
    ("value", "like", "expected"),
    [("3", 0, 3), (" 2.5 ", 0.0, 2.5), (4, 0.0, 4.0), ("true", False, True), ("0", True, False)],
)
def test_values_take_their_attribute_type(value, like, expected):
    got = convert(value, like)
    assert got == expected and type(got) is type(expected)


@pytest.mark.parametrize(
    ("value", "like"),
    [
        ("3.5", 0),
        ("inf", 0.0),
        ("nan", 0.0),
        (True, 0),
        (True, 0.0),
        ("yes", False),
        ("1e999", 0.0),
    ],
)
def test_values_that_do_not_convert_are_refused(value, like):
    with pytest.raises(ValueError):
        convert(value, like)


# ------------------------------------------------------------------------------ from a descriptor
def test_assembly_gives_each_monitor_its_kind():
    app = d.application(
        components=(
            d.component("Locomotion", ports=(d.port("LocomotionPort"),)),
            d.component("Access"),
        ),
        monitors=(
            d.monitor("Control", sources=(d.ref("port", "Locomotion.LocomotionPort"),)),
            d.monitor("Telemetry", acquisition="subscribe", xpath="/telemetry"),
            d.monitor(
                "Usage",
                frequency=1.0,
                acquisition="poll",
                operation="countUsers",
                sources=(d.ref("component", "Access"),),
            ),
            d.monitor("Own", frequency=2.0),
        ),
    )
    with assemble(app, clock=VirtualClock()) as run:
        container = run.container()
        kinds = {m: type(container.monitor(m)) for m in container.monitors()}
        assert kinds["Control"] is InterceptingMonitor
        assert kinds["Telemetry"] is SubscribingMonitor
        assert kinds["Usage"] is PollingMonitor
        assert kinds["Own"].__name__ == "Monitor"
        assert container.monitor("Telemetry").xpath == "/telemetry"
        assert container.monitor("Usage").operation == "countUsers"
        assert run.context.inline  # virtual clock: deterministic delivery


def test_a_monitor_class_declaring_its_attributes_has_them_without_a_descriptor():
    class Usage(PollingMonitor):
        attribute_defaults: ClassVar[dict[str, object]] = {"numUsers": 1}

    usage = Usage("Usage", frequency=1.0, sources=["Access"], operation="countUsers")
    assert usage.attributes == {"numUsers": 1}
    usage.attributes["numUsers"] = 5  # its own copy: the class's defaults stay
    assert Usage.attribute_defaults == {"numUsers": 1}
    given = Usage("Usage", frequency=1.0, sources=["Access"], operation="n", attributes={"x": 0})
    assert given.attributes == {"x": 0}  # what the assembly gives (the descriptor) wins
