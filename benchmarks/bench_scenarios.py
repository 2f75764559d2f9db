"""Benchmark: ``acordcs-gen test`` (docs/testing.md), against B.

Prints, measured in one run:
- 1,000 steps of the WebLab's SpeedLimiting set (12 rules, mamdani) in process, the model read
  and described once beforehand (not timed): the scenario's whole run (the application assembled
  on a virtual clock, 1,000 monitor updates each firing the set, one expectation judged per step)
  and the same with every firing's rule degrees computed (what coverage and a failure report ask
  for); medians of 7, wall clock and the thread's CPU time (target: under 50 ms beyond reading
  the model); beside them, the peer: the
  same application and the same 1,000 monitor updates, nothing recorded or judged (the runtime's
  own cost, which bench_runtime.py measures per firing);
- B: the time lxml takes to parse and re-serialise ``samples/weblab/weblab.xmi`` (as in
  docs/benchmarks.md), and the whole process of ``acordcs-gen test samples/weblab/weblab.xmi``
  (the WebLab's scenarios, interpreter start included) as a multiple of B, alternated with it,
  15 runs each, medians (target: 2 B plus 1 ms per 100 steps), and beside it the whole process of
  ``acordcs-gen validate`` on the same file, the command every CI run pays already.

Run: ``.venv/bin/python benchmarks/bench_scenarios.py``
"""

from __future__ import annotations

import statistics
import subprocess
import sys
import time
from pathlib import Path

from lxml import etree

ROOT = Path(__file__).resolve().parents[1]
WEBLAB = ROOT / "samples" / "weblab" / "weblab.xmi"
CLI = str(Path(sys.executable).with_name("acordcs-gen"))
STEPS = 1_000
ROUNDS = 7
PAIRS = 15


def speed_scenario(names):
    from acordcs.scenarios.scenario_file import Expectation, Scenario, Step
    from acordcs.scenarios.yaml_reading import Located

    at = Located(None, "bench", 1, 1)
    steps = [
        Step(
            float(i),
            (("Control.cycleRate", (i % 30) / 10.0), ("Control.angle", float((i * 7) % 90))),
            at,
        )
        for i in range(STEPS)
    ]
    expectations = [
        Expectation("value", float(i), float(i), "Locomotion.maxSpeed", 0.0, 1e9, 0.0, at)
        for i in range(STEPS)
    ]
    return Scenario("bench", "bench", ("SpeedLimiting",), steps, expectations)


def median_ms(fn, rounds: int = ROUNDS) -> tuple[float, float]:
    """Medians of the wall-clock and of the thread's CPU time (ms): on a host whose cores are
    shared, the CPU time leaves out the waits for a core (as bench_clips.py measures)."""
    wall, cpu = [], []
    for _ in range(rounds):
        start, start_cpu = time.perf_counter(), time.thread_time()
        fn()
        wall.append(time.perf_counter() - start)
        cpu.append(time.thread_time() - start_cpu)
    return 1000 * statistics.median(wall), 1000 * statistics.median(cpu)


def main() -> int:
    from acordcs.generator.describe import describe
    from acordcs.model.reading import read_model
    from acordcs.scenarios.model_names import ModelNames
    from acordcs.scenarios.scenario_run import run_scenario
    from acordcs.scenarios.virtual_run import VirtualApplication

    started = time.perf_counter()
    names = ModelNames.of(describe(read_model(str(WEBLAB)).architecture))
    read_ms = 1000 * (time.perf_counter() - started)
    scenario = speed_scenario(names)
    outcome = run_scenario(scenario, names)  # warm: imports, the engine's first compile
    assert outcome.passed and len(outcome.run.firings) == STEPS, outcome.failures[:1]

    def with_degrees() -> None:
        done = run_scenario(scenario, names)
        for _set, firing in done.run.firings:
            firing.rules  # noqa: B018 (computed when first asked)

    def runtime_alone() -> None:
        # The peer: the same application assembled, the same 1,000 updates of the Control
        # monitor firing the same set, nothing recorded or judged (the runtime's own cost).
        app = VirtualApplication(names.app, policy_sets=["SpeedLimiting"], results={}, watched=[])
        control = app.home["Control"].monitor("Control")
        for step in scenario.steps:
            control.update(**{n.split(".")[1]: v for n, v in step.values})
        app.close()

    (run_ms, run_cpu), (degrees_ms, degrees_cpu) = (
        median_ms(lambda: run_scenario(scenario, names)),
        median_ms(with_degrees),
    )
    alone_ms, alone_cpu = median_ms(runtime_alone)
    print(f"model read and described once (not timed below): {read_ms:.1f} ms")
    print(
        f"{STEPS:,} steps of SpeedLimiting in process: {run_ms:.1f} ms wall, {run_cpu:.1f} ms CPU "
        f"({1000 * run_cpu / STEPS:.1f} us CPU per step; target < 50 ms); with every firing's "
        f"rule degrees: {degrees_ms:.1f} ms wall, {degrees_cpu:.1f} ms CPU; the runtime alone (the "
        f"same application and updates, nothing recorded or judged): {alone_ms:.1f} ms wall, "
        f"{alone_cpu:.1f} ms CPU, so the scenario takes {run_cpu / alone_cpu:.2f}x the runtime's "
        "CPU time"
    )

    def b() -> None:
        etree.tostring(etree.parse(str(WEBLAB)))

    def command(*args: str) -> None:
        done = subprocess.run([CLI, *args], capture_output=True, check=False)
        assert done.returncode == 0, done.stdout + done.stderr

    scenarios_steps = sum(
        len(s.steps)
        for s in __import__(
            "acordcs.scenarios.scenario_file", fromlist=["read_scenarios"]
        ).read_scenarios(
            __import__(
                "acordcs.scenarios.yaml_reading", fromlist=["read_scenario_yaml"]
            ).read_scenario_yaml(str(WEBLAB.with_name("weblab.scenarios.yaml"))),
            names,
        )
    )
    times: dict[str, list[float]] = {"B": [], "test": [], "validate": []}
    runs = {
        "B": b,
        "test": lambda: command("test", str(WEBLAB)),
        "validate": lambda: command("validate", str(WEBLAB)),
    }
    for round_ in range(PAIRS):
        order = list(runs)[round_ % 3 :] + list(runs)[: round_ % 3]
        for name in order:
            start = time.perf_counter()
            runs[name]()
            times[name].append(time.perf_counter() - start)
    b_ms = 1000 * statistics.median(times["B"])
    test_ms = 1000 * statistics.median(times["test"])
    validate_ms = 1000 * statistics.median(times["validate"])
    target = 2 * b_ms + scenarios_steps / 100
    print(
        f"B (lxml parse + reserialise of weblab.xmi, {WEBLAB.stat().st_size:,} bytes): {b_ms:.2f} ms"
    )
    print(
        f"acordcs-gen test samples/weblab/weblab.xmi (7 scenarios, {scenarios_steps} steps), whole "
        f"process: {test_ms:.0f} ms = {test_ms / b_ms:.0f} B (target 2 B + 1 ms per 100 steps "
        f"= {target:.1f} ms); acordcs-gen validate of the same file: {validate_ms:.0f} ms = "
        f"{validate_ms / b_ms:.0f} B; test / validate: {test_ms / validate_ms:.2f}"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
