"""Java components (standalone; prints figures, asserts nothing). Takes about half a minute.

1. A Python component calling an operation of a component through a synchronous port, in
   process: the mixed greenhouse's ``Sensor.AskVentPort -> Vent.calibrate(25.0)`` (which calls
   back ``Vent.ThermoPort -> Sensor.readTemperature``), with the vent hosted in Java (the
   sample's ``Vent.java``, through JPype) against the same vent in Python (the same code, the
   component tagged ``language=python``) through the same ports, alternated in batches; p50 and
   p90 of each call, and their ratio.
2. The JVM's start (``acordcs.runtime.jvm.machine.started_in``) and the whole container's
   assembly in a fresh interpreter, with its classes compiled already (the cache warm), against
   the same assembly without the Java component's container (``Shed``: no JPype loaded).

Usage: python benchmarks/bench_java.py [--quick]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from acordcs.cli import main as cli_main

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "samples" / "mixed" / "greenhouse.uml"


def build(out: Path) -> None:
    shutil.copytree(MODEL.parent / "app", out, dirs_exist_ok=True)
    if cli_main(["build", "-q", str(MODEL), "-o", str(out)]) != 0:
        raise SystemExit(f"the build of {MODEL} failed")


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(int(q * len(ordered)), len(ordered) - 1)]


def calls(out: Path, batches: int, per_batch: int) -> None:
    sys.path.insert(0, str(out))
    from mixedgreenhouse_app import registry
    from mixedgreenhouse_app.base.Vent import VentBase

    class PythonVent(VentBase):  # Vent.java's calibrate, in Python
        def calibrate(self, reference: float) -> float:
            if reference < 0 or reference > 50:
                raise ValueError(f"reference {reference} C is outside the sensor's range")
            return reference - float(self.port("ThermoPort").call("readTemperature"))

        def report(self) -> str:
            return ""

    app = registry.descriptor()
    as_python = dataclasses.replace(
        app,
        components=tuple(
            dataclasses.replace(c, language="python") if c.name == "Vent" else c
            for c in app.components
        ),
    )
    java = registry.assemble_application(only=["House"], remote={"Shed": "PYRO:x@127.0.0.1:9"})
    python = registry.assemble(
        as_python,
        factories={**registry.FACTORIES, "Vent": PythonVent},
        only=["House"],
        remote={"Shed": "PYRO:x@127.0.0.1:9"},
    )
    ports = {
        "java": java.container("House").find("Sensor").port("AskVentPort"),
        "python": python.container("House").find("Sensor").port("AskVentPort"),
    }
    times: dict[str, list[float]] = {"java": [], "python": []}
    for port in ports.values():  # warm-up
        for _ in range(2000):
            port.call("calibrate", 25.0)
    clock = time.perf_counter_ns
    for _ in range(batches):
        for which, port in ports.items():
            taken = times[which]
            for _ in range(per_batch):
                began = clock()
                port.call("calibrate", 25.0)
                taken.append((clock() - began) / 1000)
    java.close()
    python.close()
    p = {w: (statistics.median(t), percentile(t, 0.9)) for w, t in times.items()}
    n = batches * per_batch
    print(f"1. Sensor.AskVentPort -> Vent.calibrate(25.0) (and back through Vent.ThermoPort), in "
          f"process, {n} calls each, alternated in {batches} batches:")  # fmt: skip
    for which in ("java", "python"):
        print(f"   vent in {which:6}: p50 {p[which][0]:7.2f} us, p90 {p[which][1]:7.2f} us")
    print(f"   Java / Python: p50 {p['java'][0] / p['python'][0]:.2f}x "
          f"(+{p['java'][0] - p['python'][0]:.2f} us), p90 {p['java'][1] / p['python'][1]:.2f}x "
          f"(+{p['java'][1] - p['python'][1]:.2f} us)")  # fmt: skip


START = """
import sys, time
began = time.perf_counter()
from mixedgreenhouse_app.registry import assemble_application
app = assemble_application(only=[{which!r}], remote={{{other!r}: 'PYRO:x@127.0.0.1:9'}})
took = time.perf_counter() - began
from acordcs.runtime.jvm import machine
app.close()
print(took, machine.started_in if 'jpype' in sys.modules else 0.0)
"""


def starts(out: Path, runs: int) -> None:
    env = {**os.environ, "PYTHONPATH": str(out)}
    got: dict[str, list[tuple[float, float]]] = {"House": [], "Shed": []}
    for _ in range(runs):
        for which, other in (("House", "Shed"), ("Shed", "House")):
            code = START.format(which=which, other=other)
            done = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                                  text=True, check=True, timeout=120)  # fmt: skip
            took, jvm = map(float, done.stdout.split())
            got[which].append((took, jvm))
    house = statistics.median(t for t, _ in got["House"])
    shed = statistics.median(t for t, _ in got["Shed"])
    jvm = statistics.median(j for _, j in got["House"])
    print(f"2. container assembly in a fresh interpreter (imports included), median of {runs}:")
    print(f"   House (hosts the Java vent): {house * 1000:7.1f} ms, of which the JVM's start "
          f"{jvm * 1000:.1f} ms")  # fmt: skip
    print(f"   Shed (Python only, no JPype loaded): {shed * 1000:7.1f} ms")
    print(f"   the Java component adds {(house - shed) * 1000:.1f} ms to the start")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="fewer calls and starts")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="bench-java-") as tmp:
        out = Path(tmp)
        build(out)
        calls(out, 5 if args.quick else 20, 1000 if args.quick else 2500)
        print(f"   (load average {os.getloadavg()[0]:.1f})")
        starts(out, 3 if args.quick else 7)
        print(f"   (load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
