"""A context provider client in a process of its own, for tests that run it on another network host
(inside a network namespace): ``python -m tests.support.context_peer publish|subscribe BROKER ...``.

``publish BROKER COUNT RATE``: ``COUNT`` QoS 1 documents as publisher ``sensor`` at ``RATE``/s,
printing ``published N`` every 100, then ``close()``; last line: JSON ``{"unacknowledged": N}``.
``subscribe BROKER``: a persistent session (``clean_session=False``, client id ``context-peer``)
subscribed to ``sensor``; prints ``ready``; once the publisher's end marker has come (at most 90 s)
prints JSON with the sequence numbers received and its counters, and exits."""

from __future__ import annotations

import json
import sys
import threading
import time

from acordcs.runtime.context import ContextError, MqttContextProvider


def publish(broker: str, count: int, rate: float) -> None:
    provider = MqttContextProvider(broker, 1883, mirror=False, client_id="context-peer-publisher")
    start = time.monotonic()
    for i in range(1, count + 1):
        delay = start + i / rate - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        while True:
            try:
                provider.publish("sensor", f"<sensor><i>{i}</i></sensor>")
                break
            except ContextError:  # the client's queue is full while the broker is away
                provider.flush(0.05)
        if i % 100 == 0:
            print(f"published {i}", flush=True)
    print(json.dumps({"unacknowledged": provider.close(timeout=30)}), flush=True)


def subscribe(broker: str) -> None:
    provider = MqttContextProvider(broker, 1883, mirror=False, inline=True,
                                   client_id="context-peer", clean_session=False)  # fmt: skip
    seqs: list[int] = []
    lock = threading.Lock()

    def took(note) -> None:
        with lock:
            seqs.append(note.seq)

    provider.subscribe(took, "/sensor/i", "sensor")
    print("ready", flush=True)
    deadline = time.monotonic() + 90
    while provider.stats()["ended"] < 1 and time.monotonic() < deadline:
        time.sleep(0.05)
    with lock:
        got = list(seqs)
    stats = provider.stats()
    provider.close()
    print(json.dumps({"seqs": got, **{k: stats[k] for k in
                      ("lost", "duplicates", "reconnects", "ended", "malformed", "late")}}), flush=True)  # fmt: skip


if __name__ == "__main__":
    if sys.argv[1] == "publish":
        publish(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]))
    else:
        subscribe(sys.argv[2])
