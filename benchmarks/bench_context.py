"""Context provider benchmark (issue 5). Standalone: ``.venv/bin/python benchmarks/bench_context.py``.

1. Documents/s parsed and matched against N = 100, 1,000, 10,000 subscriptions of the form
   ``path[. op constant]`` (half for any publisher, half for one of 10 publishers), for the index and
   for the naive loop evaluating every subscription with lxml. Both are checked to agree.
2. Embedded publish -> callback latency (p50/p99).
3. Over a real mosquitto on loopback (started here, own config): publish -> callback latency and loss
   at 5,000 messages/s, the publisher in a separate process.
"""

from __future__ import annotations

import argparse
import os
import random
import subprocess
import sys
import threading
import time

import loopback_broker
from lxml import etree

from acordcs.runtime.context import (
    ContextError,
    ContextProvider,
    MqttContextProvider,
    SubscriptionIndex,
)
from acordcs.runtime.context.xmlparse import Limits, parse_document
from acordcs.runtime.context.xpathexpr import compile_expression, recognise

LEAVES = [
    "/robot/battery",
    "/robot/speed",
    "/robot/pose/x",
    "/robot/pose/y",
    "/robot/pose/theta",
    "/robot/net/bandwidth",
    "/robot/net/latency",
    "/robot/cpu/load",
    "/robot/cpu/temp",
    "/robot/users",
]
PUBLISHERS = [f"robot{i}" for i in range(10)]


def telemetry(rng: random.Random, stamp: int = 0) -> bytes:
    v = {leaf: f"{rng.uniform(0, 100):.2f}" for leaf in LEAVES}
    return (
        (
            "<robot><stamp>{}</stamp><battery>{}</battery><speed>{}</speed>"
            "<pose><x>{}</x><y>{}</y><theta>{}</theta></pose>"
            "<net><bandwidth>{}</bandwidth><latency>{}</latency></net>"
            "<cpu><load>{}</load><temp>{}</temp></cpu><users>{}</users></robot>"
        )
        .format(stamp, *(v[leaf] for leaf in LEAVES))
        .encode()
    )


def subscriptions(n: int, rng: random.Random) -> list[tuple[str, str | None]]:
    """Alarm-like subscriptions: thresholds spread well beyond the values (a few percent fire)."""
    subs = []
    for _ in range(n):
        leaf, op = rng.choice(LEAVES), rng.choice([">", ">=", "<", "<=", "="])
        if op in (">", ">="):
            const = f"{rng.uniform(0, 1000):.2f}"
        elif op in ("<", "<="):
            const = f"{rng.uniform(-900, 100):.2f}"
        else:
            const = f"{rng.uniform(0, 100):.2f}"
        publisher = None if rng.random() < 0.5 else rng.choice(PUBLISHERS)
        subs.append((f"{leaf}[. {op} {const}]", publisher))
    return subs


class Sub:
    __slots__ = ("__weakref__", "compiled", "publisher", "xpath")

    def __init__(self, xpath: str, publisher: str | None) -> None:
        self.xpath, self.publisher = xpath, publisher
        self.compiled = compile_expression(xpath, 4096)


def naive(subs: list[Sub], tree: etree._ElementTree, publisher: str) -> list:
    out = []
    for sub in subs:
        if sub.publisher is not None and sub.publisher != publisher:
            continue
        nodes = sub.compiled(tree)
        if nodes:
            out.append((sub, nodes))
    return out


def bench_throughput() -> None:
    print("== documents/s parsed + matched (300-byte telemetry document) ==")
    rng = random.Random(5)
    docs = [(rng.choice(PUBLISHERS), telemetry(rng, i)) for i in range(2000)]
    limits = Limits()
    print(f"{'N':>7} {'index docs/s':>13} {'naive docs/s':>13} {'ratio':>7} {'matches/doc':>12}")
    for n in (100, 1000, 10_000):
        subs = [Sub(x, p) for x, p in subscriptions(n, rng)]
        index = SubscriptionIndex()
        for sub in subs:
            index.add(sub, sub.publisher, recognise(sub.xpath), sub.compiled)
        # the index must agree with the naive loop before it is timed
        for publisher, data in docs[:20]:
            tree = parse_document(publisher, data, limits)
            got = {
                id(s): [tree.getpath(x) for x in nodes]
                for subs, nodes, _ in index.match(tree, publisher)
                for s in subs
            }
            want = {
                id(s): [tree.getpath(x) for x in nodes] for s, nodes in naive(subs, tree, publisher)
            }
            assert got == want, "index and naive loop disagree"
        matched = 0
        best = 0.0
        for _ in range(3):
            started = time.perf_counter()
            for publisher, data in docs:
                chunks = index.match(parse_document(publisher, data, limits), publisher)
                matched += sum(len(subs) for subs, _, _ in chunks)
            best = max(best, len(docs) / (time.perf_counter() - started))
        naive_docs = docs[: max(20, 20_000 // n)]
        started = time.perf_counter()
        for publisher, data in naive_docs:
            naive(subs, parse_document(publisher, data, limits), publisher)
        slow = len(naive_docs) / (time.perf_counter() - started)
        print(
            f"{n:>7} {best:>13,.0f} {slow:>13,.0f} {best / slow:>6.0f}x {matched / (3 * len(docs)):>12.1f}"
        )


def percentiles(samples_ns: list[int]) -> str:
    ordered = sorted(samples_ns)
    p50 = ordered[len(ordered) // 2] / 1e3
    p99 = ordered[int(len(ordered) * 0.99)] / 1e3
    return f"p50 {p50:.1f} us, p99 {p99:.1f} us"


def _embedded_latency(
    background: list[tuple[str, str | None]], samples: int
) -> tuple[list[int], float]:
    rng = random.Random(7)
    with ContextProvider() as provider:
        fired = [0]

        def other(note, fired=fired) -> None:
            fired[0] += 1

        for xpath, publisher in background:
            provider.subscribe(other, xpath, publisher)
        got = threading.Event()
        stamp = [0]

        def callback(note) -> None:
            stamp[0] = time.perf_counter_ns()
            got.set()

        provider.subscribe(callback, "/robot/battery[. >= 0]", "robot0")
        data = telemetry(rng)
        latencies = []
        for i in range(samples):
            got.clear()
            started = time.perf_counter_ns()
            provider.publish("robot0", data)
            got.wait(5)
            if i >= 100:  # warm-up
                latencies.append(stamp[0] - started)
        time.sleep(0.2)
        return latencies, fired[0] / samples


def bench_embedded_latency(samples: int = 3000) -> None:
    print("== embedded publish -> callback (callbacks run in the provider's delivery threads) ==")
    rng = random.Random(11)
    quiet = [(x, p) for x, p in subscriptions(1000, rng) if p is not None and p != "robot0"]
    busy = subscriptions(1000, rng)
    for label, background in (
        ("alone", []),
        (f"{len(quiet)} other subscriptions indexed, none for this publisher", quiet),
        ("1,000 other subscriptions indexed, some firing", busy),
    ):
        latencies, fired = _embedded_latency(background, samples)
        print(f"{label}: {percentiles(latencies)}; other callbacks per document: {fired:.1f}")


def mqtt_publisher(port: int, rate: int, count: int, qos: int) -> None:
    """Runs in a child process: publish ``count`` documents at ``rate``/s with a monotonic timestamp."""
    rng = random.Random(9)
    with MqttContextProvider("127.0.0.1", port, qos=qos, mirror=False) as provider:
        template = telemetry(rng).replace(b"<stamp>0</stamp>", b"<stamp>%d</stamp>")
        interval = 1.0 / rate
        start = time.monotonic()
        for i in range(count):
            delay = start + i * interval - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            try:
                provider.publish("robot0", template % time.monotonic_ns())
            except (
                ContextError
            ) as err:  # e.g. the client's queue is full: the machine cannot keep up
                print(f"publisher stopped after {i} documents: {err}")
                sys.exit(1)
        time.sleep(0.5)  # let the last QoS 0 messages leave the socket


def bench_mqtt(rate: int = 5000, seconds: float = 4.0) -> None:
    print(f"== over mosquitto (loopback), publisher in another process, {rate} msg/s ==")
    if not loopback_broker.available():
        print(f"mosquitto not installed ({loopback_broker.MOSQUITTO}): skipped")
        return
    with loopback_broker.loopback_broker() as port:
        count = int(rate * seconds)
        for qos in (0, 1):
            latencies: list[int] = []
            done = threading.Event()

            def callback(note, latencies=latencies, done=done, count=count) -> None:
                latencies.append(time.monotonic_ns() - int(note.nodes[0].text))
                if len(latencies) >= count:
                    done.set()

            with MqttContextProvider("127.0.0.1", port, qos=qos, mirror=False) as subscriber:
                subscriber.subscribe(callback, "/robot/stamp", "robot0", queue_size=100_000)
                child = subprocess.Popen(
                    [
                        sys.executable,
                        __file__,
                        "--mqtt-publisher",
                        str(port),
                        str(rate),
                        str(count),
                        str(qos),
                    ]
                )
                child.wait(timeout=60)
                done.wait(5 if child.returncode == 0 else 1)
                stats = subscriber.stats()
            received = len(latencies)
            print(
                f"QoS {qos}: sent {count}, received {received}, lost (seq gaps) {stats['lost']}, "
                f"dropped in mailbox {stats['dropped']}; {percentiles(latencies) if latencies else 'no samples'}"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--mqtt-publisher", nargs=4, type=int, metavar=("PORT", "RATE", "COUNT", "QOS")
    )
    args = parser.parse_args()
    if args.mqtt_publisher:
        port, rate, count, qos = args.mqtt_publisher
        mqtt_publisher(port, rate, count, qos)
        return
    started = time.perf_counter()
    # the figures depend on what else runs: say so
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()[0]:.2f}")
    bench_throughput()
    bench_embedded_latency()
    bench_mqtt()
    print(
        f"load average at end: {os.getloadavg()[0]:.2f}; total {time.perf_counter() - started:.0f} s"
    )


if __name__ == "__main__":
    main()
