"""The MQTT context provider's payloads (runtime/context/mqtt_wire.py): each written payload reads
back as written, its signature checked against an HMAC-SHA256 computed here from the documented
fields (topic, epoch, sequence number, body), and anything else on the topics is refused."""

from __future__ import annotations

import hashlib
import hmac

import pytest

from acordcs.runtime.context.mqtt_wire import (
    Payload,
    document_payload,
    end_payload,
    read_payload,
)

KEY = b"k" * 32
TOPIC = "acordcs/ctx/robot%2F1"
EPOCH = b"0123456789abcdef"


def oracle(topic: str, epoch: bytes, seq: int, body: bytes) -> bytes:
    return hmac.new(KEY, b"%s\n%s %d\n%s" % (topic.encode(), epoch, seq, body), hashlib.sha256).hexdigest().encode()  # fmt: skip


def test_a_document_reads_back_unsigned_and_signed():
    body = b"<robot><pos>3</pos></robot>"
    assert read_payload(document_payload(None, TOPIC, EPOCH, 7, body)) == Payload(
        EPOCH, 7, False, body, None
    )
    signed = document_payload(KEY, TOPIC, EPOCH, 7, body)
    assert signed.split(b"\n")[0].split(b" ")[3] == oracle(TOPIC, EPOCH, 7, body)
    read = read_payload(signed)
    assert read is not None and (read.epoch, read.seq, read.end, read.body) == (
        EPOCH,
        7,
        False,
        body,
    )
    assert read.signed_by(KEY, TOPIC)
    assert not read.signed_by(b"x" * 32, TOPIC)
    assert not read.signed_by(KEY, "acordcs/ctx/another")  # a signature is for its topic only
    assert not read_payload(document_payload(None, TOPIC, EPOCH, 7, body)).signed_by(KEY, TOPIC)


def test_an_end_marker_reads_back_and_its_signature_covers_no_document():
    read = read_payload(end_payload(KEY, TOPIC, EPOCH, 41))
    assert read is not None and (read.end, read.seq, read.body) == (True, 41, b"")
    assert read.mac == oracle(TOPIC, EPOCH, 41, b"\x00end")
    assert read.signed_by(KEY, TOPIC)
    # a document's signature does not make an end marker: the bodies differ
    doc = read_payload(document_payload(KEY, TOPIC, EPOCH, 41, b"<r/>"))
    forged_end = read_payload(b"ACE2 %s 41 %s" % (EPOCH, doc.mac))
    assert forged_end is not None and not forged_end.signed_by(KEY, TOPIC)
    assert read_payload(end_payload(None, TOPIC, EPOCH, 41)) == Payload(EPOCH, 41, True, b"", None)


@pytest.mark.parametrize(
    "payload",
    [
        b"<robot/>",
        b"ACX1 epoch\n<r/>",
        b"ACX1 epoch 1 extra\n<r/>",
        b"ACX3 epoch 1\n<r/>",
        b"ACX1 epoch -1\n<r/>",
        b"ACX1 epoch 1e3\n<r/>",
        b"ACX1 epoch " + b"9" * 20 + b"\n<r/>",
        b"ACX1  1\n<r/>",
        b"ACX1 " + b"e" * 65 + b" 1\n<r/>",
        b"ACE1 epoch 1\n<r/>",  # an end marker carries no document
        b"ACX2 epoch 1\n<r/>",  # signed, without its signature
        b"",
    ],
)
def test_anything_else_on_the_topics_is_refused(payload: bytes):
    assert read_payload(payload) is None
