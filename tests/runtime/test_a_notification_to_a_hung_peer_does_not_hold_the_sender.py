"""A notification to a container in another process is taken at once and delivered by the
connector's own thread (connectors/outbox.py): a peer that does not answer (stopped with SIGSTOP)
holds neither the sender nor its container's clock, and what cannot be delivered is counted in
the connection's ``stats["lost"]`` and recorded as the sender's fault, never lost unseen."""

from __future__ import annotations

import os
import signal

import pytest

from acordcs.runtime.component import ComponentFactory
from acordcs.runtime.connectors.outbox import CAPACITY
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from tests.runtime.test_rt_remote import (
    TIMEOUT,
    Navigator,
    RemoteProcess,
    all_stopped,
    free_port,
    wait_for,
)

pytestmark = pytest.mark.skipif(
    not os.path.isdir("/proc/self/task"), reason="needs /proc to see the peer stopped"
)


@pytest.fixture
def remote():
    proc = RemoteProcess(free_port())
    proc.start()
    yield proc
    os.kill(proc.proc.pid, signal.SIGCONT)
    proc.kill()


def sender(remote: RemoteProcess) -> tuple[Container, RemoteConnector]:
    container = Container("local")  # real time, like a deployed container
    container.install_factory(ComponentFactory("Navigator", Navigator))
    container.create("Navigator", "nav")
    connector = RemoteConnector(timeout=TIMEOUT)
    container.connect("nav.robot", RemotePort(remote.uri, "robot", "control"), connector=connector)
    container.connect(
        "nav.events", RemotePort(remote.uri, "robot", "events"), connector=connector, name="events"
    )
    return container, connector


def stop(remote: RemoteProcess) -> None:
    os.kill(remote.proc.pid, signal.SIGSTOP)
    assert wait_for(lambda: all_stopped(remote.proc.pid))


def test_a_notification_returns_while_the_peer_hangs_and_arrives_when_it_answers(remote):
    container, connector = sender(remote)
    try:
        nav = container.find("nav")
        nav.tell({"n": 0})  # connects while the peer answers
        assert wait_for(lambda: nav.ask("received") == [{"n": 0}])
        stop(remote)
        # sent from a timer, as a component's periodic push is: the timer returns at once and
        # the clock's next timer finds the item taken, waiting for the peer (not failed yet)
        waiting = []
        container.clock.call_later(0.0, lambda: nav.tell({"n": 1}))
        container.clock.call_later(0.0, lambda: waiting.append(connector.pending()))
        assert wait_for(lambda: waiting)
        assert waiting == [1] and not container.faults.recent
        os.kill(remote.proc.pid, signal.SIGCONT)
        assert wait_for(lambda: connector.pending() == 0)
        assert nav.ask("received") == [{"n": 0}, {"n": 1}]
        assert container.connection("events").stats == {"sent": 2, "lost": 0}
        assert not container.faults.recent
    finally:
        container.close()


def test_what_a_hung_peer_cannot_take_is_counted_and_reported_never_lost_unseen(remote):
    container, connector = sender(remote)
    nav = container.find("nav")
    nav.tell({"n": 0})
    assert wait_for(lambda: connector.pending() == 0)
    stop(remote)
    sent = CAPACITY + 5
    for n in range(1, sent + 1):
        nav.tell({"n": n})
    stats = container.connection("events").stats
    # every item is delivered, waiting, or counted lost (the oldest dropped for the newest)
    assert stats["sent"] + stats["lost"] + connector.pending() == sent + 1
    assert stats["lost"] >= 4
    container.close()  # waits for the peer at most the timeout, then reports by count
    assert stats["sent"] + stats["lost"] == sent + 1
    assert stats["sent"] == 1
    faults = [f for f in container.faults.recent if f.kind == "connection"]
    assert {f.where for f in faults} == {"events"}
    said = " ".join(f.error for f in faults)
    assert "OutboxFull" in said and "Undelivered" in said, said
