"""``acordcs-gen validate``: check models and report every diagnostic."""

from __future__ import annotations

import click

from acordcs.cli.report import render
from acordcs.diagnostics import Severity
from acordcs.model.reading import read_model


@click.command()
@click.argument("files", nargs=-1, required=True, type=click.Path(dir_okay=True))
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "json", "sarif"]),
    default="text",
    show_default=True,
    help="text for people, json for scripts, sarif for code-scanning dashboards.",
)
@click.option(
    "--fail-on",
    type=click.Choice(["error", "warning"]),
    default="error",
    show_default=True,
    help="Lowest severity that makes the exit code 1.",
)
def validate(files: tuple[str, ...], fmt: str, fail_on: str) -> int:
    """Check FILE... (BOUML XMI 2.x or 1.2, Eclipse UML2 .uml) against the ACORD-CS profile.

    Exit 0 when clean, 1 when a diagnostic reaches --fail-on, 2 when a file cannot be read.

    \b
    Example:
      acordcs-gen validate samples/weblab/weblab.xmi --format sarif > weblab.sarif
    """
    readings = [read_model(f) for f in files]
    click.echo(render(readings, fmt), nl=False)
    threshold = Severity.ERROR if fail_on == "error" else Severity.WARNING
    if any(r.unreadable for r in readings):
        raise click.exceptions.Exit(2)
    failed = any(d.severity >= threshold for r in readings for d in r.diagnostics)
    raise click.exceptions.Exit(1 if failed else 0)
