"""The payloads of the MQTT context provider (:mod:`.mqtt`): what a context document and the end
of a publisher's sequence look like on the broker, written and read here only.

A document is a header line and the XML: ``ACX1 <epoch> <seq>``, or signed with the application's
key ``ACX2 <epoch> <seq> <hmac-sha256 hex>`` (the HMAC covers the topic, the epoch, the sequence
number and the document). The end of a publisher's sequence (sent by ``close()``, not retained)
is a header alone, ``ACE1 <epoch> <seq>`` or signed ``ACE2 ...``: ``<seq>`` is its last
document's number, so that subscribers count a tail lost after their last document as lost.
Everything else on a provider's topics is refused (:func:`read_payload`)."""

from __future__ import annotations

import hashlib
import hmac
from typing import NamedTuple

DOCUMENT = b"ACX1"
SIGNED_DOCUMENT = b"ACX2"
END = b"ACE1"
SIGNED_END = b"ACE2"
END_BODY = b"\x00end"  # what an end marker's signature covers: no document has this body
MAX_SEQ_DIGITS = 19  # a sequence number fits 63 bits; longer is not ours
MAX_EPOCH_BYTES = 64


def signature(key: bytes, topic: str, epoch: bytes, seq: int, body: bytes) -> bytes:
    """The HMAC-SHA256 (hex) of a payload on ``topic``."""
    mac = hmac.new(key, b"%s\n%s %d\n" % (topic.encode(), epoch, seq), hashlib.sha256)
    mac.update(body)
    return mac.hexdigest().encode()


def document_payload(key: bytes | None, topic: str, epoch: bytes, seq: int, data: bytes) -> bytes:
    """The payload of document ``data``, number ``seq`` of the publisher of ``topic``."""
    if key is None:
        return b"%s %s %d\n%s" % (DOCUMENT, epoch, seq, data)
    mac = signature(key, topic, epoch, seq, data)
    return b"%s %s %d %s\n%s" % (SIGNED_DOCUMENT, epoch, seq, mac, data)


def end_payload(key: bytes | None, topic: str, epoch: bytes, seq: int) -> bytes:
    """The end of the sequence of the publisher of ``topic``, whose last document was ``seq``."""
    if key is None:
        return b"%s %s %d" % (END, epoch, seq)
    mac = signature(key, topic, epoch, seq, END_BODY)
    return b"%s %s %d %s" % (SIGNED_END, epoch, seq, mac)


class Payload(NamedTuple):
    """A payload read: the publisher's ``epoch`` and ``seq``, whether it ends the sequence
    (``end``, no ``body``), the document's ``body``, and the signature it carries (None: none).
    A tuple: one is made for every message received."""

    epoch: bytes
    seq: int
    end: bool
    body: bytes
    mac: bytes | None

    def signed_by(self, key: bytes, topic: str) -> bool:
        """Whether the payload carries a valid signature with ``key`` for ``topic``."""
        if self.mac is None:
            return False
        body = END_BODY if self.end else self.body
        return hmac.compare_digest(self.mac, signature(key, topic, self.epoch, self.seq, body))


def read_payload(payload: bytes) -> Payload | None:
    """``payload`` read, or None when it is not a context document or an end marker."""
    header, _, body = payload.partition(b"\n")
    parts = header.split(b" ")
    end = parts[0] in (END, SIGNED_END)
    signed = len(parts) == 4 and parts[0] in (SIGNED_DOCUMENT, SIGNED_END)
    if (
        not (signed or (len(parts) == 3 and parts[0] in (DOCUMENT, END)))
        or (end and body)
        or not parts[2].isdigit()
        or len(parts[2]) > MAX_SEQ_DIGITS
        or not 0 < len(parts[1]) <= MAX_EPOCH_BYTES
    ):
        return None
    return Payload(parts[1], int(parts[2]), end, body, parts[3] if signed else None)
