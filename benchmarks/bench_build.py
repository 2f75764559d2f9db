"""Benchmark: ``acordcs-gen build --target all`` on a synthetic 2,000-class model, against lxml.

The model: 2,000 classes, 500 of them components deployed on 20 containers, 100 monitors and 100
policy sets (``tools.bouml_writer.synthetic``); its build writes about 2,400 files (the script
prints how many). Times are whole processes (interpreter start included), printed in multiples
of B, the time lxml takes to parse and re-serialize the model file. Every figure is a median of
runs alternated with the others (the host's speed drifts between minutes, as
``bench_validate.py`` explains):

- a cold build into an empty directory (target: at most 15 B): read, validate, describe, every
  target, every file written once, the manifest;
- a no-op rebuild of the same model into a built directory (target: at most 2 B, zero files
  written: the mtime_ns of every file is checked after the runs);
- a forced rebuild (``--force``: the model read and every target run, nothing written since
  nothing changed), and ``--check`` (the same, comparing bytes with the files on disk);
- ``acordcs-gen validate`` of the model, for comparison (what every build does first).

"after" is the ``acordcs-gen`` beside this interpreter; "before", when ``BENCH_BEFORE`` names
another installation's ``acordcs-gen`` (an older checkout's ``.venv/bin/acordcs-gen``), is measured
in the same run, alternated with it.

Run: ``BENCH_BEFORE=../old/.venv/bin/acordcs-gen .venv/bin/python benchmarks/bench_build.py``
(``BENCH_PAIRS=15`` runs of each).
"""

from __future__ import annotations

import os
import re
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from lxml import etree

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/, tests/ of the repository
from tools.bouml_writer.synthetic import generate

PAIRS = int(os.environ.get("BENCH_PAIRS", "15"))
AFTER = str(Path(sys.executable).with_name("acordcs-gen"))
BEFORE = os.environ.get("BENCH_BEFORE", "")


def alternated(fns: dict[str, Callable[[], None]], rounds: int = PAIRS) -> dict[str, float]:
    """Median time of each of ``fns``, run one after the other ``rounds`` times."""
    times: dict[str, list[float]] = {name: [] for name in fns}
    for _ in range(rounds):
        for name, fn in fns.items():
            start = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - start)
    return {name: statistics.median(runs) for name, runs in times.items()}


# Both installations run with their bytecode compiled once, into a cache of this run: a source
# tree changed since its installation (with PYTHONDONTWRITEBYTECODE set, as here) would otherwise
# compile its changed modules in every process, and its figures would say so, not the build.
ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def run(cli: str, *args: str, expect: int = 0) -> str:
    done = subprocess.run([cli, *args], capture_output=True, text=True, env=ENV)
    if done.returncode != expect:
        raise SystemExit(
            f"{cli} {' '.join(args)} exited {done.returncode}:\n{done.stdout}{done.stderr}"
        )
    return done.stdout + done.stderr


def state(directory: Path) -> dict[str, int]:
    return {str(p): p.stat().st_mtime_ns for p in directory.rglob("*") if p.is_file()}


def main() -> int:
    tools = {"after": AFTER, **({"before": BEFORE} if BEFORE else {})}
    with tempfile.TemporaryDirectory() as tmp:
        ENV["PYTHONPYCACHEPREFIX"] = str(Path(tmp, "pycache"))  # compiled by the first builds
        model = Path(tmp, "synthetic-2000.xmi")
        model.write_text(generate(classes=2000, seed=1, components=500, containers=20), "utf-8")
        built: dict[str, Path] = {}
        written: dict[str, int] = {}
        for name, cli in tools.items():
            built[name] = Path(tmp, f"built-{name}")
            said = run(cli, "build", str(model), "-o", str(built[name]), "-q")
            found = re.search(r": (\d+) written", said)
            written[name] = int(found.group(1)) if found else -1
        for cli in tools.values():  # validate's modules compiled too
            run(cli, "validate", "-q", str(model))
        files = {name: state(directory) for name, directory in built.items()}
        counter = iter(range(10**6))

        def cold(cli: str) -> Callable[[], None]:  # a new directory each time (removed at the end)
            return lambda: run(cli, "build", str(model), "-o", f"{tmp}/cold{next(counter)}", "-q")

        def noop(cli: str, directory: Path) -> Callable[[], None]:
            def rebuild() -> None:
                said = run(cli, "build", str(model), "-o", str(directory))
                assert "up to date" in said, said

            return rebuild

        fns: dict[str, Callable[[], None]] = {"B": lambda: etree.tostring(etree.parse(str(model)))}
        for name, cli in tools.items():
            fns[f"cold {name}"] = cold(cli)
            fns[f"no-op {name}"] = noop(cli, built[name])
            fns[f"validate {name}"] = lambda cli=cli: run(cli, "validate", "-q", str(model))
        fns["force after"] = lambda: run(
            AFTER, "build", str(model), "-o", str(built["after"]), "--force"
        )
        fns["check after"] = lambda: run(
            AFTER, "build", str(model), "-o", str(built["after"]), "--check"
        )
        medians = alternated(fns)
        unchanged = {name: state(built[name]) == files[name] for name in tools}
        size = model.stat().st_size / 1e6
        output = sum(Path(p).stat().st_size for p in files["after"]) / 1e6

    b = medians["B"]
    print(
        f"synthetic model: 2,000 classes (500 components, 20 containers, 100 policy sets), "
        f"{size:.1f} MB; medians of {PAIRS} runs, alternated"
    )
    for name, cli in tools.items():
        print(f"{name:6s} {cli}: a cold build writes {written[name]} files")
    print(f"after: {len(files['after'])} files in the output, {output:.1f} MB")
    print(f"B  lxml parse + serialize                 {b * 1e3:7.1f} ms")
    for name in tools:
        print(
            f"   cold build, {name:6s} (target <= 15 B)     {medians[f'cold {name}'] * 1e3:7.1f} ms = "
            f"{medians[f'cold {name}'] / b:5.2f} B"
        )
    for name in tools:
        print(
            f"   no-op rebuild, {name:6s} (target <= 2 B)  {medians[f'no-op {name}'] * 1e3:7.1f} ms = "
            f"{medians[f'no-op {name}'] / b:5.2f} B; files written: "
            f"{'0' if unchanged[name] else 'SOME (mtimes changed)'}"
        )
    for name in tools:
        print(
            f"   validate, {name:6s} (for comparison)     {medians[f'validate {name}'] * 1e3:7.1f} ms = "
            f"{medians[f'validate {name}'] / b:5.2f} B"
        )
    for what in ("force", "check"):
        print(
            f"   build --{what}, after                    {medians[f'{what} after'] * 1e3:7.1f} ms = "
            f"{medians[f'{what} after'] / b:5.2f} B"
        )
    if "before" in tools:
        print(f"   cold build after / before: {medians['cold after'] / medians['cold before']:.2f}")
    return 0 if all(unchanged.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
