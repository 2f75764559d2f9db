"""The distributed context provider against a real mosquitto started (and restarted) by the tests."""

from __future__ import annotations

import socket
import threading
from pathlib import Path

import pytest

from acordcs.runtime.context import (
    ContextError,
    MqttContextProvider,
    Notification,
    PublishError,
    SubscriptionError,
    publisher_topic,
)
from tests.support.services import Broker, free_port, wait_for

pytestmark = pytest.mark.service


class Inbox:
    def __init__(self) -> None:
        self.notes: list[Notification] = []
        self.lock = threading.Lock()

    def __call__(self, note: Notification) -> None:
        with self.lock:
            self.notes.append(note)

    def __len__(self) -> int:
        with self.lock:
            return len(self.notes)


@pytest.fixture
def broker(tmp_path: Path):
    server = Broker(tmp_path)
    server.start()
    yield server
    server.stop()


@pytest.fixture
def clients(broker: Broker):
    made: list[MqttContextProvider] = []

    def make(**options) -> MqttContextProvider:
        client = MqttContextProvider("127.0.0.1", broker.port, **options)
        made.append(client)
        return client

    yield make
    for client in made:
        client.close()
    # closing stopped paho's network threads and the delivery workers
    leftovers = [
        t.name for t in threading.enumerate() if t.name.startswith(("paho-mqtt", "acordcs-ctx-"))
    ]
    assert not leftovers


def test_topic_escapes_mqtt_metacharacters() -> None:
    assert publisher_topic("robot/1+#$ x") == "acordcs/ctx/robot%2F1%2B%23%24%20x"


def test_publish_reaches_remote_subscriber_with_selected_nodes(clients) -> None:
    publisher, subscriber = clients(), clients(mirror=False)
    inbox = Inbox()
    subscriber.subscribe(inbox, "/robot/battery[. < 20]", publisher="robot/1")
    publisher.publish("robot/1", "<robot><battery>50</battery></robot>")
    publisher.publish(
        "robot/2", "<robot><battery>5</battery></robot>"
    )  # another topic: not received
    publisher.publish("robot/1", "<robot><battery>15</battery></robot>")
    assert wait_for(lambda: len(inbox) == 1)
    note = inbox.notes[0]
    assert (note.publisher, note.seq, [n.text for n in note.nodes]) == ("robot/1", 2, ["15"])
    assert subscriber.publishers() == ["robot/1"]  # mirror=False: only the topic it needs
    assert subscriber.stats()["lost"] == 0


def test_client_socket_has_tcp_nodelay(clients) -> None:
    client = clients()
    sock = client._client.socket()
    assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) != 0


def test_retained_latest_document_and_query(clients) -> None:
    publisher = clients()
    publisher.publish("r1", "<robot><speed>1</speed></robot>")
    publisher.publish("r1", "<robot><speed>3</speed></robot>")
    publisher.publish("r2", "<robot><speed>0.5</speed></robot>")
    assert wait_for(lambda: publisher.latest("r2") is not None and publisher.latest("r1")[0] == 2)
    late = clients()  # connects after the fact: the broker hands it the retained documents
    assert wait_for(lambda: late.publishers() == ["r1", "r2"])
    assert [(r.publisher, r.seq) for r in late.query("/robot/speed[. > 0.7]")] == [("r1", 2)]


def test_retired_publisher_disappears_from_retained_state(clients) -> None:
    publisher = clients()
    publisher.publish("old", "<robot/>")
    publisher.publish("kept", "<robot/>")
    assert wait_for(lambda: publisher.publishers() == ["kept", "old"])
    publisher.retire("old")
    assert wait_for(lambda: publisher.publishers() == ["kept"])
    late = clients()
    assert wait_for(lambda: late.publishers() == ["kept"])
    assert late.latest("old") is None


def test_qos0_and_qos2_also_deliver(clients) -> None:
    for qos in (0, 2):
        inbox = Inbox()
        sub, pub = clients(qos=qos), clients(qos=qos, prefix=f"q{qos}")
        sub_q = clients(qos=qos, prefix=f"q{qos}")
        sub_q.subscribe(inbox, "/a")
        pub.publish("p", "<a/>")
        assert wait_for(lambda inbox=inbox: len(inbox) == 1)
        sub.close()


def test_sequence_gaps_are_counted_as_losses(clients) -> None:
    subscriber = clients()
    inbox = Inbox()
    subscriber.subscribe(inbox, publisher="p")
    # a foreign client publishing with our framing, skipping seq 2 and 3, then replaying 4
    raw = clients()
    topic = publisher_topic("p")
    for seq in (1, 4, 4):
        raw._client.publish(topic, b"ACX1 feedfeedfeedfeed %d\n<a/>" % seq, qos=1).wait_for_publish(
            5
        )
    raw._client.publish(topic, b"garbage", qos=1).wait_for_publish(5)
    raw._client.publish(topic, b"ACX1 feedfeedfeedfeed 5\n<a><b></a>", qos=1).wait_for_publish(5)
    assert wait_for(lambda: subscriber.stats()["malformed"] == 2)
    stats = subscriber.stats()
    assert (stats["lost"], stats["duplicates"]) == (2, 1)
    assert [n.seq for n in inbox.notes] == [1, 4]


def test_broker_restart_subscribers_receive_again_without_resubscribing(
    broker: Broker, clients
) -> None:
    subscriber, publisher = clients(mirror=False), clients()
    inbox = Inbox()
    subscriber.subscribe(inbox, "/t[. > 0]", publisher="sensor")
    publisher.publish("sensor", "<t>1</t>")
    assert wait_for(lambda: len(inbox) == 1)
    broker.restart()  # same port, and without persistence it has forgotten every subscription
    assert wait_for(lambda: subscriber.connected and publisher.connected, timeout=20)
    # publish until one arrives: the publisher may reconnect before the subscriber has re-subscribed
    assert wait_for(
        lambda: publisher.publish("sensor", "<t>2</t>") and len(inbox) >= 2,
        timeout=20,
        interval=0.1,
    )
    assert inbox.notes[1].nodes[0].text == "2"
    assert subscriber.stats()["reconnects"] >= 1


def test_qos0_publish_during_outage_is_a_clear_error(broker: Broker, clients) -> None:
    publisher = clients(qos=0)
    broker.stop()
    assert wait_for(lambda: not publisher.connected)
    with pytest.raises(ContextError, match="not sent") as info:
        publisher.publish("p", "<a/>")
    assert info.value.hint


def test_bad_input_is_refused_before_the_broker(clients) -> None:
    publisher = clients()
    with pytest.raises(PublishError):
        publisher.publish("p", "<!DOCTYPE a [<!ENTITY x SYSTEM 'file:///etc/passwd'>]><a>&x;</a>")
    with pytest.raises(PublishError):
        publisher.publish("p", "<a>")
    with pytest.raises(SubscriptionError, match="Unregistered function"):
        publisher.subscribe(print, "/a[evil(.)]")
    assert publisher.stats()["rejected"] == 2


def test_unreachable_broker_is_a_clear_error() -> None:
    with pytest.raises(ContextError, match="cannot reach the MQTT broker") as info:
        MqttContextProvider("127.0.0.1", free_port(), connect_timeout=2)
    assert "start mosquitto" in info.value.hint


def test_missing_mosquitto_skips_locally_but_fails_in_ci(monkeypatch: pytest.MonkeyPatch) -> None:
    from tests.support import services as ctx_helpers

    monkeypatch.setattr(ctx_helpers, "MOSQUITTO_CANDIDATES", ("/nonexistent/mosquitto",))
    monkeypatch.setenv("CI", "true")
    with pytest.raises(pytest.fail.Exception, match="must run in CI"):
        ctx_helpers.mosquitto_binary()
    monkeypatch.delenv("CI")
    with pytest.raises(pytest.skip.Exception, match="mosquitto not found"):
        ctx_helpers.mosquitto_binary()


def test_inline_delivery_runs_callbacks_in_the_network_thread(clients) -> None:
    publisher, subscriber = clients(), clients(mirror=False, inline=True)
    threads: list[str] = []
    inbox = Inbox()

    def callback(note: Notification) -> None:
        threads.append(threading.current_thread().name)
        inbox(note)

    subscriber.subscribe(callback, "/robot/battery", publisher="robot/1")
    for level in (50, 40, 30):
        publisher.publish("robot/1", f"<robot><battery>{level}</battery></robot>")
    assert wait_for(lambda: len(inbox) == 3)
    assert [n.seq for n in inbox.notes] == [1, 2, 3]
    assert all(name.startswith("paho-mqtt") for name in threads), threads
    assert subscriber.stats()["lost"] == 0
