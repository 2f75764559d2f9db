"""Many containers (issue 33's scale test, on loopback). Standalone:
``.venv/bin/python benchmarks/bench_many_containers.py [--counts 5 20 50] [--seconds 3]``.

For each count N: N container processes, each serving one component over our Pyro5 connector
(``ContainerServer``, the same object also registered bare), started at once: the time until all
serve, and each one's resident memory. Then one client process calls a small operation on every
container, round robin from 4 threads (each thread its own containers), for ``--seconds``: calls
per second and p50/p99 through our connector, then the same through bare Pyro5 proxies to the
same objects (the named peer, same run; alternated, twice each), and the CPU the containers
spent per call. Then the
time until all N have stopped (their standard input closed). The host's load is printed: the
figures of a loaded 2-core host vary from run to run by tens of percent.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import Pyro5.api

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from acordcs.runtime.ports import sync_port

THREADS = 4
PAYLOAD = {"angle": 12.5, "speed": 80}


class Echo(CtxComponent):
    ports = (sync_port("api"),)

    def echo(self, x: Any) -> Any:
        return x


class Caller(CtxComponent):
    ports = (sync_port("out", role="required"),)


def serve(name: str) -> None:
    """A container process: one Echo, served on a free loopback port, until stdin closes."""
    container = Container(name)
    container.install_factory(ComponentFactory("Echo", Pyro5.api.expose(Echo)))
    ref = container.create("Echo", "echo")
    server = ContainerServer(container, port=0)
    bare = server.daemon.register(ref.instance, "bare.echo")
    print("READY", server.uri, bare, flush=True)
    sys.stdin.read()
    server.close()
    container.close()


def cpu_seconds(pid: int) -> float:
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def call_for(seconds: float, callers: list[list]) -> tuple[int, list[float]]:
    """Each of ``callers`` (a thread's callables) called round robin for ``seconds``."""
    latencies: list[list[float]] = [[] for _ in callers]
    stop = time.monotonic() + seconds

    def work(i: int) -> None:
        mine, out = callers[i], latencies[i]
        clock = time.perf_counter
        while time.monotonic() < stop:
            for call in mine:
                t0 = clock()
                call()
                out.append(clock() - t0)

    threads = [threading.Thread(target=work, args=(i,)) for i in range(len(callers))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    merged = sorted(x for part in latencies for x in part)
    return len(merged), merged


def percentile(ordered: list[float], q: float) -> float:
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] * 1e3


def run(count: int, seconds: float) -> None:
    env = {k: v for k, v in os.environ.items() if k != "ACORDCS_TOKEN"}
    started = time.perf_counter()
    procs = [
        subprocess.Popen([sys.executable, __file__, "--serve", f"c{i}"], stdin=subprocess.PIPE,
                         stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
        for i in range(count)
    ]  # fmt: skip
    try:
        lines = [p.stdout.readline().split() for p in procs]
        start_s = time.perf_counter() - started
        if any(len(line) != 3 or line[0] != "READY" for line in lines):
            raise SystemExit(f"a container did not start: {lines}")
        memory = [rss_mb(p.pid) for p in procs]
        client = Container("client", clock=VirtualClock())
        client.install_factory(ComponentFactory("Caller", Caller))
        ours_calls: list[list] = [[] for _ in range(THREADS)]
        bare_calls: list[list] = [[] for _ in range(THREADS)]
        for i, (_, uri, bare_uri) in enumerate(lines):
            client.create("Caller", f"caller{i}")
            client.connect(f"caller{i}.out", RemotePort(uri, "echo", "api"),
                           connector=RemoteConnector(timeout=10.0))  # fmt: skip
            out = client.find(f"caller{i}").instance.port("out")
            ours_calls[i % THREADS].append(lambda out=out: out.call("echo", PAYLOAD))
            bare_calls[i % THREADS].append(bare_uri)

        def bare_callers() -> list[list]:
            """Proxies made in the calling threads' stead: one per container, claimed per call."""
            made = []
            for uris in bare_calls:
                row = []
                for uri in uris:
                    proxy = Pyro5.api.Proxy(uri)
                    proxy._pyroSerializer = "serpent"
                    proxy._pyroTimeout = 10.0

                    def call(proxy=proxy) -> None:
                        proxy._pyroClaimOwnership()
                        proxy.echo(PAYLOAD)

                    row.append(call)
                made.append(row)
            return made

        peers = bare_callers()
        call_for(0.5, ours_calls)  # connect and warm up both
        call_for(0.5, peers)
        # alternated, twice each: the load of a shared host changes within a run
        results: dict[str, list[tuple[int, list[float], float]]] = {"ours": [], "bare": []}
        for kind in ("ours", "bare", "ours", "bare"):
            cpu = sum(cpu_seconds(p.pid) for p in procs)
            n, lat = call_for(seconds, ours_calls if kind == "ours" else peers)
            results[kind].append((n, lat, sum(cpu_seconds(p.pid) for p in procs) - cpu))
        client.close()
        stopping = time.perf_counter()
        for p in procs:
            p.stdin.close()
        for p in procs:
            p.wait(timeout=60)
        stop_s = time.perf_counter() - stopping
    finally:
        for p in procs:
            if p.poll() is None:
                p.kill()
                p.wait()
    print(
        f"{count:>3} containers: all serving after {start_s:.2f} s, all stopped after "
        f"{stop_s:.2f} s; memory per container {statistics.median(memory):.1f} MB (median, "
        f"max {max(memory):.1f})"
    )
    for kind, label in (("ours", "ours"), ("bare", "bare Pyro5")):
        for n, lat, cpu in results[kind]:
            print(
                f"     {label}: {n / seconds:,.0f} calls/s, p50 {percentile(lat, 0.5):.2f} ms, "
                f"p99 {percentile(lat, 0.99):.2f} ms, containers' CPU "
                f"{cpu / max(n, 1) * 1e6:.0f} us/call"
            )
    best = {k: max(n for n, _, _ in v) for k, v in results.items()}
    print(f"     ours / bare Pyro5, calls per second (best of 2 each): "
          f"{best['ours'] / max(best['bare'], 1):.2f}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--serve", help=argparse.SUPPRESS)
    parser.add_argument("--counts", type=int, nargs="+", default=[5, 20, 50])
    parser.add_argument("--seconds", type=float, default=3.0, help="length of each call phase")
    args = parser.parse_args()
    if args.serve:
        serve(args.serve)
        return
    print(f"cores: {os.cpu_count()}, load average at start: {os.getloadavg()[0]:.2f}")
    print(f"== containers on loopback, {THREADS} calling threads, round robin ==")
    for count in args.counts:
        run(count, args.seconds)
    print(f"load average at end: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
