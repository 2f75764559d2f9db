"""Runtime benchmarks (standalone; prints figures, asserts nothing). Takes well under 2 minutes.

1. Adaptation latency in-process: a monitor reading (or a component property change) -> the speed
   limiting policy set fired (the project's fuzzy engine if present, else a crisp one) -> the new
   speed written to the component. p50 / p99 over many changes.
2. A remote call through our Pyro5 connector against a bare Pyro5 call to the same object in the
   same server process (serpent both; target: at most 1.2 at p50 and p90, issue 33), with a
   control: a second bare proxy to a second object, whose ratio to the first shows this run's
   noise. Each round makes the three calls in an order rotated through all six orders
   (``--fixed-order``: ours then bare, as first designed). The caller and the server each run on
   a CPU of their own (``--no-pin``: where the scheduler puts them). ``--calibrate`` adds two bare
   calls with 15 us of CPU spent in the server or in the caller: what that much more code costs.
3. Virtual-time speed-up of an idle container with 10 monitors at 10 Hz (simulated s per wall s).

Usage: python benchmarks/bench_runtime.py [--quick] [--fixed-order] [--no-pin] [--calibrate]
"""

from __future__ import annotations

import argparse
import itertools
import os
import select
import socket
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any, ClassVar

import Pyro5.api

from acordcs.engines.engine_registry import EngineSetup, Variable, lookup_engine, register_engine
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from acordcs.runtime.errors import EngineNotAvailableError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.policy import PolicySet
from acordcs.runtime.ports import sync_port

SPEED_RULES = [
    "slow1: if cycleRate is small and angle is narrow then Locomotion.speed is slow",
    "med1: if cycleRate is medium and angle is narrow then Locomotion.speed is medium",
    "fast1: if cycleRate is large and angle is narrow then Locomotion.speed is fast",
    "slow2: if cycleRate is small and angle is wide then Locomotion.speed is slow",
    "slow3: if cycleRate is medium and angle is wide then Locomotion.speed is slow",
    "med2: if cycleRate is large and angle is wide then Locomotion.speed is medium",
]
VARIABLES = {
    "control.cycleRate": Variable(
        0, 3, "small := trape 0 0 0.8 1.2; medium := trian 0.8 1.4 2.0; large := trape 1.6 2.2 3 3"
    ),
    "control.angle": Variable(0, 90, "narrow := trape 0 0 20 45; wide := trape 20 45 90 90"),
    "Locomotion.speed": Variable(
        0, 200, "slow := trape 0 0 40 80; medium := trian 50 100 150; fast := trian 120 200 200"
    ),
}
CRISP_RULES = [
    "if control.cycleRate < 1.2 then Locomotion.speed = 40",
    "if control.cycleRate >= 1.2 and control.angle < 30 then Locomotion.speed = 140",
    "if control.cycleRate >= 1.2 and control.angle >= 30 then Locomotion.speed = 60",
]


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 100.0}


class Control(Monitor):
    pass


class MiniCrisp:
    """A fallback crisp engine (first-match thresholds) used only if no project engine exists."""

    def __init__(self, setup: EngineSetup) -> None:
        from acordcs.rules import parse_rule

        self.parse = parse_rule
        self.values: dict[str, Any] = {}
        self.rules: dict[str, list[Any]] = {}

    def defrule(self, rule: str, ruleset: str) -> str:
        self.rules.setdefault(ruleset, []).append(self.parse(rule, "crisp"))
        return str(len(self.rules[ruleset]))

    def set(self, variable: str, value: object) -> None:
        self.values[variable] = value

    def get(self, variable: str) -> object:
        return self.values.get(variable)

    def fire(self, ruleset: str) -> None:
        rate, angle = self.values["control.cycleRate"], self.values["control.angle"]
        self.values["Locomotion.speed"] = 40.0 if rate < 1.2 else 140.0 if angle < 30 else 60.0


def percentile(sorted_values: list[float], q: float) -> float:
    return sorted_values[min(len(sorted_values) - 1, int(q * len(sorted_values)))]


def adaptation_latency(n: int) -> None:
    try:
        lookup_engine("fuzzy")
        engine, rules, variables = "fuzzy", SPEED_RULES, VARIABLES
        label = "project fuzzy engine (acordcs.engines.fuzzy, mamdani)"
    except EngineNotAvailableError:
        register_engine("bench-crisp", MiniCrisp, syntax="crisp")
        engine, rules, variables = "bench-crisp", CRISP_RULES, {}
        label = "fallback crisp engine (no acordcs.engines.fuzzy)"
    with Container("bench", clock=VirtualClock()) as c:
        c.install_factory(ComponentFactory("Locomotion", Locomotion))
        c.create("Locomotion", "Locomotion")
        control = Control("control", attributes={"cycleRate": 1.0, "angle": 0.0})
        c.add_monitor(control)
        ps = PolicySet(
            "SpeedLimiting",
            {"speed": rules},
            engine=engine,
            adapts=["Locomotion"],
            fed_by=["control"],
            variables=variables,
        )
        c.add_policy_set(ps)
        inputs = [(0.2 + 2.6 * ((i * 7919) % 1000) / 1000, (i * 31) % 90) for i in range(n)]
        for rate, angle in inputs[:200]:  # warm-up (compiles the rule set)
            control.update(cycleRate=rate, angle=float(angle))
        samples = []
        changed = 0
        clock = time.perf_counter_ns
        for rate, angle in inputs:
            before = c.get_property("Locomotion", "speed")
            t0 = clock()
            control.update(cycleRate=rate, angle=float(angle))
            t1 = clock()
            samples.append((t1 - t0) / 1000)
            changed += c.get_property("Locomotion", "speed") != before
        samples.sort()
        assert c.faults.counts["total"] == 0, list(c.faults.recent)
        # The engine's own share: the four calls alone.
        eng = ps.engine
        t0 = clock()
        for rate, angle in inputs:
            eng.set("cycleRate", rate)
            eng.set("angle", float(angle))
            eng.fire("speed")
            eng.get("Locomotion.speed")
        engine_us = (clock() - t0) / 1000 / len(inputs)
    print(f"1. adaptation latency in-process ({label}), {n} monitor readings:")
    print(
        f"   reading -> policy fired -> speed written: p50 {percentile(samples, 0.5):.1f} us, "
        f"p99 {percentile(samples, 0.99):.1f} us (target p50 <= 50 us); {changed} changed the speed"
    )
    print(f"   the engine alone (set, set, fire, get): {engine_us:.1f} us per reading, mean")


class Echo(CtxComponent):
    ports = (sync_port("api"),)

    def echo(self, x: Any) -> Any:
        return x

    def echo_after(self, us: float, x: Any) -> Any:
        """``x``, after ``us`` microseconds of this process's CPU (``--calibrate``)."""
        spin(us)
        return x


def spin(us: float) -> None:
    """Spend ``us`` microseconds of CPU (a busy loop: the cost of that much more code)."""
    end = time.perf_counter() + us / 1e6
    while time.perf_counter() < end:
        pass


def serve(port: int, cpu: int | None) -> None:
    """The server process: one container, plus its component object registered bare, and a second
    component of the same class registered bare (the A/A control); on ``cpu`` when given."""
    if cpu is not None:
        os.sched_setaffinity(0, {cpu})
    container = Container("server")
    container.install_factory(ComponentFactory("Echo", Pyro5.api.expose(Echo)))
    ref = container.create("Echo", "echo")
    server = ContainerServer(container, port=port)
    bare = server.daemon.register(ref.instance, "bare.echo")
    control = server.daemon.register(container.create("Echo", "echo2").instance, "control.echo")
    more = [server.daemon.register(container.create("Echo", f"echo{i}").instance, f"more{i}.echo") for i in (3, 4)]  # fmt: skip
    print("READY", server.uri, bare, control, *more, flush=True)
    sys.stdin.read()
    server.close()
    container.close()


ORDERS = list(itertools.permutations(("ours", "bare", "control")))
"""The order of a round's three calls, taken in turn: each kind is first, second and third
equally often, since a call's place in the round changes its time."""

SPIN_US = 15.0
CALIBRATION = list(
    itertools.permutations(("ours", "bare", "control", "server+spin", "caller+spin"))
)
"""``--calibrate``: two more bare calls, one spending :data:`SPIN_US` of CPU in the server before it
answers, one spending it in the caller before it calls: what that much more code on either side
costs in the ratio, against what ours costs (all 120 orders, taken in turn)."""

Calls = dict[str, Callable[[Any], Any]]


def timed(calls: Calls, orders: list[tuple[str, ...]], rounds: int) -> dict[str, list[float]]:
    """Each kind's call times in us (sorted), ``rounds`` rounds taking ``orders`` in turn; and
    the times by place in the round, under ``"<kind>@<place>"``."""
    payload = {"angle": 12.5, "speed": 80}
    times: dict[str, list[float]] = {}
    clock = time.perf_counter_ns
    for i in range(rounds):
        for place, kind in enumerate(orders[i % len(orders)]):
            call = calls[kind]
            t0 = clock()
            call(payload)
            took = (clock() - t0) / 1000
            times.setdefault(kind, []).append(took)
            times.setdefault(f"{kind}@{place}", []).append(took)
    for values in times.values():
        values.sort()
    return times


def ratios(times: dict[str, list[float]], kind: str, against: str) -> str:
    a, b = times[kind], times[against]
    return (
        f"p50 {percentile(a, 0.5):.1f} vs {percentile(b, 0.5):.1f} us: ratio "
        f"{percentile(a, 0.5) / percentile(b, 0.5):.3f}; p90 {percentile(a, 0.9):.1f} vs "
        f"{percentile(b, 0.9):.1f} us: ratio {percentile(a, 0.9) / percentile(b, 0.9):.3f}"
    )


def cores_apart(pin: bool) -> tuple[int, int] | None:
    """Two CPUs this process may use, for the caller and the server (None: not pinned). Two hosts
    never share a core; on one machine the scheduler moves the two processes' threads between
    cores differently from run to run, and that placement, not the code, made most of the spread
    of this ratio (1.07 to 1.60 unpinned, in one session)."""
    if not pin or not hasattr(os, "sched_getaffinity"):
        return None
    cpus = sorted(os.sched_getaffinity(0))
    return (cpus[0], cpus[1]) if len(cpus) >= 2 else None


def remote_ratio(n: int, rounds: int, fixed_order: bool, pin: bool, calibrate: bool) -> None:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    cpus = cores_apart(pin)
    before = os.sched_getaffinity(0) if cpus else None
    if cpus:
        os.sched_setaffinity(0, {cpus[0]})
    proc = subprocess.Popen(
        [sys.executable, __file__, "--serve", str(port)]
        + (["--serve-cpu", str(cpus[1])] if cpus else []),
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        ready, _, _ = select.select([proc.stdout], [], [], 30)
        line = proc.stdout.readline() if ready else ""
        if not line.startswith("READY"):
            raise SystemExit(f"server did not start: {line!r}")
        _, uri, bare_uri, control_uri, *more_uris = line.split()
        with Container("client", clock=VirtualClock()) as c:

            class Caller(CtxComponent):
                ports = (sync_port("out", role="required"),)

            c.install_factory(ComponentFactory("Caller", Caller))
            c.create("Caller", "caller")
            c.connect(
                "caller.out", RemotePort(uri, "echo", "api"), connector=RemoteConnector(timeout=5.0)
            )
            out = c.find("caller").instance.port("out")
            proxies = [bare_proxy(u) for u in (bare_uri, control_uri, *more_uris)]
            bare, control, in_server, in_caller = proxies
            calls: Calls = {
                "ours": lambda x: out.call("echo", x),
                "bare": bare.echo,
                "control": control.echo,
                "server+spin": lambda x: in_server.echo_after(SPIN_US, x),
                "caller+spin": lambda x: (spin(SPIN_US), in_caller.echo(x))[1],
            }
            timed(calls, CALIBRATION, 300)  # connect and warm up every one
            if calibrate:
                main = same = timed(calls, CALIBRATION, rounds * n)
                design = (
                    f"each round's order rotated through all 120 of ours, bare, control, and bare "
                    f"with {SPIN_US:g} us of CPU in the server or in the caller (--calibrate)"
                )
            elif fixed_order:
                # the first design (ours, then bare, in every round), and the same design with
                # the control in our place
                main = timed(calls, [("ours", "bare")], rounds * n)
                same = timed(calls, [("control", "bare")], rounds * n)
                design = "ours then bare in every round, then control then bare (--fixed-order)"
            else:
                main = same = timed(calls, ORDERS, rounds * n)
                design = "each round's order rotated through all six of ours, bare, control"
            for p in proxies:
                p._pyroRelease()
        where = f"caller on CPU {cpus[0]}, server on CPU {cpus[1]}" if cpus else "not pinned"
        print(
            f"2. remote call over loopback, 2 processes ({where}), serpent ({rounds * n} calls "
            f"each; {design}):"
        )
        print(f"   our connector against a bare Pyro5 proxy: {ratios(main, 'ours', 'bare')}")
        print("   (target <= 1.2 at p50 and p90, issue 33)")
        print(
            "   control, a second bare proxy to a second object of the same class, against the "
            f"first (1 but for this host's noise): {ratios(same, 'control', 'bare')}"
        )
        if calibrate:
            for kind in ("server+spin", "caller+spin"):
                print(
                    f"   calibration, {kind} ({SPIN_US:g} us of CPU): {ratios(main, kind, 'bare')}"
                )
        elif not fixed_order:
            places = "; ".join(
                f"{kind} "
                + "/".join(f"{percentile(main[f'{kind}@{i}'], 0.5):.0f}" for i in range(3))
                for kind in ("ours", "bare", "control")
            )
            print(f"   median by place in the round (first/second/third), us: {places}")
    finally:
        proc.stdin.close()
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        if before:
            os.sched_setaffinity(0, before)


def bare_proxy(uri: str) -> Pyro5.api.Proxy:
    """A bare Pyro5 proxy set as the connector sets its own: serpent, a timeout, no retries."""
    proxy = Pyro5.api.Proxy(uri)
    proxy._pyroSerializer = "serpent"
    proxy._pyroTimeout = 5.0
    proxy._pyroMaxRetries = 0
    return proxy


class Idle(Monitor):
    def acquire(self) -> dict[str, float]:
        return {"load": 0.0}


def virtual_speedup(simulated: float) -> None:
    clock = VirtualClock(seed=1)
    with Container("idle", clock=clock) as c:
        monitors = [Idle(f"m{i}", frequency=10.0, attributes={"load": 0.0}) for i in range(10)]
        for m in monitors:
            c.add_monitor(m)
        t0 = time.perf_counter()
        clock.run_for(simulated)
        wall = time.perf_counter() - t0
        ticks = sum(m.ticks for m in monitors)
    print(
        f"3. virtual time, idle container with 10 monitors at 10 Hz: {simulated:.0f} simulated s "
        f"({ticks} ticks) in {wall:.2f} wall s: speed-up {simulated / wall:,.0f}x"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer samples")
    parser.add_argument(
        "--fixed-order",
        action="store_true",
        help="part 2 as first designed: ours then bare in every round (then the control then bare)",
    )
    parser.add_argument(
        "--no-pin",
        action="store_true",
        help="part 2 without the caller and the server pinned to CPUs of their own",
    )
    parser.add_argument(
        "--calibrate",
        action="store_true",
        help=f"part 2 with two more calls: bare with {SPIN_US:g} us of CPU in the server or caller",
    )
    parser.add_argument("--serve", type=int, help=argparse.SUPPRESS)
    parser.add_argument("--serve-cpu", type=int, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.serve:
        serve(args.serve, args.serve_cpu)
        return
    started = time.perf_counter()
    print(f"acordcs runtime benchmarks, python {sys.version.split()[0]}, pid {os.getpid()}")
    adaptation_latency(2000 if args.quick else 20000)
    remote_ratio(
        500 if args.quick else 2000,
        3 if args.quick else 7,
        args.fixed_order,
        not args.no_pin,
        args.calibrate,
    )
    virtual_speedup(600.0 if args.quick else 3600.0)
    print(f"total {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
