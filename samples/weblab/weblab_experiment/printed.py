"""What ``python -m weblab_experiment`` prints at the end, per path: Table 1 beside the adaptive
runs, where they differ by more than 20% and why, every condition, the fixed-speed sweep against
adaptation, and the claims. The report shows the same figures (and the SDs of every cell)."""

from __future__ import annotations

import textwrap

from weblab_experiment import display
from weblab_experiment.differences import THRESHOLD, gaps
from weblab_experiment.display import DIGITS, HEADERS, TABLE_1, TABLE_METRICS, number
from weblab_experiment.summary import (
    FAMILIES,
    PAPER,
    Claim,
    Table,
    fixed_conditions,
    sweep_verdicts,
)

WIDTH = 100


def report(table: Table, profiles: tuple[str, ...], found: list[Claim]) -> str:
    out: list[str] = []
    for path, by_condition in table.items():
        out += _table_1(by_condition, path, profiles)
        out += _conditions(by_condition, path, profiles)
        out += _sweep(by_condition, path, profiles)
    for claim in found:
        out.append(f"{claim.verdict}: {claim.path}: {claim.text} ({claim.detail})")
    return "\n".join(out)


def _table_1(by_condition, path: str, profiles: tuple[str, ...]) -> list[str]:
    adaptive = by_condition.get("adaptive", {})
    shown = [p for p in profiles if p in adaptive]
    if not shown:
        return []
    n = sorted({adaptive[p]["time_s"].n for p in shown})
    lines = [
        f"Table 1 (paper) beside the adaptive runs, path {path}: paper | mean ± sample SD over "
        f"{'/'.join(map(str, n))} runs (SD left out where it rounds to 0)",
        f"{'access':<12}" + "".join(f"{HEADERS[m]:>16}" for m in TABLE_1) + f"{'mm/cycle':>12}",
    ]
    for p in shown:
        cells = []
        for m in TABLE_1:
            paper = PAPER.get(p, {}).get(m)
            ours = display.mean_sd(adaptive[p][m], m)
            cells.append(f"{display.paper(paper, m)} | {ours}" if paper is not None else ours)
        per_cycle = (
            f"{PAPER[p]['speed_mm_s'] / PAPER[p]['cycles_per_s']:.0f} | " if p in PAPER else ""
        )
        per_cycle += display.mean(adaptive[p]["mm_per_cycle"], "mm_per_cycle")
        lines.append(f"{p:<12}" + "".join(f"{c:>16}" for c in cells) + f"{per_cycle:>12}")
    flagged = [g for g in gaps(by_condition, path, profiles) if g.flagged]
    if flagged:
        lines.append(f"Where they differ by more than {THRESHOLD:.0%}, and why:")
        for gap in flagged:
            text = f"{gap.header}: {gap.figures()}. {gap.why}"
            lines += textwrap.wrap(text, WIDTH, initial_indent="- ", subsequent_indent="  ")
    return [*lines, ""]


def _conditions(by_condition, path: str, profiles: tuple[str, ...]) -> list[str]:
    lines = [
        f"Every condition, path {path}: means (the report gives each cell's SD); finished: runs "
        "that reached the finish line",
        f"{'condition':<20} {'profile':<12}"
        + "".join(f"{HEADERS[m]:>11}" for m in TABLE_METRICS)
        + f"{'finished':>10}",
    ]
    for condition, by_profile in by_condition.items():
        for p in profiles:
            cell = by_profile.get(p)
            if cell is None:
                continue
            lines.append(
                f"{condition:<20} {p:<12}"
                + "".join(f"{number(cell[m].mean, DIGITS[m]):>11}" for m in TABLE_METRICS)
                + f"{display.finished(cell['finished']):>10}"
            )
    return [*lines, ""]


def _sweep(by_condition, path: str, profiles: tuple[str, ...]) -> list[str]:
    lines: list[str] = []
    for prefix, what in FAMILIES.items():
        if "adaptive" not in by_condition or not fixed_conditions(by_condition, prefix):
            continue
        verdicts = sweep_verdicts(by_condition, profiles, prefix)
        lines += [
            f"Fixed speeds ({what}) against adaptation, path {path}: adaptive minus fixed time "
            "to the finish, s, [95% Welch interval]; user requests per run of the fixed speed",
            f"{'condition':<20}" + "".join(f"{p:>30}" for p in profiles),
        ]
        for c, by_profile in verdicts.items():
            cells = []
            for p in profiles:
                if p not in by_profile:
                    cells.append("")
                    continue
                users = number(by_condition[c][p]["user_requests"].mean, 1)
                cells.append(f"{display.interval(by_profile[p])}, {users} req.")
            lines.append(f"{c:<20}" + "".join(f"{x:>30}" for x in cells))
        lines.append("")
    return lines
