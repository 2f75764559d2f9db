"""``acordcs-gen inspect``: what the reader understood of a model."""

from __future__ import annotations

import json

import click

from acordcs.generator.diagnostics import printable
from acordcs.generator.pipeline import read_model
from acordcs.generator.summary import summarize


@click.command()
@click.argument("file", type=click.Path(dir_okay=True))
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
def inspect(file: str, fmt: str) -> int:
    """Show what was read from FILE: UML element counts, stereotype applications, ACORD-CS roles.

    Exit 0 when the file was read, 2 when it could not be.

    \b
    Example:
      acordcs-gen inspect samples/weblab/weblab.xmi --format json
    """
    reading = read_model(file, check=False)
    if reading.unreadable:
        for d in reading.diagnostics:
            click.echo(d.format_text(), err=True)
        raise click.exceptions.Exit(2)
    data = summarize(reading)
    if fmt == "json":
        click.echo(json.dumps(data, indent=2))
    else:
        click.echo(_text(data))
    raise click.exceptions.Exit(0)


def _text(data: dict) -> str:
    lines = [
        f"{data['file']}: {data['dialect']} ({data['exporter'] or 'unknown exporter'}), model {data['model']!r}"
    ]
    kinds = ", ".join(f"{n} {k}" for k, n in data["classifiers"].items()) or "none"
    lines.append(f"  classifiers: {kinds}")
    for key in (
        "attributes",
        "operations",
        "associations",
        "generalizations",
        "dependencies",
        "packages",
    ):
        lines.append(f"  {key}: {data[key]}")
    apps = ", ".join(f"{k} x{n}" for k, n in data["stereotype_applications"].items()) or "none"
    lines.append(f"  stereotype applications: {apps}")
    acordcs = data["acordcs"]
    lines.append("  ACORD-CS:")
    for kind, names in acordcs["elements"].items():
        lines.append(f"    {kind} ({len(names)}): {', '.join(names)}")
    for container, hosted in acordcs["deployment"].items():
        lines.append(f"    container {container} hosts: {', '.join(hosted) or 'nothing'}")
    for ps, info in acordcs["policy_sets"].items():
        lines.append(
            f"    policy set {ps}: engine {info['engine']}, {info['rules']} rules, adapts "
            f"{', '.join(info['adapts']) or 'nothing'}, fed by {', '.join(info['fed_by']) or 'nothing'}"
        )
    if data["diagnostics"]:
        lines.append(f"  reader diagnostics: {data['diagnostics']}")
    return "\n".join(printable(line) for line in lines)
