"""The experiment's files: results.json, results.csv, the plots (PNG, SVG, PDF) and report.html
(Jinja2, with autoescaping: run errors and names reach the page as text)."""

from __future__ import annotations

import csv
import json
from importlib import resources
from pathlib import Path
from typing import Any

from jinja2 import Environment, FileSystemLoader, StrictUndefined, select_autoescape
from weblab_sim import experiment

from weblab_experiment import display, tuning
from weblab_experiment.differences import THRESHOLD, gaps
from weblab_experiment.grid import Outcome
from weblab_experiment.plots import FORMATS, all_plots
from weblab_experiment.summary import (
    FAMILIES,
    METRICS,
    PAPER,
    Claim,
    Table,
    fixed_conditions,
    sweep_verdicts,
)


def unfinished(outcomes: list[Outcome]) -> list[dict[str, Any]]:
    """The runs that did not reach the finish line: those that failed (raised) and those that hit
    the time cap, each with what happened."""
    out = []
    for o in outcomes:
        if o.error is not None:
            what = "failed: " + o.error.strip().splitlines()[-1]
        elif not o.metrics["finished"]:
            m = o.metrics
            what = (
                f"hit the time cap at {m['time_s']:g} s, {m['progress_mm']:.0f} mm along the "
                f"stripe, after {m['recovery_actions']} recovery actions and "
                f"{m['user_requests']} user requests"
            )
        else:
            continue
        out.append(
            {
                "path": o.task.path,
                "condition": o.task.condition,
                "profile": o.task.profile,
                "seed": o.task.seed,
                "what": what,
            }
        )
    return out


def as_json(
    table: Table, outcomes: list[Outcome], found: list[Claim], meta: dict[str, Any]
) -> dict[str, Any]:
    """results.json: per path, condition and profile each metric's mean, sample SD and n; the
    claims; the runs that did not finish; how the experiment ran (``meta``)."""
    return {
        "meta": meta,
        "paper_table_1": PAPER,
        "results": {
            path: {
                c: {
                    p: {m: {"mean": s.mean, "sd": s.sd, "n": s.n} for m, s in cell.items()}
                    for p, cell in by_profile.items()
                }
                for c, by_profile in by_condition.items()
            }
            for path, by_condition in table.items()
        },
        "claims": [
            {
                "path": c.path,
                "claim": c.text,
                "claimed": c.claimed,
                "holds": c.holds,
                "verdict": c.verdict,
                "figures": c.detail,
            }
            for c in found
        ],
        "unfinished_runs": unfinished(outcomes),
    }


def csv_rows(table: Table) -> list[list[object]]:
    """results.csv: one row per (path, condition, profile, metric)."""
    rows: list[list[object]] = [["path", "condition", "profile", "metric", "mean", "sd", "n"]]
    for path, by_condition in table.items():
        for condition, by_profile in by_condition.items():
            for profile, cell in by_profile.items():
                for metric in METRICS:
                    s = cell[metric]
                    rows.append(
                        [path, condition, profile, metric, f"{s.mean:.6g}", f"{s.sd:.6g}", s.n]
                    )
    return rows


def write_all(
    out: Path,
    outcomes: list[Outcome],
    table: Table,
    found: list[Claim],
    profiles: tuple[str, ...],
    meta: dict[str, Any],
) -> dict[str, Path]:
    """Every file of the report in ``out``; their paths by kind."""
    out.mkdir(parents=True, exist_ok=True)
    data = as_json(table, outcomes, found, meta)
    results = out / "results.json"
    results.write_text(json.dumps(data, indent=2) + "\n", encoding="utf-8")
    table_csv = out / "results.csv"
    with table_csv.open("w", newline="", encoding="utf-8") as handle:
        csv.writer(handle).writerows(csv_rows(table))
    plots = all_plots(outcomes, table, profiles, out)
    env = Environment(
        loader=FileSystemLoader(str(resources.files("weblab_experiment") / "templates")),
        autoescape=select_autoescape(["html", "j2"]),
        undefined=StrictUndefined,  # a missing cell is an error here, not a blank in the page
    )
    paths = {
        path: {
            "adaptive": by_condition.get("adaptive", {}),
            "conditions": by_condition,
            "gaps": gaps(by_condition, path, profiles),
            "fixed": fixed_conditions(by_condition),
            "sweeps": {
                prefix: (what, sweep_verdicts(by_condition, profiles, prefix))
                for prefix, what in FAMILIES.items()
                if "adaptive" in by_condition and fixed_conditions(by_condition, prefix)
            },
            "claims": [c for c in found if c.path == path],
            "plots": [p for p in plots if p.stem.endswith(f"-{path}")],
        }
        for path, by_condition in table.items()
    }
    page = env.get_template("report.html.j2").render(
        meta=meta,
        profiles=profiles,
        paths=paths,
        paper_table=PAPER,
        unfinished=data["unfinished_runs"],
        tuning=tuning.rows(),
        threshold=THRESHOLD,
        formats=FORMATS,
        show=display,
        table_metrics=display.TABLE_METRICS,
        table_1=display.TABLE_1,
        headers=display.HEADERS,
        all_hold=all(c.holds for c in found if c.claimed),
        rules={
            "time_cap": meta.get("time_cap_s", experiment.TIME_CAP),
            "patience": experiment.PATIENCE,
            "repeats": experiment.REPEATS,
            "adaptive_speed": experiment.ADAPTIVE_SPEED,
            "backwards_mm": experiment.BACKWARDS_MM,
        },
    )
    report = out / "report.html"
    report.write_text(page, encoding="utf-8")
    return {"json": results, "csv": table_csv, "report": report, **{p.stem: p for p in plots}}
