"""Fuzzy firing and FCL reading with many overlapping terms (issue 22, item 4), before and after.

"Before" is the commit before this work (``BEFORE``, extracted with ``git archive`` into a temporary
directory), "after" the checkout this script is in; each measurement runs in its own Python
process (peak memory is that process's), both in this same run:

1. ``fire()`` of a rule set whose output has 250 terms that all overlap (triangles spanning most of
   the range, all 250 rules firing): milliseconds per firing, median over fresh inputs, for every
   exact combination (target < 10 ms); before: the mamdani centroid only (seconds per firing);
2. reading a 1 MB FCL file (two inputs of 250 terms, an output of 250 overlapping terms, rules up to
   1 MB): seconds and peak memory (target < 2 s and < 200 MB): the growth of the process's peak
   size during the read, and in a second run the peak of Python's own allocations (tracemalloc);
3. reading a 1 MB FCL file that is 26,000 terms of one output: refused at the first term past the
   limit; before, run with 1.5 GB of address space and 60 s at most (it would take 5 GB).

Run: .venv/bin/python benchmarks/bench_fuzzy_deep.py   (3 to 5 minutes on 2 cores, most of it the "before" runs)
"""

from __future__ import annotations

import json
import os
import random
import resource
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

BEFORE = "1bc763a"  # the last commit before the polyline path and the fast FCL reader
ROOT = Path(__file__).resolve().parent.parent
TERMS = 250
SIZE = 1_000_000


def overlapping_terms(prefix: str, rnd: random.Random) -> list[str]:
    out = []
    for k in range(TERMS):
        a, c = rnd.uniform(0, 100), rnd.uniform(150, 250)
        out.append(f"{prefix}{k} := trian {a:.3f} {rnd.uniform(a, c):.3f} {c:.3f}")
    return out


def rules_file(rnd: random.Random) -> str:
    def narrow(prefix: str) -> str:
        return "\n".join(
            f"  TERM {prefix}{k} := TRIAN {k} {k + 0.5} {k + 1};" for k in range(TERMS)
        )

    wide = "\n".join(f"  TERM {t};" for t in overlapping_terms("o", rnd)).replace(
        " := trian", " := TRIAN"
    )
    head = (
        "FUNCTION_BLOCK b\nVAR_INPUT x : REAL; z : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        f"FUZZIFY x\n{narrow('i')}\n  RANGE := (0 .. {TERMS});\nEND_FUZZIFY\n"
        f"FUZZIFY z\n{narrow('i')}\n  RANGE := (0 .. {TERMS});\nEND_FUZZIFY\n"
        f"DEFUZZIFY y\n{wide}\n  RANGE := (0 .. 250);\n  METHOD : COG;\nEND_DEFUZZIFY\n"
        "RULEBLOCK r\n  AND : MIN;\n  ACT : MIN;\n  ACCU : MAX;\n"
    )
    parts, total, n = [head], len(head), 0
    tail = "END_RULEBLOCK\nEND_FUNCTION_BLOCK\n"
    while total < SIZE - len(tail) - 80:
        n += 1
        i, j, o = rnd.randrange(TERMS), rnd.randrange(TERMS), rnd.randrange(TERMS)
        line = f"  RULE {n} : IF x IS i{i} AND z IS i{j} THEN y IS o{o};\n"
        parts.append(line)
        total += len(line)
    return "".join(parts) + tail


def terms_file() -> str:
    head = "FUNCTION_BLOCK b\nVAR_INPUT x : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
    head += (
        "FUZZIFY x\n  TERM a := TRIAN 0 1 2;\nEND_FUZZIFY\nDEFUZZIFY y\n  RANGE := (0 .. 300);\n"
    )
    parts, total, k = [head], len(head), 0
    rnd = random.Random(3)
    while total < SIZE - 120:
        a = rnd.uniform(0, 100)
        line = f"  TERM o{k} := TRIAN {a:.2f} {a + 50:.2f} {a + 150:.2f};\n"
        parts.append(line)
        total += len(line)
        k += 1
    rules = "RULEBLOCK r\n  RULE 1 : IF x IS a THEN y IS o0;\nEND_RULEBLOCK\n"
    return "".join(parts) + "END_DEFUZZIFY\n" + rules + "END_FUNCTION_BLOCK\n"


# ---------------------------------------------------------------------------------- children
def child_fire(combination: str, fires: int) -> dict:
    from acordcs.engines.fuzzy import FuzzyEngine, Semantics

    act, accu, method = combination.split("/")
    rnd = random.Random(11)
    engine = FuzzyEngine(Semantics(act=act, accu=accu, method=method))
    # every input term covers the whole input range: all 250 rules fire, at different degrees
    engine.define_variable(
        "x", 0, TERMS, "; ".join(f"i{k} := trian -300 {k} 550" for k in range(TERMS))
    )
    engine.define_variable("y", 0, 250, "; ".join(overlapping_terms("o", rnd)))
    for k in range(TERMS):
        engine.defrule(f"if x is i{k} then y is o{k}", "s")
    engine.set("x", 125.0)
    engine.fire("s")  # compiles the rule set
    times, cpu = [], []
    for _ in range(fires):
        engine.set("x", rnd.uniform(0, TERMS))
        t0, c0 = time.perf_counter(), time.process_time()
        engine.fire("s")
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    return {"ms": statistics.median(times) * 1e3, "cpu_ms": statistics.median(cpu) * 1e3}


def child_read(path: str, traced: bool, without: str = "") -> dict:
    """Seconds and the growth of the process's peak size; or (``traced``, a separate run because
    tracing slows every allocation) the peak of Python's allocations during the read. ``without``
    a speed device of the reader, to judge it: "fast" (lark reads every file), "gc-pause"."""
    import gc
    import tracemalloc

    if without == "fast":
        from acordcs.engines.fuzzy import fcl_fast

        def decline(text: str) -> None:
            raise fcl_fast.Decline

        fcl_fast.parse = decline
    elif without == "gc-pause":
        gc.disable = lambda: None

    from acordcs.engines.fuzzy import read_fcl
    from acordcs.engines.rule_engine import RuleError

    text = Path(path).read_text(encoding="utf-8")
    base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    if traced:
        tracemalloc.start()
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        read_fcl(text, filename=Path(path).name)
        outcome = "read"
    except RuleError as err:
        outcome = f"refused: {str(err)[:70]}..."
    except MemoryError:
        outcome = "MemoryError"
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    if traced:
        return {"traced_mb": tracemalloc.get_traced_memory()[1] / 1e6}
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    return {"s": seconds, "cpu": cpu, "rss_mb": (rss - base) / 1024, "outcome": outcome}


# ---------------------------------------------------------------------------------- the run
def run(src: Path, args: list[str], limit_gb: float | None = None, timeout: float = 300) -> dict:
    env = dict(os.environ, PYTHONPATH=str(src))

    def cap() -> None:
        if limit_gb:
            size = int(limit_gb * 2**30)
            resource.setrlimit(resource.RLIMIT_AS, (size, size))

    try:
        done = subprocess.run(
            [sys.executable, __file__, "--child", *args],
            env=env,
            capture_output=True,
            text=True,
            timeout=timeout,
            preexec_fn=cap,
        )
    except subprocess.TimeoutExpired:
        return {"outcome": f"still running after {timeout:.0f} s (stopped)"}
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["?"])[-1]
        return {"outcome": f"failed: {last[:80]}"}
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> int:
    with tempfile.TemporaryDirectory() as tmp:
        before = Path(tmp) / "before"
        archive = subprocess.run(
            ["git", "-C", str(ROOT), "archive", BEFORE, "src"], capture_output=True, check=True
        )
        (Path(tmp) / "before.tar").write_bytes(archive.stdout)
        with tarfile.open(Path(tmp) / "before.tar") as tar:
            tar.extractall(before, filter="data")
        after = ROOT / "src"
        rules_path, terms_path = Path(tmp) / "rules-1mb.fcl", Path(tmp) / "terms-1mb.fcl"
        rules_path.write_text(rules_file(random.Random(7)), encoding="utf-8")
        terms_path.write_text(terms_file(), encoding="utf-8")

        print(f"fire() with {TERMS} overlapping output terms, all firing (ms per firing, median;")
        print("cpu: the process's CPU time, which other work on the machine does not inflate)\n")
        head = f"| {'act / accu / method':<22} | {'after':>8} | {'after cpu':>9} | {'before':>10} |"
        print(head + f" {'ratio':>7} |")
        print(f"|{'-' * 24}|{'-' * 10}|{'-' * 11}|{'-' * 12}|{'-' * 9}|")
        for combo in ("MIN/MAX/COG", "MIN/MAX/COA", "MIN/MAX/LM", "MIN/MAX/RM", "MIN/MAX/MM",
                      "MIN/SUM/COG", "PROD/BSUM/COA"):  # fmt: skip
            now = run(after, ["fire", combo, "200"])
            then = None
            if combo == "MIN/MAX/COG":  # seconds per firing before: two firings
                then = run(before / "src", ["fire", combo, "2"], timeout=120)
            shown = f"{then['ms']:>10,.0f}" if then and "ms" in then else f"{'':>10}"
            ratio = f"{then['ms'] / now['ms']:>6,.0f}x" if then and "ms" in then else f"{'':>7}"
            wall, cpu = now.get("ms", float("nan")), now.get("cpu_ms", float("nan"))
            print(f"| {combo:<22} | {wall:>8.2f} | {cpu:>9.2f} | {shown} | {ratio} |")

        for label, path, cap in (("rules", rules_path, None), ("terms", terms_path, 1.5)):
            size = path.stat().st_size / 1e6
            print(
                f"\nread_fcl of a {size:.2f} MB file of {label} (seconds, peak memory of the read)"
            )
            for name, src, limit, timeout in (
                ("after", after, None, 300),
                ("before", before / "src", cap, 60 if cap else 300),
            ):
                m = run(src, ["read", str(path)], limit_gb=limit, timeout=timeout)
                if "s" in m:
                    t = run(src, ["readmem", str(path)], limit_gb=limit, timeout=timeout)
                    traced = f"{t['traced_mb']:6.0f} MB" if "traced_mb" in t else t["outcome"]
                    print(
                        f"  {name:<6} {m['s']:7.2f} s (cpu {m['cpu']:5.2f} s)  peak size "
                        f"+{m['rss_mb']:5.0f} MB  Python's allocations {traced}  {m['outcome']}"
                    )
                else:
                    print(f"  {name:<6} {m['outcome']}")
        print(
            "\nthe reader's speed devices, judged on the rules file (cpu seconds; alternated, 3 runs)"
        )
        runs: dict[str, list[float]] = {"all": [], "fast": [], "gc-pause": []}
        for _ in range(3):
            for without in runs:
                m = run(after, ["read", str(rules_path), without if without != "all" else ""])
                runs[without].append(m.get("cpu", float("nan")))
        best = {k: min(v) for k, v in runs.items()}
        for without, label in (
            ("fast", "the fast path (lark reads)"),
            ("gc-pause", "the gc pause"),
        ):
            saved = 1.0 - best["all"] / best[without]
            print(
                f"  without {label:<26} {best[without]:5.2f} s vs {best['all']:5.2f} s: saves {saved:.0%}"
            )
    return 0


if __name__ == "__main__":
    if len(sys.argv) > 1 and sys.argv[1] == "--child":
        kind = sys.argv[2]
        if kind == "fire":
            result = child_fire(sys.argv[3], int(sys.argv[4]))
        else:
            without = sys.argv[4] if len(sys.argv) > 4 else ""
            result = child_read(sys.argv[3], traced=kind == "readmem", without=without)
        print(json.dumps(result))
        sys.exit(0)
    sys.exit(main())
