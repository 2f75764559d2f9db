"""Benchmark: ``acordcs-gen build --target all`` on the synthetic 2,000-class model, against lxml.

Prints, measured in one run on the same file, whole-process times (interpreter start included) as
multiples of B, the time lxml takes to parse and re-serialize the model file; the three are
alternated, 15 runs each, and their medians compared (the host's speed drifts between minutes,
as ``bench_validate.py`` explains):

- a cold build into an empty directory (target: at most 6 B): read, validate, describe, the
  ``config`` stylesheet through Saxon, 90 FCL and 10 CLIPS files, the manifest;
- a no-op rebuild of the same model into the built directory (target: at most 2 B, zero files
  written: the mtime_ns of every file is checked after each run);
- for comparison, ``acordcs-gen validate`` on the same model, and a forced rebuild (``--force``:
  the model read and every target run, nothing written since nothing changed).

Run: ``.venv/bin/python benchmarks/bench_build.py``
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from lxml import etree

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # tools/, tests/ of the repository
from tools.bouml_writer.synthetic import generate

PAIRS = int(os.environ.get("BENCH_PAIRS", "15"))
CLI = [str(Path(sys.executable).with_name("acordcs-gen"))]


def alternated(*fns, rounds: int = PAIRS) -> list[float]:
    """Medians of ``fns`` run one after the other ``rounds`` times."""
    times: list[list[float]] = [[] for _ in fns]
    for _ in range(rounds):
        for fn, runs in zip(fns, times, strict=True):
            start = time.perf_counter()
            fn()
            runs.append(time.perf_counter() - start)
    return [statistics.median(runs) for runs in times]


def run(*args: str) -> str:
    done = subprocess.run([*CLI, *args], capture_output=True, text=True)
    if done.returncode != 0:
        raise SystemExit(f"acordcs-gen {' '.join(args)} failed:\n{done.stdout}{done.stderr}")
    return done.stdout


def state(directory: Path) -> dict[str, int]:
    return {str(p): p.stat().st_mtime_ns for p in directory.rglob("*") if p.is_file()}


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        model = Path(tmp, "synthetic-2000.xmi")
        model.write_text(generate(classes=2000, seed=1), encoding="utf-8")
        built = Path(tmp, "built")
        run("build", str(model), "-o", str(built), "--target", "all")
        files = state(built)
        cold_dirs = iter(Path(tmp, f"cold{n}") for n in range(PAIRS + 1))

        def cold() -> None:  # a new directory each time, removed after the runs (not timed)
            run("build", str(model), "-o", str(next(cold_dirs)), "--target", "all")

        def noop() -> None:
            said = run("build", str(model), "-o", str(built), "--target", "all")
            assert "up to date" in said, said

        b, cold_s, noop_s, validate_s, forced_s = alternated(
            lambda: etree.tostring(etree.parse(str(model))),
            cold,
            noop,
            lambda: run("validate", str(model)),
            lambda: run("build", str(model), "-o", str(built), "--force"),
        )
        unchanged = state(built) == files
        size = model.stat().st_size / 1e6
        output = sum(Path(p).stat().st_size for p in files) / 1e6

    print(
        f"synthetic model: 2,000 classes, {size:.1f} MB; build output: {len(files)} files, "
        f"{output:.1f} MB; medians of {PAIRS} runs, alternated"
    )
    print(f"B  lxml parse + serialize                    {b * 1e3:7.1f} ms")
    print(
        f"   build --target all, cold (empty output)    {cold_s * 1e3:7.1f} ms = "
        f"{cold_s / b:4.2f} B (target <= 6 B)"
    )
    print(
        f"   build --target all, no-op rebuild          {noop_s * 1e3:7.1f} ms = "
        f"{noop_s / b:4.2f} B (target <= 2 B); files written: "
        f"{'0' if unchanged else 'SOME (mtimes changed)'}"
    )
    print(
        f"   validate (for comparison)                  {validate_s * 1e3:7.1f} ms = {validate_s / b:4.2f} B"
    )
    print(
        f"   build --force (model read, targets run,    {forced_s * 1e3:7.1f} ms = "
        f"{forced_s / b:4.2f} B\n      nothing written)"
    )
    return 0 if unchanged else 1


if __name__ == "__main__":
    sys.exit(main())
