"""``acordcs-gen convert``: a model from one form to another, the text notation
(``docs/notation.md``), the Eclipse UML2 file Papyrus opens, or the XMI 2.1 BOUML reads.

The output is written whole or not at all (a temporary file in its directory, then renamed); the
Papyrus form applies ``ACORDCS.profile.uml``, which is written beside it when it is not there.
"""

from __future__ import annotations

import os
from pathlib import Path

import click

from acordcs.cli.inputs import read_one
from acordcs.cli.report import as_text
from acordcs.diagnostics import Severity, printable
from acordcs.errors import AcordError


@click.command(short_help="Convert a model: text notation, Papyrus (.uml) or BOUML (.xmi).")
@click.argument("model", type=click.Path(dir_okay=True, allow_dash=True))
@click.option(
    "-o",
    "--output",
    type=click.Path(dir_okay=False),
    help="The file to write; without it the model goes to standard output. Its suffix chooses "
    "the form unless --to does: .acord text, .uml Papyrus, .xmi BOUML.",
)
@click.option(
    "--to",
    "form",
    type=click.Choice(["text", "papyrus", "bouml"]),
    help="The form to write: text (the notation), papyrus (Eclipse UML2, the ACORDCS profile "
    "applied) or bouml (XMI 2.1). Default: by the output's suffix, else text for an XMI model "
    "and papyrus for a text one.",
)
def convert(model: str, output: str | None, form: str | None) -> None:
    """Write MODEL (any model validate reads: XMI, Papyrus .uml or the text notation .acord;
    - reads standard input) in another form. What the profile says is converted (the elements
    with an ACORD-CS stereotype, their tags, attributes, operations, ports, relations, the
    packages they are in, comments and ids); other UML content is not.

    Converting to XMI and back gives the same text; XMI to text and back, the same application
    descriptor. An error in reading the model (a relation naming no element, an unknown
    stereotype, ...) stops it: nothing written.

    Exit 0 when written, 1 when the model has errors that would be lost, 2 when MODEL cannot be
    read or the output cannot be written.

    \b
    Examples:
      acordcs-gen convert samples/tutorial/greenhouse.uml -o greenhouse.acord
      acordcs-gen convert greenhouse.acord -o greenhouse.uml
      acordcs-gen convert greenhouse.acord --to bouml -o greenhouse.xmi
    """
    from acordcs.model.outline_builder import SUFFIXES, to_form
    from acordcs.notation.text_model import DIALECT

    reading = read_one(model, check=False)
    if form is None:
        by_suffix = SUFFIXES.get(Path(output).suffix.lower()) if output else None
        form = by_suffix or ("papyrus" if reading.uml.dialect == DIALECT else "text")
    if reading.unreadable or reading.architecture is None:
        click.echo(as_text([reading]), nl=False)
        raise click.exceptions.Exit(2)
    errors = [d for d in reading.diagnostics if d.severity >= Severity.ERROR]
    if reading.diagnostics:
        click.echo(as_text([reading]), nl=False, err=output is None)
    if errors:
        click.echo(
            f"acordcs-gen convert: error: {printable(reading.file)} has {len(errors)} "
            f"error{'s' if len(errors) != 1 else ''} in what it says: nothing written (a "
            "conversion would lose what they concern; acordcs-gen validate lists them)",
            err=True,
        )
        raise click.exceptions.Exit(1)
    try:
        data = to_form(reading.architecture, form)
    except AcordError as refused:
        click.echo(
            f"acordcs-gen convert: error: {printable(reading.file)}: {printable(refused.message)}"
            f" [{printable(refused.element or '')}]: nothing written",
            err=True,
        )
        raise click.exceptions.Exit(1) from None
    if output is None:
        click.echo(data.decode("utf-8"), nl=False)
        return
    target = Path(output)
    files = {target: data}
    if form == "papyrus":
        from acordcs.notation.xmi_forms import PROFILE_FILE
        from acordcs.profile.profile_files import eclipse_profile

        beside = target.parent / PROFILE_FILE
        if not beside.exists():
            files[beside] = eclipse_profile()
    for path, content in files.items():
        try:
            _write_whole(path, content)
        except OSError as err:
            click.echo(
                f"acordcs-gen convert: error: {printable(str(path))}: cannot be written: "
                f"{err.strerror or err}; give a path in a directory you can write to",
                err=True,
            )
            raise click.exceptions.Exit(2) from None
        what = "the ACORDCS profile it applies" if path != target else f"the {form} form"
        click.echo(f"wrote {printable(str(path))} ({what})")


def _write_whole(path: Path, data: bytes) -> None:
    """``data`` into ``path``, whole or not at all."""
    if path.is_dir():
        raise IsADirectoryError(21, "it is a directory")
    path.parent.mkdir(parents=True, exist_ok=True)
    temporary = path.with_name(f".{path.name}.acordcs-tmp")
    temporary.unlink(missing_ok=True)
    try:
        descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        with open(descriptor, "wb") as handle:
            handle.write(data)
        os.replace(temporary, path)
    finally:
        temporary.unlink(missing_ok=True)
