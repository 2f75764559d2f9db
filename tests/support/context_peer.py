"""A context provider client in a process of its own, for tests that run it on another network host
(inside a network namespace): ``python -m tests.support.context_peer publish|subscribe BROKER ...``.

``publish BROKER COUNT RATE [KEEPALIVE]``: ``COUNT`` QoS 1 documents as publisher ``sensor`` at
``RATE``/s (``KEEPALIVE`` s between pings, default 30: a short one finds a dead link soon),
printing ``published N`` every 100, then ``close()``; last line: JSON
``{"unacknowledged": N, "reconnects": N}``.
``subscribe BROKER``: a persistent session (``clean_session=False``, client id ``context-peer``)
subscribed to ``sensor``; prints ``ready``; once the publisher's end marker has come (at most 90 s)
prints JSON with the sequence numbers received and its counters, and exits.
``retained BROKER TOPIC``: prints the document the broker keeps retained on ``TOPIC`` (its body,
without our header; nothing if none comes within 5 s)."""

from __future__ import annotations

import json
import sys
import threading
import time

from acordcs.runtime.context import ContextError, MqttContextProvider


def publish(broker: str, count: int, rate: float, keepalive: int = 30) -> None:
    provider = MqttContextProvider(broker, 1883, mirror=False, client_id="context-peer-publisher",
                                   keepalive=keepalive)  # fmt: skip
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
    unacknowledged = provider.close(timeout=30)
    print(json.dumps({"unacknowledged": unacknowledged, "reconnects": provider.reconnects}),
          flush=True)  # fmt: skip


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


def retained(broker: str, topic: str) -> None:
    import paho.mqtt.client as mqtt
    from paho.mqtt.enums import CallbackAPIVersion

    got = threading.Event()
    bodies: list[bytes] = []

    def on_message(_client, _userdata, message) -> None:
        bodies.append(message.payload.partition(b"\n")[2])
        got.set()

    client = mqtt.Client(CallbackAPIVersion.VERSION2)
    client.on_message = on_message
    client.on_connect = lambda c, *_: c.subscribe(topic, qos=1)
    client.connect(broker, 1883)
    client.loop_start()
    got.wait(5)
    client.loop_stop()
    client.disconnect()
    print(b"".join(bodies[:1]).decode(errors="replace"), flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "retained":
        retained(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "publish":
        publish(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]), *map(int, sys.argv[5:6]))
    else:
        subscribe(sys.argv[2])
