"""Hostile framing on the broker (issue 14): a sequence number of thousands of digits is a
malformed message, said in one warning line, not a traceback; the next real document arrives."""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from acordcs.runtime.context import MqttContextProvider, publisher_topic
from tests.support.services import Broker, wait_for

pytestmark = pytest.mark.service


@pytest.fixture
def broker(tmp_path: Path):
    server = Broker(tmp_path)
    server.start()
    yield server
    server.stop()


def test_a_5000_digit_sequence_number_is_malformed_without_a_traceback(broker, caplog) -> None:
    subscriber = MqttContextProvider("127.0.0.1", broker.port)
    raw = MqttContextProvider("127.0.0.1", broker.port)
    try:
        notes = []
        subscriber.subscribe(notes.append, publisher="p")
        topic = publisher_topic("p")
        with caplog.at_level(logging.DEBUG, logger="acordcs"):
            for seq in (b"9" * 5000, b"1" * 20):
                payload = b"ACX1 feedfeedfeedfeed " + seq + b"\n<a/>"
                raw._client.publish(topic, payload, qos=1).wait_for_publish(5)
            assert wait_for(lambda: subscriber.stats()["malformed"] == 2)
            raw.publish("p", "<a><b/></a>")
            assert wait_for(lambda: len(notes) == 1)
        assert not [r for r in caplog.records if r.exc_info], "a traceback was logged"
        warned = [r.getMessage() for r in caplog.records if r.levelno == logging.WARNING]
        assert len(warned) >= 2 and all(len(w) < 300 for w in warned), warned
        assert all("not an acordcs context document" in w for w in warned), warned
    finally:
        raw.close()
        subscriber.close()
