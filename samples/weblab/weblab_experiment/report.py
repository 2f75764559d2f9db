"""The experiment's files: results.json, results.csv, the plots and report.html (Jinja2, with
autoescaping: run errors and names reach the page as text)."""

from __future__ import annotations

import csv
import json
from importlib import resources
from pathlib import Path
from typing import Any

from jinja2 import Environment, FileSystemLoader, select_autoescape

from weblab_experiment.grid import Outcome
from weblab_experiment.plots import all_plots
from weblab_experiment.summary import METRICS, PAPER, Claim, Stat, as_json, csv_rows

DIFFERENCES = (
    "the speeds are lower than the paper's because the model's speed rules (12 rules over the cycle "
    "rate and the trajectory angle) also slow the robot down on turns, and our path has five of "
    "them; recoveries are fewer because the simulated stripe detection loses the stripe less often "
    "than the real camera did; the link figures (round-trip time, bandwidth, grab and processing "
    "times) were tuned so that the cycle rates match Table 1's, while the path, the camera and the "
    "rules were fixed beforehand (samples/weblab/README.md)."
)


HEADERS = {
    "cycles_per_s": "cycles/s",
    "speed_mm_s": "speed mm/s",
    "time_s": "time s",
    "recoveries": "recov.",
    "stripe_losses": "losses",
    "user_requests": "user req.",
    "fps": "fps",
    "mm_per_cycle": "mm/cycle",
    "finished": "finished",
    "faults": "faults",
}
"""Column headers of the conditions table (results.json keeps the plain metric names)."""


def write_all(
    out: Path,
    outcomes: list[Outcome],
    table: dict[str, dict[str, dict[str, Stat]]],
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
    )
    page = env.get_template("report.html.j2").render(
        meta=meta,
        claims=found,
        profiles=profiles,
        table=table,
        paper_table=PAPER,
        metrics=METRICS,
        plots=plots,
        failed=data["failed_runs"],
        differences=DIFFERENCES,
        headers=HEADERS,
    )
    report = out / "report.html"
    report.write_text(page, encoding="utf-8")
    return {"json": results, "csv": table_csv, "report": report, **{p.stem: p for p in plots}}
