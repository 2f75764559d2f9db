"""Issue 33's scale test over MQTT, on network hosts made here: 5 hosts and one for the broker,
each a network namespace on a bridge with a link-local address (``tests/support/netns.py``: the
same hosts the namespaced tests make, torn down at the end). Needs root and mosquitto (exit 2
without them). Standalone:
``.venv/bin/python benchmarks/bench_mqtt_scale.py [--quick] [--counts 5 10 25 50] [--rates 5 2 1 0.5 0.2]``.

For each count N: a mosquitto of its own on the broker's host, N container processes spread
round robin over the 5 hosts, each with one ``MqttContextProvider`` (QoS 1, ``mirror=False``)
reaching the broker by a name only the hosts' own ``hosts`` files know. Each process publishes 10
monitors at ``--hz`` (10 Hz: 100 documents/s per process, 5,000 in all at 50; all the monitors
take turns over each period, an even stream rather than bursts) and holds 200
subscriptions (10,000 at 50): 20 per monitor, going round the processes other than the monitor's,
so that a document reaches min(20, N - 1) processes and every process receives 20 notifications
per document it publishes, at every count. For ``--seconds`` (at least 10 periods): each
process's CPU (% of a core, ``/proc/PID/stat``) and resident memory, the broker's CPU, memory and
messages per second in (the documents) and out (the PUBLISH packets it sent, its ``$SYS``
counter, read by a client on its host), end-to-end p50/p99 from
publish to callback (``CLOCK_MONOTONIC``: one clock for every namespace of the machine), the
notifications missing when the processes closed (each subscription's rounds, by round number;
twice too; and the providers' own sequence gaps), what was still unacknowledged at close (by
count), and the rates achieved against those asked (documents published per second over the
publishing; notifications delivered per second from the first arrival to the last). Then, at the
largest count, the rates per monitor of ``--rates`` from the highest down, until one holds:
nothing lost or left undelivered and both rates at least 95% of those asked. The load average is
printed: on a shared host the figures say what this host holds, not what the code costs.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import loopback_broker
import paho.mqtt.client as mqtt
from paho.mqtt.enums import CallbackAPIVersion

from acordcs.runtime.context import MqttContextProvider

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tests/ of the repository
from tests.support import netns

DOCUMENT = "<monitor><stamp>%d %d</stamp><value>%.3f</value><state>nominal</state></monitor>"
HOSTS = ("h1", "h2", "h3", "h4", "h5")
BROKER = "broker.scale.test"  # resolved by the hosts' own hosts files only
PORT = 1883
# PUBLISH packets the broker sent; mosquitto's count of those it received leaves out retained ones
# (its test of the packet type keeps the retain bit), which every document here is: the broker's
# input is the documents the containers published.
SYS_COUNTERS = ("$SYS/broker/publish/messages/sent",)
HOLDS = 0.95  # the share of the asked rates a step must achieve to hold
MIN_ROUNDS = 10  # a slow rate runs longer: its rates measured over at least this many periods


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


def rounds_for(seconds: float, hz: float) -> int:
    """The rounds each monitor publishes in a step: ``seconds`` of them, at least MIN_ROUNDS."""
    return max(round(seconds * hz), MIN_ROUNDS)


def load() -> str:
    return "/".join(f"{figure:.2f}" for figure in os.getloadavg())


# -- the processes on the hosts -------------------------------------------------------------------
def container(index: int, count: int, args: argparse.Namespace) -> None:
    """Publish this process's monitors, hold its share of the subscriptions (each on a monitor of
    another process); once told, wait for the last documents, close, report as one JSON line."""
    monitors = args.monitors_per_container * count
    mine = [m for m in range(monitors) if m % count == index]
    rounds = rounds_for(args.seconds, args.hz)
    provider = MqttContextProvider(BROKER, PORT, qos=1, mirror=False, flush_timeout=20)
    latencies: list[int] = []
    seen: dict[int, bytearray] = {}  # subscription -> times each round arrived
    lock = threading.Lock()
    complete = threading.Event()
    state = {"left": 0, "first": 0, "last": 0}

    def subscribe(j: int) -> None:
        counts = seen[j] = bytearray(rounds)

        def took(note) -> None:
            now = time.monotonic_ns()
            stamp, r = note.nodes[0].text.split()
            with lock:
                latencies.append(now - int(stamp))
                state["first"] = state["first"] or now
                state["last"] = now
                if counts[int(r)] == 0:
                    state["left"] -= 1
                    if state["left"] == 0:
                        complete.set()
                counts[int(r)] = min(counts[int(r)] + 1, 255)

        provider.subscribe(took, "/monitor/stamp", f"monitor{j % monitors}", subscriber=("s", j))

    total = args.subscriptions_per_container * count
    state["left"] = sum(rounds for j in range(total) if holder(j, count, monitors) == index)
    for j in range(total):
        if holder(j, count, monitors) == index:
            subscribe(j)
    print("READY", flush=True)
    sys.stdin.readline()  # every process has subscribed: go
    period = 1.0 / args.hz
    start = time.monotonic()
    for r in range(rounds):  # the monitors of all the processes take turns over each period
        for m in mine:
            delay = start + (r + m / monitors) * period - time.monotonic()
            if delay > 0:
                time.sleep(delay)
            provider.publish(f"monitor{m}", DOCUMENT % (time.monotonic_ns(), r, r * 0.5))
    publishing = time.monotonic() - start + period / monitors  # rounds / hz when on time
    print("PUBLISHED", flush=True)
    sys.stdin.readline()  # every process has published: the last documents are on their way
    complete.wait(args.drain)
    stats = provider.stats()
    unacknowledged = provider.close()
    with lock:
        samples = sorted(latencies)
        missing = sum(counts.count(0) for counts in seen.values())
        twice = sum(len(counts) - counts.count(0) - counts.count(1) for counts in seen.values())
    report = {
        "received": len(samples),
        "missing": missing,
        "twice": twice,
        "first": state["first"],
        "last": state["last"],
        "p50": samples[len(samples) // 2] / 1e6 if samples else None,
        "p99": samples[int(len(samples) * 0.99)] / 1e6 if samples else None,
        "seq_lost": stats["lost"],
        "dropped": stats["dropped"],
        "unacknowledged": unacknowledged,
        "published": rounds * len(mine),
        "publishing": publishing,
    }
    print(json.dumps(report), flush=True)


def sys_probe() -> None:
    """On the broker's host: for each line read (a ``CLOCK_MONOTONIC`` time in s), print as a JSON
    line each of the broker's ``$SYS`` counters as it last arrived by then (value, arrival time);
    READY once connected and the counters have arrived."""
    history: dict[str, list[tuple[int, float]]] = {}
    arrived = threading.Event()

    def on_message(_client, _userdata, message) -> None:
        history.setdefault(message.topic, []).append((int(message.payload), time.monotonic()))
        if len(history) == len(SYS_COUNTERS):
            arrived.set()

    client = mqtt.Client(CallbackAPIVersion.VERSION2, protocol=mqtt.MQTTv311)
    client.on_message = on_message
    client.on_connect = lambda c, *_: [c.subscribe(topic) for topic in SYS_COUNTERS]
    deadline = time.monotonic() + 10
    while True:  # the broker has just been started
        try:
            client.connect(BROKER, PORT)
            break
        except OSError:
            if time.monotonic() > deadline:
                raise
            time.sleep(0.05)
    client.loop_start()
    arrived.wait(10)
    print("READY", flush=True)
    for line in sys.stdin:
        when = float(line)
        latest = {
            topic: max((e for e in entries if e[1] <= when), default=entries[0], key=lambda e: e[1])
            for topic, entries in list(history.items())
        }
        print(json.dumps(latest), flush=True)
    client.loop_stop()


# -- the driver -----------------------------------------------------------------------------------
def spawn(host: netns.Host, *argv: str, stdout=subprocess.PIPE) -> subprocess.Popen:
    return subprocess.Popen(host.command(*argv), stdin=subprocess.PIPE, stdout=stdout, text=True)


def expect(proc: subprocess.Popen, word: str, what: str) -> None:
    line = proc.stdout.readline()
    if not line.startswith(word):
        raise SystemExit(f"{what} did not say {word}: {line!r} (exit {proc.poll()})")


def tell(procs: list[subprocess.Popen], word: str) -> None:
    for proc in procs:
        proc.stdin.write(word + "\n")
        proc.stdin.flush()


def broker_counters(probe: subprocess.Popen, when: float) -> dict[str, list]:
    """The broker's counters as they were at ``when`` (``time.monotonic()``)."""
    tell([probe], repr(when))
    return json.loads(probe.stdout.readline())


def per_second(before: dict, after: dict, began: float, topic: str) -> float:
    """The counter's growth per second from ``began`` (the broker idle until then, so ``before``
    still holds) to its last update in the window (``$SYS`` is updated once a second)."""
    v0, v1, t1 = before[topic][0], after[topic][0], after[topic][1]
    return (v1 - v0) / (t1 - began) if t1 > began else float("nan")


def step(network: netns.Network, count: int, hz: float, args: argparse.Namespace) -> bool:
    """One run of ``count`` containers at ``hz`` per monitor; prints its figures, returns whether
    this host held it."""
    args.hz = hz
    broker_host = network.hosts["broker"]
    workdir = Path(tempfile.mkdtemp(prefix="bench-scale-"))
    conf = loopback_broker.write_config(workdir, broker_host.address, PORT, "sys_interval 1\n")
    broker = spawn(broker_host, loopback_broker.MOSQUITTO, "-c", str(conf), stdout=None)
    me = [sys.executable, __file__]
    probe = spawn(broker_host, *me, "--sys-probe")
    procs = []
    try:
        expect(probe, "READY", "the $SYS client on the broker's host")
        options = [f"--{k}={getattr(args, k)}" for k in ("seconds", "hz", "drain")]
        options += [f"--monitors-per-container={args.monitors_per_container}"]
        options += [f"--subscriptions-per-container={args.subscriptions_per_container}"]
        for i in range(count):
            host = network.hosts[HOSTS[i % len(HOSTS)]]
            procs.append(spawn(host, *me, "--container", str(i), str(count), *options))
        for i, proc in enumerate(procs):
            expect(proc, "READY", f"container process {i}")
        load_before = load()
        cpu0 = {p.pid: cpu_seconds(p.pid) for p in procs}
        broker0 = cpu_seconds(broker.pid)
        counters0 = broker_counters(probe, time.monotonic())
        began = time.monotonic_ns()
        tell(procs, "go")
        for i, proc in enumerate(procs):
            expect(proc, "PUBLISHED", f"container process {i}")
        wall = (time.monotonic_ns() - began) / 1e9
        cpu = [(cpu_seconds(p.pid) - cpu0[p.pid]) / wall for p in procs]
        memory = [resident_mb(p.pid) for p in procs]
        broker_cpu = (cpu_seconds(broker.pid) - broker0) / wall
        broker_mb = resident_mb(broker.pid)
        counters1 = broker_counters(probe, time.monotonic())
        tell(procs, "drain")
        reports = [json.loads(p.communicate(timeout=180)[0].splitlines()[-1]) for p in procs]
        time.sleep(1.5)  # the broker's counters once every process has closed
        counters2 = broker_counters(probe, time.monotonic())
    finally:
        for proc in [*procs, probe, broker]:
            with contextlib.suppress(OSError):
                proc.stdin and proc.stdin.close()
            if proc.poll() is None:
                proc.terminate()
            proc.wait(timeout=30)
        conf.unlink()
        workdir.rmdir()
    return summarize(count, hz, args, reports, cpu, memory, broker_cpu, broker_mb, wall,
                     (counters0, counters1, counters2), (began, load_before))  # fmt: skip


def summarize(count, hz, args, reports, cpu, memory, broker_cpu, broker_mb, wall, counters,
              start) -> bool:  # fmt: skip
    began, load_before = start
    asked = count * args.monitors_per_container * hz
    asked_notes = asked * args.subscriptions_per_container / args.monitors_per_container
    published = sum(r["published"] for r in reports)
    received = sum(r["received"] for r in reports)
    achieved = published / max(r["publishing"] for r in reports)
    arrivals = max(r["last"] for r in reports) - min(r["first"] or began for r in reports)
    delivered = received / (arrivals / 1e9 + 1 / (hz * count * args.monitors_per_container))
    missing = sum(r["missing"] for r in reports)
    faults = {
        k: sum(r[k] for r in reports) for k in ("twice", "seq_lost", "dropped", "unacknowledged")
    }
    p50 = statistics.median(r["p50"] for r in reports if r["p50"] is not None)
    p99 = max(r["p99"] for r in reports if r["p99"] is not None)
    held = (
        missing == 0
        and not any(faults.values())
        and achieved >= HOLDS * asked
        and delivered >= HOLDS * asked_notes
    )
    print(
        f"{count:3d} containers at {hz:g} Hz: published {achieved:,.0f} documents/s (asked "
        f"{asked:,.0f}), delivered {delivered:,.0f} notifications/s (asked {asked_notes:,.0f}); "
        f"missing at close {missing:,} of {received + missing:,} notifications, twice "
        f"{faults['twice']}, providers' sequence gaps {faults['seq_lost']}, dropped "
        f"{faults['dropped']}, unacknowledged at close {faults['unacknowledged']}"
    )
    print(
        f"     end to end: p50 {p50:.2f} ms (median of the containers'), p99 {p99:.2f} ms (the "
        f"worst container's); CPU per container {statistics.median(cpu) * 100:.1f}% of a core "
        f"(median, max {max(cpu) * 100:.1f}%, all {sum(cpu) * 100:.0f}%), memory "
        f"{statistics.median(memory):.1f} MB (median, max {max(memory):.1f}) over {wall:.1f} s"
    )
    before, after, end = counters
    total_out = end[SYS_COUNTERS[0]][0] - before[SYS_COUNTERS[0]][0]
    print(
        f"     broker: CPU {broker_cpu * 100:.1f}% of a core, {broker_mb:.1f} MB, "
        f"{achieved:,.0f} PUBLISH/s in (the documents), "
        f"{per_second(before, after, began / 1e9, SYS_COUNTERS[0]):,.0f} PUBLISH/s out ($SYS, "
        f"while publishing), {total_out:,} out in all ({published:,} documents in)"
    )
    print(
        f"     load average {load_before} before, {load()} after: {'HELD' if held else 'NOT HELD'}"
    )
    return held


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--container", nargs=2, type=int, help=argparse.SUPPRESS)
    parser.add_argument("--sys-probe", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--quick", action="store_true", help="5 and 10 containers, 4 s each")
    parser.add_argument("--counts", type=int, nargs="+", default=[5, 10, 25, 50])
    parser.add_argument("--rates", type=float, nargs="+", default=[5, 2, 1, 0.5, 0.2],
                        help="Hz per monitor tried at the largest count when --hz does not hold")  # fmt: skip
    parser.add_argument("--hz", type=float, default=10.0)
    parser.add_argument("--monitors-per-container", type=int, default=10)
    parser.add_argument("--subscriptions-per-container", type=int, default=200)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument(
        "--drain", type=float, default=10.0, help="s to wait for the last documents"
    )
    args = parser.parse_args()
    if args.container:
        container(*args.container, args)
        return
    if args.sys_probe:
        sys_probe()
        return
    if os.geteuid() != 0:
        print("bench_mqtt_scale: the network hosts are namespaces (ip netns), which need root: "
              "run it as root (sudo)", file=sys.stderr)  # fmt: skip
        sys.exit(2)
    if not loopback_broker.available():
        print(f"bench_mqtt_scale: mosquitto is not installed ({loopback_broker.MOSQUITTO}): "
              "install the Debian package mosquitto", file=sys.stderr)  # fmt: skip
        sys.exit(2)
    if args.quick:
        args.counts, args.rates, args.seconds, args.drain = [5, 10], [5], 4.0, 5.0
    print(
        f"cores: {os.cpu_count()}, load average at start: {load()}; per container "
        f"{args.monitors_per_container} monitors at {args.hz:g} Hz and "
        f"{args.subscriptions_per_container} subscriptions (20 per monitor, on the monitors of "
        f"the other containers), {args.seconds:g} s per step (at least {MIN_ROUNDS} periods), QoS 1; containers round robin on "
        f"{len(HOSTS)} network hosts, mosquitto on a sixth"
    )
    network = netns.make_network(*HOSTS, "broker", hosts={BROKER: "broker"})
    try:
        held = {}
        for count in args.counts:
            held[count] = step(network, count, args.hz, args)
        top = max(args.counts)
        holds_at = args.hz if held[top] else None
        for hz in sorted((hz for hz in args.rates if hz < args.hz), reverse=True):
            if holds_at is not None:
                break
            print(f"-- {top} containers at {hz:g} Hz per monitor")
            holds_at = hz if step(network, top, hz, args) else None
        if holds_at is None:
            print(f"this host holds {top} containers at none of the rates tried")
        else:
            print(f"this host holds {top} containers at {holds_at:g} Hz per monitor")
    finally:
        network.teardown()
    print(f"load average at end: {load()}")


if __name__ == "__main__":
    main()
