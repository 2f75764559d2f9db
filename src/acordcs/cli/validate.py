"""``acordcs-gen validate``: check models and report every diagnostic."""

from __future__ import annotations

import click

from acordcs.cli.inputs import read_models
from acordcs.cli.report import render
from acordcs.diagnostics import Severity


@click.command(short_help="Check models against the ACORD-CS profile; report every finding.")
@click.argument("files", nargs=-1, required=True, type=click.Path(dir_okay=True, allow_dash=True))
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["text", "gcc", "json", "sarif"]),
    default="text",
    show_default=True,
    help="text for people and editors (file:line:col: severity: CODE message), gcc for editors' "
    "problem matchers (the same lines in gcc's words: error, warning, note; no summary), json for "
    "scripts, sarif for code-scanning dashboards.",
)
@click.option(
    "--fail-on",
    type=click.Choice(["error", "warning"]),
    default="error",
    show_default=True,
    help="Lowest severity that makes the exit code 1.",
)
@click.option(
    "-q",
    "--quiet",
    is_flag=True,
    help="Text format: print only the diagnostics that reach --fail-on, no summary lines.",
)
def validate(files: tuple[str, ...], fmt: str, fail_on: str, quiet: bool) -> int:
    """Check FILE... (BOUML XMI 2.x or 1.2, Eclipse UML2/Papyrus .uml; - reads standard input)
    against the ACORD-CS profile.

    Exit 0 when clean, 1 when a diagnostic reaches --fail-on, 2 when a file cannot be read or is
    not a model (a Papyrus .notation or .di file).

    \b
    Examples:
      acordcs-gen validate samples/weblab/weblab.xmi --format sarif > weblab.sarif
      acordcs-gen validate - < model.xmi
    """
    if files.count("-") > 1:
        raise click.UsageError("'-' (standard input) can be given once")
    readings = read_models(files)
    threshold = Severity.ERROR if fail_on == "error" else Severity.WARNING
    if any(r.unreadable for r in readings):
        code = 2
    else:
        failed = any(d.severity >= threshold for r in readings for d in r.diagnostics)
        code = 1 if failed else 0
    shown = threshold if quiet else None
    click.echo(render(readings, fmt, exit_code=code, at_least=shown), nl=False)
    raise click.exceptions.Exit(code)
