"""The MQTT half of issue 33's scale test, on loopback. Standalone:
``.venv/bin/python benchmarks/bench_mqtt_scale.py [--counts 5 50] [--monitors 500] [--seconds 5]``.

For each count N: one mosquitto started here, N container processes, each with one
``MqttContextProvider`` (QoS 1, ``mirror=False``); the processes together publish ``--monitors``
monitors' readings at ``--hz`` (500 at 10 Hz: 5,000 documents/s in all, each process its share)
and hold ``--subscriptions`` subscriptions (10,000: 20 per monitor, going round the processes
other than the monitor's, so that a document reaches up to 20 processes: the broker's fan-out
grows with the count). For ``--seconds``: end-to-end p50/p99 from publish to
callback (the stamp in each document, ``CLOCK_MONOTONIC`` being one clock for every process of
the host), documents received against those expected (losses), the providers' ``lost`` counts,
and each process's CPU (per second of the run) and resident memory; the broker's CPU too. The
load average is printed: on a shared 2-core host the figures say what this host holds, not what
the code costs.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path

import loopback_broker

from acordcs.runtime.context import MqttContextProvider

DOCUMENT = "<monitor><stamp>%d</stamp><value>%.3f</value><state>nominal</state></monitor>"


def cpu_seconds(pid: int) -> float:
    """User and system CPU seconds of process ``pid`` so far (``/proc/PID/stat``)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def resident_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def holder(j: int, count: int, monitors: int) -> int:
    """The process holding subscription ``j``, on monitor ``j % monitors`` (published by process
    ``monitor % count``): the monitor's subscriptions go round the other processes, so a document
    reaches min(subscriptions per monitor, count - 1) processes (one, with a single process)."""
    if count == 1:
        return 0
    owner = (j % monitors) % count
    return (owner + 1 + (j // monitors) % (count - 1)) % count


# -- a container process --------------------------------------------------------------------------
def container(index: int, count: int, port: int, args: argparse.Namespace) -> None:
    """Publish this process's monitors, subscribe its share of the subscriptions (each on a monitor
    of another process), report what it received as one JSON line."""
    mine = [m for m in range(args.monitors) if m % count == index]
    provider = MqttContextProvider("127.0.0.1", port, qos=1, mirror=False, flush_timeout=20)
    latencies: list[int] = []
    lock = threading.Lock()

    def took(note) -> None:
        stamp = int(note.nodes[0].text)
        now = time.monotonic_ns()
        with lock:
            latencies.append(now - stamp)

    subscribed: list[int] = []  # the monitor of each subscription here
    for j in range(args.subscriptions):
        if holder(j, count, args.monitors) == index:
            monitor = j % args.monitors
            provider.subscribe(took, "/monitor/stamp", f"monitor{monitor}", subscriber=("s", j))
            subscribed.append(monitor)
    print("READY", flush=True)
    sys.stdin.readline()  # every process has subscribed: go
    period = 1.0 / args.hz
    start = time.monotonic()
    rounds = int(args.seconds * args.hz)
    for r in range(rounds):
        delay = start + r * period - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        for m in mine:
            provider.publish(f"monitor{m}", DOCUMENT % (time.monotonic_ns(), r * 0.5))
    publishing = time.monotonic() - start  # longer than --seconds when the host falls behind
    time.sleep(2.0)  # the last round reaches the subscribers
    stats = provider.stats()
    unacknowledged = provider.close()
    with lock:
        samples = sorted(latencies)
    print(
        json.dumps(
            {
                "received": len(samples),
                "expected": sum(rounds for _ in subscribed),
                "p50": samples[len(samples) // 2] / 1e6 if samples else None,
                "p99": samples[int(len(samples) * 0.99)] / 1e6 if samples else None,
                "lost": stats["lost"],
                "dropped": stats["dropped"],
                "unacknowledged": unacknowledged,
                "published": rounds * len(mine),
                "publishing": publishing,
            }
        ),
        flush=True,
    )


# -- the driver -----------------------------------------------------------------------------------
def run(count: int, args: argparse.Namespace) -> None:
    with loopback_broker.loopback_broker() as port:
        broker = loopback_broker.PIDS.get(port)
        procs = [
            subprocess.Popen(
                [sys.executable, __file__, "--container", str(i), str(count), str(port)]
                + [
                    f"--{k}={getattr(args, k)}"
                    for k in ("monitors", "subscriptions", "hz", "seconds")
                ],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                text=True,
            )
            for i in range(count)
        ]
        for proc in procs:
            line = proc.stdout.readline()
            if not line.startswith("READY"):
                raise SystemExit(f"a container process did not start: {line!r}")
        cpu0 = {p.pid: cpu_seconds(p.pid) for p in procs}
        broker0 = cpu_seconds(broker) if broker else 0.0
        began = time.monotonic()
        for proc in procs:
            proc.stdin.write("go\n")
            proc.stdin.flush()
        time.sleep(args.seconds)
        wall = time.monotonic() - began
        cpu = [(cpu_seconds(p.pid) - cpu0[p.pid]) / wall for p in procs]
        memory = [resident_mb(p.pid) for p in procs]
        broker_cpu = (cpu_seconds(broker) - broker0) / wall if broker else float("nan")
        reports = [json.loads(p.communicate(timeout=120)[0].splitlines()[-1]) for p in procs]
    received = sum(r["received"] for r in reports)
    expected = sum(r["expected"] for r in reports)
    published = sum(r["published"] for r in reports)
    p50 = statistics.median(r["p50"] for r in reports if r["p50"] is not None)
    p99 = max(r["p99"] for r in reports if r["p99"] is not None)
    print(
        f"{count:3d} containers: {published / max(r['publishing'] for r in reports):,.0f} "
        f"documents/s published (asked: {args.monitors * args.hz:,.0f}), "
        f"{received / args.seconds:,.0f} notifications/s received; received {received:,} of "
        f"{expected:,} expected ({expected - received:,} not delivered when the processes "
        f"closed), lost (seq gaps) "
        f"{sum(r['lost'] for r in reports)}, dropped {sum(r['dropped'] for r in reports)}, "
        f"unacknowledged at close {sum(r['unacknowledged'] for r in reports)}"
    )
    print(
        f"     end to end: p50 {p50:.2f} ms (median of the containers'), p99 {p99:.2f} ms "
        f"(the worst container's); CPU per container {statistics.median(cpu) * 100:.1f}% of a "
        f"core (median, max {max(cpu) * 100:.1f}%), memory {statistics.median(memory):.1f} MB "
        f"(median); broker CPU {broker_cpu * 100:.1f}% of a core; load average {load()}"
    )


def load() -> str:
    return "/".join(f"{figure:.2f}" for figure in os.getloadavg())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--container", nargs=3, type=int, help=argparse.SUPPRESS)
    parser.add_argument("--counts", type=int, nargs="+", default=[5, 50])
    parser.add_argument("--monitors", type=int, default=500)
    parser.add_argument("--subscriptions", type=int, default=10_000)
    parser.add_argument("--hz", type=float, default=10.0)
    parser.add_argument("--seconds", type=float, default=5.0)
    args = parser.parse_args()
    if args.container:
        index, count, port = args.container
        container(index, count, port, args)
        return
    if not loopback_broker.available():
        print(f"mosquitto not installed ({loopback_broker.MOSQUITTO}): skipped")
        return
    print(
        f"cores: {os.cpu_count()}, load average at start: {load()}; {args.monitors} monitors at "
        f"{args.hz:g} Hz, {args.subscriptions:,} subscriptions, {args.seconds:g} s per count, QoS 1"
    )
    for count in args.counts:
        per_monitor = args.subscriptions // args.monitors
        print(
            f"-- {count} containers: each document to {min(per_monitor, max(count - 1, 1))} "
            f"process(es), {per_monitor} subscriptions per monitor"
        )
        run(count, args)
    print(f"load average at end: {load()}")


if __name__ == "__main__":
    main()
