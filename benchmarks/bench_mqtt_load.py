"""MQTT load benchmark (issue 14). Standalone: ``.venv/bin/python benchmarks/bench_mqtt_load.py``.

Over a mosquitto started here on loopback, QoS 1, retained, the publisher in another process:

1. Saturation throughput: ``--count`` documents published as fast as the publisher can, received
   by a subscriber in this process; our provider at both ends beside bare paho-mqtt at both ends
   (same payload, QoS, retain, in-flight window and TCP_NODELAY), in the same run.
2. Latency at a fixed rate (``--rate``, 2,000 documents/s, for ``--seconds`` per kind, in
   ``--slices`` slices, the kinds taking turns): p50/p99 from publish to the subscriber's callback,
   and loss (documents sent but not received).

``ours`` is the provider as configured by default (a quick callback runs in paho's network thread
once seen quick), ``ours-threads`` always delivers through the delivery threads (``inline=False``),
``ours-inline`` always in paho's network thread (``inline=True``); all publish with the provider.
Bare paho sends the same bytes. Every figure is also printed as a ratio to paho's in the same run;
``--repeat`` runs the whole comparison again (the load average is printed before each).
"""

from __future__ import annotations

import argparse
import os
import random
import socket
import subprocess
import sys
import threading
import time

import loopback_broker
import paho.mqtt.client as mqtt
from paho.mqtt.enums import CallbackAPIVersion

from acordcs.runtime.context import ContextError, MqttContextProvider

TOPIC = "acordcs/ctx/robot0"


def telemetry(stamp_marker: bytes = b"%d") -> bytes:
    """A 300-byte robot telemetry document whose <stamp> is a monotonic_ns placeholder."""
    rng = random.Random(9)
    values = "".join(f"<v{i}>{rng.uniform(0, 100):.3f}</v{i}>" for i in range(10))
    return b"<robot><stamp>" + stamp_marker + b"</stamp>" + values.encode() + b"</robot>"


def stamp_of(document: bytes) -> int | None:
    """The stamp of a document; None for a payload without one (the provider's end marker)."""
    start = document.find(b"<stamp>") + 7
    if start < 7:
        return None
    return int(document[start : document.index(b"<", start)])


def paho_client() -> mqtt.Client:
    client = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
    client.max_inflight_messages_set(1000)
    client.max_queued_messages_set(10_000)
    client.on_socket_open = lambda c, u, sock: sock.setsockopt(
        socket.IPPROTO_TCP, socket.TCP_NODELAY, 1
    )
    return client


# -- publisher (child process) ----------------------------------------------------------------------
def publish(kind: str, port: int, rate: int, count: int) -> None:
    """Publish ``count`` documents at ``rate``/s (0: as fast as possible) with ``kind``'s client."""
    template = telemetry()
    # bare paho sends the bytes the provider sends (its header: magic, epoch, sequence number)
    header = b"ACX1 0123456789abcdef %d\n" + template
    interval = 1.0 / rate if rate else 0.0
    if kind == "ours":
        provider = MqttContextProvider("127.0.0.1", port, qos=1, mirror=False)

        def send(data: bytes) -> None:
            while True:  # the client's queue is full: wait for the broker
                try:
                    provider.publish("robot0", data)
                    return
                except ContextError:
                    time.sleep(0.0005)

    else:
        client = paho_client()
        client.connect("127.0.0.1", port)
        client.loop_start()
        infos: list[mqtt.MQTTMessageInfo] = []

        def send(data: bytes) -> None:
            while True:  # a full client queue: wait for the broker, as the provider's caller would
                info = client.publish(TOPIC, data, qos=1, retain=True)
                if info.rc == mqtt.MQTT_ERR_SUCCESS:
                    infos.append(info)
                    return
                time.sleep(0.0005)

    start = time.monotonic()
    for i in range(count):
        if interval:
            delay = start + i * interval - time.monotonic()
            if delay > 0:
                time.sleep(delay)
        send(
            template % time.monotonic_ns()
            if kind == "ours"
            else header % (i + 1, time.monotonic_ns())
        )
    if kind == "ours":
        provider.close()  # flushes: waits for the broker's acknowledgements
    else:
        for info in infos[-1000:]:
            info.wait_for_publish(10)
        client.disconnect()
        client.loop_stop()


# -- subscriber (this process) ------------------------------------------------------------------------
class Receiver:
    def __init__(self, count: int) -> None:
        self.count = count
        self.latencies: list[int] = []
        self.first = self.last = 0.0
        self.done = threading.Event()
        self.cpu = 0.0  # CPU seconds of this process (the subscriber's threads) during the run

    def took(self, stamp: int) -> None:
        now = time.monotonic_ns()
        if not self.latencies:
            self.first = now / 1e9
        self.latencies.append(now - stamp)
        self.last = now / 1e9
        if len(self.latencies) >= self.count:
            self.done.set()


def subscribe(kind: str, port: int, receiver: Receiver):
    """A subscriber of ``kind`` feeding ``receiver``; returns its closer."""
    if kind.startswith("ours"):
        inline = {"ours": None, "ours-threads": False, "ours-inline": True}[kind]
        provider = MqttContextProvider("127.0.0.1", port, qos=1, mirror=False, inline=inline)
        provider.subscribe(
            lambda note: receiver.took(int(note.nodes[0].text)),
            "/robot/stamp",
            "robot0",
            queue_size=1_000_000,
        )
        return provider.close, provider.stats
    client = paho_client()
    subscribed = threading.Event()
    client.on_message = lambda c, u, m: (
        None if (stamp := stamp_of(m.payload)) is None else receiver.took(stamp)
    )
    client.on_subscribe = lambda *a: subscribed.set()
    client.connect("127.0.0.1", port)
    client.loop_start()
    client.subscribe(TOPIC, qos=1)
    subscribed.wait(5)

    def close() -> None:
        client.disconnect()
        client.loop_stop()

    return close, lambda: {}


def run(
    kind: str, port: int, rate: int, count: int, publisher: str | None = None
) -> tuple[Receiver, dict]:
    """``count`` documents from a ``publisher`` (default: ``kind``) client to a ``kind`` one."""
    receiver = Receiver(count)
    close, stats = subscribe(kind, port, receiver)
    cpu = time.process_time()
    try:
        child = subprocess.Popen(
            [sys.executable, __file__, "--publisher", publisher or kind, str(port), str(rate),
             str(count)]
        )  # fmt: skip
        child.wait(timeout=600)
        receiver.done.wait(10)
        receiver.cpu = time.process_time() - cpu
        return receiver, stats()
    finally:
        close()


def percentile(samples: list[int], q: float) -> float:
    ordered = sorted(samples)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] / 1e6


def clear_retained(port: int) -> None:
    client = paho_client()
    client.connect("127.0.0.1", port)
    client.loop_start()
    client.publish(TOPIC, b"", qos=1, retain=True).wait_for_publish(5)
    client.disconnect()
    client.loop_stop()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--publisher", nargs=4, metavar=("KIND", "PORT", "RATE", "COUNT"))
    parser.add_argument("--count", type=int, default=20_000, help="documents for saturation")
    parser.add_argument("--rate", type=int, default=2000, help="documents/s for the latency run")
    parser.add_argument("--seconds", type=float, default=10.0, help="length of the latency run")
    parser.add_argument("--slices", type=int, default=5, help="turns of the latency run per kind")
    parser.add_argument("--repeat", type=int, default=1, help="runs of the whole comparison")
    args = parser.parse_args()
    if args.publisher:
        kind, port, rate, count = args.publisher
        publish(kind, int(port), int(rate), int(count))
        return
    if not loopback_broker.available():
        print(f"mosquitto not installed ({loopback_broker.MOSQUITTO}): skipped")
        return
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()[0]:.2f}")
    with loopback_broker.loopback_broker() as port:
        for run_number in range(1, args.repeat + 1):
            if args.repeat > 1:
                print(f"#### run {run_number} of {args.repeat}, load average {load()}")
            compare(port, args)
    print(f"load average at end: {load()}")


def load() -> str:
    return "/".join(f"{figure:.2f}" for figure in os.getloadavg())


KINDS = ("paho", "ours", "ours-threads", "ours-inline")


def compare(port: int, args: argparse.Namespace) -> None:
    """Saturation and latency of every kind, with their ratios to bare paho's."""
    print(f"== saturation, QoS 1, retained, {args.count} documents of {len(telemetry())} B ==")
    rates: dict[str, list[float]] = {}
    for kind in KINDS + KINDS:  # interleaved: the load may change
        clear_retained(port)
        receiver, _ = run(kind, port, 0, args.count, publisher=kind[:4])
        got = len(receiver.latencies)
        span = max(receiver.last - receiver.first, 1e-9)
        rate = (got - 1) / span if got > 1 else 0.0
        rates.setdefault(kind, []).append(rate)
        cpu = receiver.cpu / max(got, 1) * 1e6
        print(
            f"{kind:>12}: received {got}/{args.count}, {rate:,.0f} documents/s, "
            f"subscriber's CPU {cpu:.0f} us/document"
        )
    best = {k: max(v) for k, v in rates.items()}
    for kind in KINDS[1:]:
        print(
            f"{kind} / bare paho (best of 2 each): {best[kind] / best['paho']:.2f} "
            f"({best[kind]:,.0f} vs {best['paho']:,.0f} documents/s)"
        )
    # in slices, the kinds taking turns: a host whose load changes by the second changes it for
    # every kind alike (10 s of one kind after 10 s of another compared two different hosts)
    count = max(1, int(args.rate * args.seconds / args.slices))
    print(
        f"== latency, QoS 1, {args.rate} documents/s for {args.seconds:g} s per kind, in "
        f"{args.slices} slices taking turns, load {load()} =="
    )
    samples: dict[str, list[int]] = {kind: [] for kind in KINDS}
    lost: dict[str, int] = dict.fromkeys(KINDS, 0)
    for _ in range(args.slices):
        for kind in KINDS:
            clear_retained(port)
            receiver, stats = run(kind, port, args.rate, count, publisher=kind[:4])
            samples[kind] += receiver.latencies
            lost[kind] += int(stats.get("lost", 0))
    figures: dict[str, tuple[float, float]] = {}
    sent = count * args.slices
    for kind in KINDS:
        got = samples[kind]
        extra = f", lost (seq gaps) {lost[kind]}" if kind != "paho" else ""
        if got:
            figures[kind] = (percentile(got, 0.5), percentile(got, 0.99))
        print(
            f"{kind:>12}: sent {sent}, received {len(got)} (missing {sent - len(got)}{extra}); "
            + (f"p50 {figures[kind][0]:.2f} ms, p99 {figures[kind][1]:.2f} ms" if got else "none")
        )
    if "paho" in figures:
        paho50, paho99 = figures["paho"]
        for kind in KINDS[1:]:
            if kind in figures:
                p50, p99 = figures[kind]
                print(
                    f"{kind} / bare paho, same run: p50 {p50 / paho50:.2f}, p99 {p99 / paho99:.2f}"
                )


if __name__ == "__main__":
    main()
