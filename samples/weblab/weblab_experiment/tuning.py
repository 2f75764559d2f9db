"""The tuning table: every parameter the experiment's figures rest on, its value, whether it was
tuned to Table 1, taken from the paper, fixed beforehand or set after the first results, and why.

One source, ``tuning.toml`` (in this package); two renderings: Markdown in
``samples/weblab/README.md`` (between :data:`BEGIN` and :data:`END`) and HTML in report.html.
``python -m weblab_experiment.tuning`` prints the Markdown; ``--write`` rewrites the README's
copy (exit 0), ``--check`` says whether it is current (exit 0) or not (exit 1).
"""

from __future__ import annotations

import argparse
import sys
import tomllib
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"
BEGIN = (
    "<!-- the tuning table: generated from weblab_experiment/tuning.toml by "
    "`python -m weblab_experiment.tuning --write`; do not edit it here -->"
)
END = "<!-- end of the tuning table -->"
BASES = ("tuned to Table 1", "from the paper", "fixed beforehand", "set after the first results")


@dataclass(frozen=True)
class Row:
    key: str
    parameter: str
    value: str
    basis: str
    why: str


def rows() -> list[Row]:
    """The table's rows, in file order; a row with an unknown basis or a missing field raises."""
    text = (resources.files("weblab_experiment") / "tuning.toml").read_text(encoding="utf-8")
    out = []
    for n, entry in enumerate(tomllib.loads(text)["row"], 1):
        row = Row(**{f: str(entry[f]) for f in Row.__dataclass_fields__})
        if row.basis not in BASES:
            raise ValueError(
                f"tuning.toml, row {n} ({row.key}): basis {row.basis!r} is not one of {BASES}"
            )
        out.append(row)
    return out


def markdown() -> str:
    """The table as Markdown, between the README's markers."""

    def cell(text: str) -> str:
        return text.replace("|", "\\|")

    lines = [BEGIN, "", "| parameter | value | basis | why |", "|---|---|---|---|"]
    lines += [
        f"| {cell(r.parameter)} | {cell(r.value)} | {cell(r.basis)} | {cell(r.why)} |"
        for r in rows()
    ]
    return "\n".join([*lines, "", END])


def readme_block(text: str) -> str | None:
    """The README's copy of the table, markers included; None when the markers are missing."""
    start, end = text.find(BEGIN), text.find(END)
    if start < 0 or end < start:
        return None
    return text[start : end + len(END)]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m weblab_experiment.tuning", description=__doc__.split("\n\n")[0]
    )
    what = parser.add_mutually_exclusive_group()
    what.add_argument("--write", action="store_true", help="rewrite the README's copy")
    what.add_argument("--check", action="store_true", help="exit 1 when the README's copy is stale")
    args = parser.parse_args(argv)
    table = markdown()
    if not (args.write or args.check):
        print(table)
        return 0
    text = README.read_text(encoding="utf-8")
    block = readme_block(text)
    if block is None:
        print(
            f"{README}: no tuning table between the markers {BEGIN!r} and {END!r}", file=sys.stderr
        )
        return 2
    if args.check:
        if block == table:
            return 0
        print(
            f"{README}: the tuning table is stale; run python -m weblab_experiment.tuning --write",
            file=sys.stderr,
        )
        return 1
    README.write_text(text.replace(block, table), encoding="utf-8")
    print(f"{README}: tuning table written ({len(rows())} rows)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
