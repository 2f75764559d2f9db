"""``python -m weblab_experiment``: the WebLab experiment (what ``make demo`` runs after validating
and building the application): every condition on every network profile for every seed, the
paper's Table 1 beside ours, the claims checked, results.json, results.csv, plots and report.html.

Exit 0 when every run finished and every claim holds, 1 when a claim does not hold or a run failed
(the report says which), 2 for bad arguments or an application that is not built (with the
command that builds it).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from weblab_experiment.grid import CONDITIONS, PROFILES, run_all, tasks
from weblab_experiment.report import write_all
from weblab_experiment.summary import claims, summarise, text_table


def _names(text: str, known: tuple[str, ...], what: str) -> tuple[str, ...]:
    if text == "all":
        return known
    names = tuple(n.strip() for n in text.split(",") if n.strip())
    unknown = [n for n in names if n not in known]
    if unknown or not names:
        raise argparse.ArgumentTypeError(
            f"unknown {what} {', '.join(unknown) or '(none given)'}; the {what}s are "
            f"{', '.join(known)} (or all)"
        )
    return names


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m weblab_experiment", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument("--seeds", type=int, default=10, help="seeds per cell (default 10)")
    parser.add_argument(
        "--profiles",
        type=lambda t: _names(t, PROFILES, "profile"),
        default=PROFILES,
        help="comma-separated network profiles (default all)",
    )
    parser.add_argument(
        "--conditions",
        type=lambda t: _names(t, CONDITIONS, "condition"),
        default=CONDITIONS,
        help="comma-separated conditions (default all)",
    )
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="processes")
    parser.add_argument(
        "--out", type=Path, default=Path("build/weblab-demo"), help="where the report goes"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    args = parser.parse_args(argv)
    if args.seeds < 1 or args.jobs < 1:
        parser.error("--seeds and --jobs must be at least 1")

    from weblab_sim.experiment import APP_DIR

    if not (APP_DIR / "weblab_app" / "registry.py").is_file():
        print(
            f"python -m weblab_experiment: the generated WebLab application is not in {APP_DIR}; "
            "build it first (make demo does): "
            "acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app",
            file=sys.stderr,
        )
        return 2
    todo = tasks(args.conditions, args.profiles, args.seeds)
    print(
        f"WebLab experiment: {len(todo)} runs ({len(args.conditions)} conditions x "
        f"{len(args.profiles)} profiles x {args.seeds} seeds) on {args.jobs} processes",
        flush=True,
    )
    outcomes, wall = run_all(todo, jobs=args.jobs, progress=not args.no_progress)
    table = summarise(outcomes)
    found = claims(table, args.profiles)
    simulated = sum(o.metrics.get("sim_s", 0.0) for o in outcomes if o.error is None)
    meta = {
        "runs": len(todo),
        "seeds": args.seeds,
        "profiles": list(args.profiles),
        "conditions": list(args.conditions),
        "jobs": args.jobs,
        "wall_s": wall,
        "simulated_s": simulated,
        "sim_per_wall": simulated / wall if wall > 0 else 0.0,
    }
    files = write_all(args.out, outcomes, table, found, args.profiles, meta)
    failed = [o for o in outcomes if o.error is not None]

    print()
    print(text_table(table, args.profiles))
    print()
    for claim in found:
        print(f"{'holds' if claim.holds else 'DOES NOT HOLD'}: {claim.text} ({claim.detail})")
    for o in failed:
        last = o.error.strip().splitlines()[-1] if o.error else ""
        print(f"FAILED RUN: {o.task.condition} {o.task.profile} seed {o.task.seed}: {last}")
    print()
    print(
        f"{simulated:.0f} simulated s in {wall:.1f} wall s on {args.jobs} processes = "
        f"{meta['sim_per_wall']:.0f} simulated s per wall s"
    )
    print(f"report: {files['report']} (data: {files['json'].name}, {files['csv'].name}, plots)")
    return 0 if not failed and all(c.holds for c in found) else 1


if __name__ == "__main__":
    sys.exit(main())
