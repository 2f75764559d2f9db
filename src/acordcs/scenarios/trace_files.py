"""``acordcs-gen test --trace DIR``: per scenario, a CSV of every input, output and rule degree at
each sample (after each step and each firing), and a plot of them on a shared time axis (SVG and
PNG: inputs, outputs, the degrees of the rules that fired), so that a modeller sees why a policy
did what it did. The plot needs matplotlib (the extra ``plots``)."""

from __future__ import annotations

import csv
import re
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from acordcs.scenarios.model_names import ModelNames
    from acordcs.scenarios.scenario_run import Outcome

MISSING_PLOTS = (
    "--trace draws its plots with matplotlib, which is not installed: "
    "pip install 'acordcs[plots]' (or leave out --trace)"
)


def plots_available() -> bool:
    import importlib.util

    return importlib.util.find_spec("matplotlib") is not None


def _stem(index: int, outcome: Outcome) -> str:
    file = Path(outcome.scenario.file).name.removesuffix(".yaml").removesuffix(".scenarios")
    slug = re.sub(r"[^A-Za-z0-9]+", "-", outcome.scenario.name).strip("-")[:60] or "scenario"
    return f"{re.sub(r'[^A-Za-z0-9.]+', '-', file)}-{index:02d}-{slug}"


def columns(outcome: Outcome, names: ModelNames) -> tuple[list[str], list[str], list[str]]:
    """The scenario's inputs, outputs (Element.attribute) and rules (PolicySet.Policy.label)."""
    inputs: dict[str, None] = {}
    outputs: dict[str, None] = {}
    for s in outcome.scenario.policy_sets:
        plan = names.plans[s]
        outputs.update(dict.fromkeys(plan.outputs))
    for s in outcome.scenario.policy_sets:
        inputs.update({v: None for v in names.plans[s].inputs if v not in outputs})
    rules = [f"{s}.{p}.{label}" for s, p, label in names.rules(outcome.scenario.policy_sets)]
    return list(inputs), list(outputs), rules


def rows(outcome: Outcome, names: ModelNames) -> tuple[list[str], list[list[object]]]:
    """The CSV's header and rows: time, what the row follows (a step, or a set's firing), each
    input and output, each rule's degree in its set's firing in effect then."""
    inputs, outputs, rules = columns(outcome, names)
    header = ["time_s", "after", *inputs, *outputs, *rules]
    firings = iter(outcome.run.firings)
    degrees: dict[str, float] = dict.fromkeys(rules, 0.0)
    out: list[list[object]] = []
    for sample in outcome.run.samples:
        if sample.fired is not None:
            policy_set, firing = next(firings)
            for (policy, label), degree in firing.rules.items():
                degrees[f"{policy_set}.{policy}.{label}"] = degree
        out.append(
            [
                sample.time,
                sample.fired or "step",
                *(sample.values.get(v) for v in (*inputs, *outputs)),
                *(degrees[r] for r in rules),
            ]
        )
    return header, out


def write_traces(directory: str, outcomes: list[Outcome], names: ModelNames) -> list[Path]:
    """Write each scenario's CSV, SVG and PNG into ``directory`` (created); the files written."""
    folder = Path(directory)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for index, outcome in enumerate(outcomes, 1):
        stem = folder / _stem(index, outcome)
        header, table = rows(outcome, names)
        with open(stem.with_suffix(".csv"), "w", newline="", encoding="utf-8") as handle:
            writer = csv.writer(handle)
            writer.writerow(header)
            writer.writerows(table)
        written.append(stem.with_suffix(".csv"))
        written += _plot(stem, outcome, names, header, table)
    return written


def _plot(
    stem: Path, outcome: Outcome, names: ModelNames, header: list[str], table: list[list[object]]
) -> list[Path]:
    import matplotlib

    matplotlib.use("Agg")  # files only, no display
    matplotlib.rcParams["svg.fonttype"] = (
        "none"  # the SVG's text stays text: searchable, selectable
    )
    import matplotlib.pyplot as plt

    inputs, outputs, rules = columns(outcome, names)
    times = [float(row[0]) for row in table]  # type: ignore[arg-type]
    fired = [r for r in rules if any(row[header.index(r)] for row in table)]
    variables = [("input", v) for v in inputs] + [("output", v) for v in outputs]
    heights = [1.0] * len(variables) + ([0.25 * len(fired) + 0.4] if fired else [])
    figure, axes = plt.subplots(
        len(heights),
        1,
        sharex=True,
        figsize=(10, 1.5 * sum(heights) + 1.2),
        squeeze=False,
        gridspec_kw={"height_ratios": heights},
        layout="constrained",
    )
    # the last state drawn for a while after the last sample: 5 % of the span, at least 1 s
    end = times[-1] + max(1.0, 0.05 * (times[-1] - times[0]))
    axes[0, 0].set_xlim(times[0], end)
    for axis, (role, name) in zip(axes[:, 0], variables, strict=False):
        column = header.index(name)
        values = [row[column] for row in table]
        numeric = [float(x) if isinstance(x, int | float) else float("nan") for x in values]
        axis.step(
            [*times, end],
            [*numeric, numeric[-1]],
            where="post",
            color="C0" if role == "input" else "C3",
        )
        kind = names.attributes.get(name, "")
        variable = names.variables.get(name)
        if variable is not None:
            axis.set_ylim(variable.lo, variable.hi)
            axis.set_yticks([variable.lo, (variable.lo + variable.hi) / 2, variable.hi])
        axis.set_ylabel(
            f"{name}\n{role}, {kind}", rotation=0, ha="right", va="center", fontsize="small"
        )
        axis.grid(True, alpha=0.3)
    if fired:
        axis = axes[-1, 0]
        matrix = [[float(row[header.index(r)]) for row in table] for r in fired]  # type: ignore[arg-type]
        edges = [*times, end]
        mesh = axis.pcolormesh(
            edges, range(len(fired) + 1), matrix, vmin=0, vmax=1, cmap="Greens", shading="flat"
        )
        axis.set_yticks([i + 0.5 for i in range(len(fired))])
        axis.set_yticklabels([r.split(".", 1)[1] for r in fired], fontsize="small")
        axis.invert_yaxis()
        axis.set_ylabel(
            "rules fired\n(degree)", rotation=0, ha="right", va="center", fontsize="small"
        )
        # one colour bar beside every panel, so that they keep one width and one time axis
        figure.colorbar(
            mesh, ax=axes[:, 0].tolist(), pad=0.01, fraction=0.03, label="degree (0..1)"
        )
    axes[-1, 0].set_xlabel("virtual time (s)")
    figure.suptitle(f"{outcome.scenario.name}: {'pass' if outcome.passed else 'FAIL'}")
    paths = [stem.with_suffix(".svg"), stem.with_suffix(".png")]
    for path in paths:
        figure.savefig(path, dpi=110)
    plt.close(figure)
    return paths
