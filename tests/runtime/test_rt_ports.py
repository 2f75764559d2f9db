"""Ports of the three kinds, overflow policies, stream rates, and replacement keeping state."""

from __future__ import annotations

import pytest

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.errors import PortError, QueueFullError
from acordcs.runtime.ports import PortSpec, sync_port
from tests.support.components import (
    BetterCounter,
    Camera,
    Client,
    Counter,
    Receiver,
    Screen,
    Sender,
)


@pytest.fixture
def box():
    clock = VirtualClock(seed=3)
    container = Container("box", clock=clock)
    for cls in (Counter, BetterCounter, Client, Sender, Receiver, Camera, Screen):
        container.install_factory(ComponentFactory(cls.__name__, cls))
    yield container
    container.close()


def test_async_notification_is_queued_and_pumped_by_the_clock(box):
    sender = box.create("Sender", "s")
    receiver = box.create("Receiver", "r")
    box.connect("s.out", "r.inbox")
    sender.send("hello")
    # Decoupled from the sender: nothing delivered until the clock runs.
    assert receiver.instance.got == []
    box.clock.run_for(0.0)
    assert receiver.instance.got == ["hello"]


@pytest.mark.parametrize(
    ("policy", "expected"),
    [("drop_oldest", [3, 4, 5]), ("drop_newest", [1, 2, 3])],
)
def test_bounded_queue_overflow_policies(box, policy, expected):
    box.create("Sender", "s")
    receiver = box.create("Receiver", "r")
    box.connect("s.out", "r.inbox")
    box.set_property("r.inbox", "overflow", policy)
    for n in range(1, 6):
        box.find("s").send(n)
    port = receiver.port("inbox")
    assert port.dropped == 2
    box.clock.run_for(0.0)
    assert receiver.instance.got == expected


def test_reject_overflow_policy_tells_the_sender(box):
    box.create("Sender", "s")
    box.create("Receiver", "r")
    box.connect("s.out", "r.inbox")
    box.set_property("r.inbox", "overflow", "reject")
    for n in range(3):
        box.find("s").send(n)
    with pytest.raises(QueueFullError, match=r"queue of port r.inbox is full \(3 messages\)"):
        box.find("s").send(99)


def test_raising_notification_handler_is_isolated_and_later_messages_arrive(box):
    sender = box.create("Sender", "s")
    receiver = box.create("Receiver", "r")
    box.connect("s.out", "r.inbox")
    sender.send("a")
    sender.send("boom")
    sender.send("b")
    box.clock.run_for(0.0)
    assert receiver.instance.got == ["a", "b"]
    assert box.faults.counts["component"] == 1
    assert box.faults.recent[-1].where == "r.on_inbox"


def test_stream_rate_is_a_port_property_that_can_change(box):
    box.create("Camera", "cam")
    screen = box.create("Screen", "scr")
    box.connect("scr.video", "cam.video")
    box.clock.run_for(1.0)
    assert len(screen.instance.frames) == 10
    box.set_property("cam.video", "rate", 2.0)
    box.clock.run_for(1.0)
    assert len(screen.instance.frames) == 12
    box.set_property("cam.video", "rate", 0)  # paused
    box.clock.run_for(5.0)
    assert len(screen.instance.frames) == 12
    with pytest.raises(PortError, match="rate must be a number >= 0"):
        box.set_property("cam.video", "rate", -1)


def test_port_kind_mismatches_are_refused(box):
    box.create("Camera", "cam")
    box.create("Receiver", "r")
    with pytest.raises(PortError, match=r"cannot connect .* \(asynchronous\) to .* \(stream\)"):
        box.connect("r.inbox", "cam.video")
    with pytest.raises(PortError, match="needs a port of kind asynchronous"):
        box.find("cam").port("video").notify("x")


def test_bad_port_declarations_are_reported():
    with pytest.raises(PortError, match="kind 'sync' is not one of"):
        PortSpec("p", kind="sync")
    with pytest.raises(PortError, match="overflow 'drop_all'"):
        PortSpec("p", kind="asynchronous", overflow="drop_all")

    class NoHandler(CtxComponent):
        ports = (PortSpec("p", "asynchronous", handler="missing"),)

    with Container("c", clock=VirtualClock()) as c:
        c.install_factory(ComponentFactory("NoHandler", NoHandler))
        with pytest.raises(PortError, match="handler 'missing' is not a method"):
            c.create("NoHandler", "n")


def test_replacement_keeps_state_connections_and_handles(box):
    counter = box.create("Counter", "srv")
    client = box.create("Client", "cli")
    box.connect("cli.api", "srv.api")
    client.use(3)
    client.use(4)
    box.set_property("srv", "limit", 42)
    new = box.replace("srv", "BetterCounter")
    assert new == counter  # the old handle follows the replacement
    assert type(counter.instance) is BetterCounter
    assert counter.get("count") == 7
    assert counter.get("limit") == 42
    assert counter.instance.history == [3, 7]
    assert client.use(1) == 9  # the connection now reaches the new instance, counting by 2
    assert [r.name for r in box.find_by_type("BetterCounter")] == ["srv"]
    assert box.find_by_type("Counter") == []


def test_replacement_refuses_a_type_missing_a_connected_port(box):
    class Portless(Counter):
        ports = (sync_port("other"),)

    box.install_factory(ComponentFactory("Portless", Portless))
    box.create("Counter", "srv")
    box.create("Client", "cli")
    box.connect("cli.api", "srv.api")
    with pytest.raises(PortError, match=r"connected port 'api' .* has no counterpart"):
        box.replace("srv", "Portless")
    assert type(box.find("srv").instance) is Counter
    assert box.find("cli").use() == 1


def test_save_and_restore_state_round_trip(box):
    ref = box.create("Counter", "a")
    ref.bump(5)
    state = ref.instance.save_state()
    other = box.create("Counter", "b")
    other.instance.restore_state(state)
    assert other.get("count") == 5
    assert other.instance.history == [5]
    state["properties"]["count"] = 99  # a saved state is a copy
    assert ref.get("count") == 5
