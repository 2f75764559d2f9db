"""``python -m weblab_experiment``: the WebLab experiment (what ``make demo`` runs after validating
and building the application): every condition on every network profile for every seed, on the
default path (``--paths`` adds the sharp, right-angle and gentle ones, or all), the fixed speeds
of a sweep in both families (every policy off; only SpeedLimiting off) besides the named
conditions, the paper's Table 1 beside ours, the claims checked, results.json, results.csv,
plots and report.html.

Exit 0 when every run finished and every claim holds (a claim made on some paths only is shown
on the others, "not claimed here", and does not count there), 1 when a claim does not hold or a run did
not finish (it failed, or hit the time cap: the report lists them), 2 for bad arguments or an
application that is not built (with the command that builds it).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from weblab_sim.experiment import FIXED_RANGE, TIME_CAP, UNLIMITED, fixed_speed

from weblab_experiment import printed
from weblab_experiment.grid import CONDITIONS, PATHS, PROFILES, SWEEP, fixed_name, run_all, tasks
from weblab_experiment.report import write_all
from weblab_experiment.summary import claims, summarise

SEEDS = 6
"""Seeds per cell by default: 288 runs on the default path, the time of the 300 that make demo ran
before the fixed speeds with the recovery kept were added (runs on a path vary by a second or
two from seed to seed, so the intervals stay narrow)."""


def _names(text: str, known: tuple[str, ...], what: str, fixed: bool = False) -> tuple[str, ...]:
    """Comma-separated names of ``known`` (or "all"), in the order given, each once; with
    ``fixed``, also ``fixed_<speed>``."""
    if text == "all":
        return known
    names = tuple(dict.fromkeys(n.strip() for n in text.split(",") if n.strip()))
    unknown = [n for n in names if n not in known and not (fixed and fixed_speed(n) is not None)]
    if unknown or not names:
        more = (
            f", fixed_<speed>, no_speed_policy_<speed> ({FIXED_RANGE[0]:g} to "
            f"{FIXED_RANGE[1]:g} mm/s)"
            if fixed
            else ""
        )
        raise argparse.ArgumentTypeError(
            f"unknown {what} {', '.join(unknown) or '(none given)'}; the {what}s are "
            f"{', '.join(known)}{more} (or all)"
        )
    return names


def _speeds(text: str) -> tuple[float, ...]:
    if text == "none":
        return ()
    try:
        speeds = tuple(dict.fromkeys(float(v) for v in text.split(",") if v.strip()))
    except ValueError:
        speeds = ()
    if not speeds or not all(FIXED_RANGE[0] <= v <= FIXED_RANGE[1] for v in speeds):
        raise argparse.ArgumentTypeError(
            f"fixed speeds must be comma-separated numbers from {FIXED_RANGE[0]:g} to "
            f"{FIXED_RANGE[1]:g} (mm/s), or none; not {text!r}"
        )
    return speeds


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m weblab_experiment", description=__doc__.split("\n\n")[0]
    )
    parser.add_argument(
        "--seeds", type=int, default=SEEDS, help=f"seeds per cell (default {SEEDS})"
    )
    parser.add_argument(
        "--first-seed", type=int, default=0, help="the first seed (default 0): seeds N, N+1, ..."
    )
    parser.add_argument(
        "--profiles",
        type=lambda t: _names(t, PROFILES, "profile"),
        default=PROFILES,
        help=f"comma-separated network profiles ({', '.join(PROFILES)}; default all)",
    )
    parser.add_argument(
        "--conditions",
        type=lambda t: _names(t, CONDITIONS, "condition", fixed=True),
        default=None,
        help=f"comma-separated conditions ({', '.join(CONDITIONS)}, fixed_<speed>, "
        "no_speed_policy_<speed>; default all of them and the sweep's fixed speeds in both "
        "families)",
    )
    parser.add_argument(
        "--fixed-speeds",
        type=_speeds,
        default=None,
        help="the sweep's fixed speeds, comma-separated mm/s, or none, each run as fixed_<speed> "
        "and no_speed_policy_<speed> (default "
        f"{','.join(f'{v:g}' for v in SWEEP)} when --conditions is not given, else none)",
    )
    parser.add_argument(
        "--paths",
        type=lambda t: _names(t, PATHS, "path"),
        default=("default",),
        help=f"comma-separated paths ({', '.join(PATHS)}, or all; default default)",
    )
    parser.add_argument(
        "--time-cap",
        type=float,
        default=TIME_CAP,
        help=f"simulated seconds after which a run has failed (default {TIME_CAP:g})",
    )
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="processes")
    parser.add_argument(
        "--out", type=Path, default=Path("build/weblab-demo"), help="where the report goes"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = _parser()
    args = parser.parse_args(argv)
    if args.seeds < 1 or args.jobs < 1 or args.first_seed < 0 or not args.time_cap > 0:
        parser.error(
            "--seeds and --jobs must be at least 1, --first-seed at least 0, --time-cap above 0"
        )
    # canonical order: the claims read residential -> campus -> LAN as rising network speed
    profiles = tuple(p for p in PROFILES if p in args.profiles)
    speeds = (
        args.fixed_speeds
        if args.fixed_speeds is not None
        else (SWEEP if args.conditions is None else ())
    )
    conditions = tuple(
        dict.fromkeys(
            [
                *(args.conditions or CONDITIONS),
                *(fixed_name(v) for v in speeds),
                *(fixed_name(v, UNLIMITED) for v in speeds),
            ]
        )
    )

    from weblab_sim.experiment import APP_DIR

    if not (APP_DIR / "weblab_app" / "registry.py").is_file():
        print(
            f"python -m weblab_experiment: the generated WebLab application is not in {APP_DIR}; "
            "build it first (make demo does): "
            "acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app",
            file=sys.stderr,
        )
        return 2
    todo = tasks(conditions, profiles, args.seeds, args.first_seed, args.paths, args.time_cap)
    last = args.first_seed + args.seeds - 1
    print(
        f"WebLab experiment: {len(todo)} runs ({len(conditions)} conditions x {len(profiles)} "
        f"profiles x {len(args.paths)} path{'s' if len(args.paths) != 1 else ''} x {args.seeds} "
        f"seeds, {args.first_seed} to {last}) on {args.jobs} processes",
        flush=True,
    )
    outcomes, wall = run_all(todo, jobs=args.jobs, progress=not args.no_progress)
    table = summarise(outcomes)
    found = claims(table, outcomes, profiles)
    simulated = sum(o.metrics.get("sim_s", 0.0) for o in outcomes if o.error is None)
    meta = {
        "runs": len(todo),
        "seeds": args.seeds,
        "first_seed": args.first_seed,
        "profiles": list(profiles),
        "conditions": list(conditions),
        "paths": list(args.paths),
        "time_cap_s": args.time_cap,
        "jobs": args.jobs,
        "wall_s": wall,
        "simulated_s": simulated,
        "sim_per_wall": simulated / wall if wall > 0 else 0.0,
    }
    files = write_all(args.out, outcomes, table, found, profiles, meta)
    unfinished = [o for o in outcomes if o.error is not None or not o.metrics["finished"]]

    print()
    print(printed.report(table, profiles, found))
    for o in unfinished:
        what = o.error.strip().splitlines()[-1] if o.error else f"hit the {o.task.time_cap:g} s cap"
        print(
            f"DID NOT FINISH: path {o.task.path}, {o.task.condition}, {o.task.profile}, "
            f"seed {o.task.seed}: {what}"
        )
    print()
    print(
        f"{simulated:.0f} simulated s in {wall:.1f} wall s on {args.jobs} processes = "
        f"{meta['sim_per_wall']:.0f} simulated s per wall s "
        f"(load average {os.getloadavg()[0]:.1f})"
    )
    print(f"report: {files['report']} (data: {files['json'].name}, {files['csv'].name}, plots)")
    return 0 if not unfinished and all(c.holds for c in found if c.claimed) else 1


if __name__ == "__main__":
    sys.exit(main())
