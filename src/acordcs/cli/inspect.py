"""``acordcs-gen inspect``: what the reader understood of a model."""

from __future__ import annotations

import json

import click

from acordcs.cli.inputs import read_one
from acordcs.cli.summary import summarize, summary_text


@click.command()
@click.argument("file", type=click.Path(dir_okay=True, allow_dash=True))
@click.option(
    "--format", "fmt", type=click.Choice(["text", "json"]), default="text", show_default=True
)
def inspect(file: str, fmt: str) -> int:
    """Show what was read from FILE (- reads standard input): UML element counts, stereotype
    applications, ACORD-CS roles.

    Exit 0 when the file was read; 1 when it is UML but none of its classes could be read
    (error R208, as validate reports it); 2 when it could not be read or is not a model.

    \b
    Example:
      acordcs-gen inspect samples/weblab/weblab.xmi --format json
    """
    reading = read_one(file, check=False)
    if reading.unreadable:
        for d in reading.diagnostics:
            click.echo(d.format_text(), err=True)
        raise click.exceptions.Exit(2)
    # A file whose classes the reader could not read is refused as validate refuses it, not shown
    # as an empty model.
    refused = [d for d in reading.diagnostics if d.code == "R208"]
    if refused:
        for d in refused:
            click.echo(d.format_text(), err=True)
        raise click.exceptions.Exit(1)
    data = summarize(reading)
    if fmt == "json":
        click.echo(json.dumps(data, indent=2))
    else:
        click.echo(summary_text(data))
    raise click.exceptions.Exit(0)
