"""close() right after publishing: the QoS 1 documents already accepted reach the broker (flushed),
or the publisher says by count which did not; a tail lost on the way is counted by the subscribers
(the publisher's end marker carries its last sequence number). Against a real mosquitto."""

from __future__ import annotations

import logging
import threading
from pathlib import Path

import paho.mqtt.client as mqtt
import pytest
from paho.mqtt.enums import CallbackAPIVersion

from acordcs.runtime.context import ContextError, MqttContextProvider, publisher_topic
from tests.support.services import Broker, wait_for

pytestmark = pytest.mark.service

PADDING = "x" * 200


@pytest.fixture
def broker(tmp_path: Path):
    server = Broker(tmp_path)
    server.start()
    yield server
    server.stop()


class Seqs:
    """The sequence numbers a subscriber's callback saw (inline: in paho's network thread)."""

    def __init__(self) -> None:
        self.seen: set[int] = set()
        self.lock = threading.Lock()

    def __call__(self, note) -> None:
        with self.lock:
            self.seen.add(note.seq)

    def __len__(self) -> int:
        with self.lock:
            return len(self.seen)


def publish_all(provider: MqttContextProvider, count: int) -> None:
    """``count`` documents as fast as publish() returns; a full client queue is waited out, as
    the provider's hint says."""
    for i in range(count):
        while True:
            try:
                provider.publish("robot", f"<robot><i>{i}</i><pad>{PADDING}</pad></robot>")
                break
            except ContextError:
                provider.flush(0.001)


def test_20000_documents_then_close_all_arrive(broker: Broker) -> None:
    subscriber = MqttContextProvider("127.0.0.1", broker.port, mirror=False, inline=True)
    seqs = Seqs()
    subscriber.subscribe(seqs, "/robot/i", "robot")
    publisher = MqttContextProvider("127.0.0.1", broker.port, mirror=False)
    try:
        publish_all(publisher, 20_000)
        assert publisher.close(timeout=60) == 0  # the broker acknowledged every one
        assert publisher.stats()["unacknowledged"] == 0
        # the end marker comes after the last document on the same topic
        assert wait_for(lambda: subscriber.stats()["ended"] == 1, timeout=60)
        stats = subscriber.stats()
        assert (len(seqs), stats["lost"], stats["duplicates"]) == (20_000, 0, 0)
        assert seqs.seen == set(range(1, 20_001))
    finally:
        publisher.close()
        subscriber.close()


def test_close_while_the_broker_is_down_reports_the_unacknowledged_documents(
    broker: Broker, caplog
) -> None:
    publisher = MqttContextProvider("127.0.0.1", broker.port, mirror=False)
    broker.stop()
    assert wait_for(lambda: not publisher.connected)
    for i in range(37):  # QoS 1: queued in the client while the broker is unreachable
        publisher.publish("robot", f"<robot><i>{i}</i></robot>")
    assert publisher.pending() == 37
    with caplog.at_level(logging.WARNING, logger="acordcs.runtime.context.mqtt"):
        assert publisher.close(timeout=0.3) == 37
    assert publisher.stats()["unacknowledged"] == 37
    assert publisher.close() == 37  # idempotent, the same answer
    (warning,) = [r.getMessage() for r in caplog.records if "not acknowledged" in r.getMessage()]
    assert "37 document(s)" in warning and "unreachable" in warning
    assert f"127.0.0.1:{broker.port}" in warning


def test_a_tail_lost_before_the_end_marker_is_counted_by_the_subscriber(broker: Broker) -> None:
    subscriber = MqttContextProvider("127.0.0.1", broker.port, mirror=False, inline=True)
    seqs = Seqs()
    subscriber.subscribe(seqs, publisher="p")
    # a bare paho client with our framing: documents 1-5 arrive, 6-8 never do, then its end at 8
    raw = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
    raw.connect("127.0.0.1", broker.port)
    raw.loop_start()
    try:
        topic = publisher_topic("p")
        for seq in range(1, 6):
            raw.publish(topic, b"ACX1 feedfeed %d\n<a/>" % seq, qos=1, retain=True)
        raw.publish(topic, b"ACE1 feedfeed 8", qos=1).wait_for_publish(5)
        assert wait_for(lambda: subscriber.stats()["ended"] == 1)
        stats = subscriber.stats()
        assert (len(seqs), stats["lost"], stats["malformed"]) == (5, 3, 0)
        # an end marker of another run (epoch) or below the last seen one counts nothing
        raw.publish(topic, b"ACE1 beefbeef 99", qos=1).wait_for_publish(5)
        raw.publish(topic, b"ACE1 feedfeed 4", qos=1).wait_for_publish(5)
        # an end marker with a body is not ours
        raw.publish(topic, b"ACE1 feedfeed 20\n<a/>", qos=1).wait_for_publish(5)
        assert wait_for(lambda: subscriber.stats()["malformed"] == 1)
        assert subscriber.stats()["lost"] == 3 and subscriber.stats()["ended"] == 3
    finally:
        raw.disconnect()
        raw.loop_stop()
        subscriber.close()


def test_with_a_payload_key_a_forged_end_marker_counts_nothing(broker: Broker) -> None:
    key = "k" * 32
    subscriber = MqttContextProvider(
        "127.0.0.1", broker.port, mirror=False, inline=True, payload_key=key
    )
    seqs = Seqs()
    subscriber.subscribe(seqs, publisher="p")
    publisher = MqttContextProvider("127.0.0.1", broker.port, mirror=False, payload_key=key)
    raw = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
    raw.connect("127.0.0.1", broker.port)
    raw.loop_start()
    try:
        publisher.publish("p", "<a/>")
        assert wait_for(lambda: len(seqs) == 1)
        raw.publish(publisher_topic("p"), b"ACE1 anything 1000", qos=1).wait_for_publish(5)
        assert wait_for(lambda: subscriber.stats()["forged"] == 1)
        assert publisher.close() == 0  # its own, signed, end marker: nothing missing
        assert wait_for(lambda: subscriber.stats()["ended"] == 1)
        assert subscriber.stats()["lost"] == 0
    finally:
        raw.disconnect()
        raw.loop_stop()
        publisher.close()
        subscriber.close()


def test_a_persistent_session_needs_a_client_id(broker: Broker) -> None:
    with pytest.raises(ContextError, match="clean_session=False needs a client_id"):
        MqttContextProvider("127.0.0.1", broker.port, clean_session=False)


def test_documents_that_come_late_are_delivered_and_no_longer_lost(broker: Broker) -> None:
    # a broker resuming a session may send a new document before those it queued meanwhile
    subscriber = MqttContextProvider("127.0.0.1", broker.port, mirror=False, inline=True)
    seqs = Seqs()
    subscriber.subscribe(seqs, publisher="p")
    raw = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
    raw.connect("127.0.0.1", broker.port)
    raw.loop_start()
    try:
        topic = publisher_topic("p")
        for seq in (1, 2, 5):
            raw.publish(topic, b"ACX1 feedfeed %d\n<a/>" % seq, qos=1).wait_for_publish(5)
        assert wait_for(lambda: len(seqs) == 3)
        assert subscriber.stats()["lost"] == 2
        for seq in (3, 4, 4):  # late, late, then a repeat
            raw.publish(topic, b"ACX1 feedfeed %d\n<a/>" % seq, qos=1).wait_for_publish(5)
        assert wait_for(lambda: subscriber.stats()["duplicates"] == 1)
        stats = subscriber.stats()
        assert (stats["lost"], stats["late"], stats["resynchronised"]) == (0, 2, 0), stats
        assert seqs.seen == {1, 2, 3, 4, 5}
        assert subscriber.latest("p")[0] == 5  # a late document is not the latest
    finally:
        raw.disconnect()
        raw.loop_stop()
        subscriber.close()
