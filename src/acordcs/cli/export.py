"""``acordcs-gen export``: the model as an instance of the ACORD-CS metamodel, for EMF tools.

The instance names its metamodel in ``xsi:schemaLocation`` as ``acordcs.ecore``, a file written
beside it, so that an EMF tool (Eclipse's Sample Reflective Ecore Model Editor, a ResourceSet in
Java) loads it without anything registered. Each file is written whole or not at all: both go to
temporary files in their directory first, and replace the old ones only once both are written.
"""

from __future__ import annotations

import os
from pathlib import Path

import click

from acordcs.cli.inputs import read_one
from acordcs.cli.report import as_text
from acordcs.diagnostics import Severity, printable
from acordcs.errors import AcordError

METAMODEL_FILE = "acordcs.ecore"


class ExportError(AcordError):
    """An export that cannot write its files: nothing was written."""

    exit_code = 2


@click.command(short_help="Write the model as an instance of acordcs.ecore (for EMF tools).")
@click.argument("model", type=click.Path(dir_okay=True, allow_dash=True))
@click.option(
    "-o",
    "--output",
    required=True,
    type=click.Path(dir_okay=False),
    help="The instance file to write (its directory is created if missing); acordcs.ecore, "
    "the metamodel it names, is written beside it.",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["ecore"]),
    default="ecore",
    show_default=True,
    help="ecore: XMI 2.0 instance of the ACORD-CS metamodel, as EMF reads and writes it.",
)
def export(model: str, output: str, fmt: str) -> None:
    """Write MODEL (- reads standard input) as an instance of the ACORD-CS metamodel into
    --output, and the metamodel acordcs.ecore beside it: containers, components with their ports,
    connections, monitors, policy sets with their policies and rules, attributes with their
    linguistic variables, operations with their parameters, each with the UML element's id and
    line. A file whose bytes would not change is left as it is.

    The model is checked first, as validate checks it: an error stops the export, nothing written.

    Exit 0 when written (or up to date), 1 when the model has errors, 2 when MODEL cannot be read
    or the files cannot be written.

    \b
    Example:
      acordcs-gen export samples/weblab/weblab.xmi -o weblab.acordcs.xmi
    """
    reading = read_one(model, check=True)
    if reading.unreadable:
        click.echo(as_text([reading]), nl=False)
        raise click.exceptions.Exit(2)
    errors = [d for d in reading.diagnostics if d.severity >= Severity.ERROR]
    if reading.diagnostics:
        click.echo(as_text([reading]), nl=False)
    if errors:
        click.echo(
            f"acordcs-gen export: error: {printable(reading.file)} has {len(errors)} "
            f"error{'s' if len(errors) != 1 else ''}: nothing written (fix them first; "
            "acordcs-gen validate lists them with their fixes)",
            err=True,
        )
        raise click.exceptions.Exit(1)
    from acordcs import metamodel
    from acordcs.model.ecore_builder import to_ecore

    instance = Path(output)
    beside = instance.parent / METAMODEL_FILE
    try:
        _check_paths(instance, beside)
        root = to_ecore(reading.architecture)
        written = _write_changed(
            {
                instance: metamodel.instance_bytes(root, schema_location=METAMODEL_FILE),
                beside: Path(metamodel.ecore_path()).read_bytes(),
            }
        )
    except ExportError as err:
        click.echo(f"acordcs-gen export: {printable(str(err))}", err=True)
        raise click.exceptions.Exit(err.exit_code) from None
    shown = printable(click.format_filename(output))
    counts = ", ".join(
        f"{len(getattr(root, feature))} {what}"
        for feature, what in (
            ("containers", "containers"),
            ("components", "components"),
            ("connections", "connections"),
            ("monitors", "monitors"),
            ("policySets", "policy sets"),
        )
    )
    state = "wrote" if instance in written else "up to date:"
    click.echo(f"{state} {shown} (an instance of {METAMODEL_FILE}: {counts})")
    state = "wrote" if beside in written else "up to date:"
    click.echo(
        f"{state} {printable(str(beside))} (the metamodel {shown} names in xsi:schemaLocation: "
        "keep the two files together)"
    )


def _check_paths(instance: Path, beside: Path) -> None:
    """Refuse, before anything is written, what the export must not overwrite."""
    if instance.name == METAMODEL_FILE:
        raise ExportError(
            f"the instance file cannot be named {METAMODEL_FILE}: the metamodel goes there",
            file=str(instance),
            hint="name it after the model, e.g. weblab.acordcs.xmi",
        )
    if instance.is_dir():
        raise ExportError(
            "is a directory", file=str(instance), hint="give a file name, e.g. DIR/model.xmi"
        )
    _refuse_foreign_metamodel(beside)


def _write_changed(files: dict[Path, bytes]) -> set[Path]:
    """Write each file whose bytes differ, each whole or not at all; the paths written."""
    instance = next(iter(files))
    changed = {path: data for path, data in files.items() if _bytes_of(path) != data}
    try:
        instance.parent.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise _unwritable(instance.parent, err) from None
    staged: dict[Path, Path] = {}
    try:
        for path, data in changed.items():
            temporary = path.with_name(f".{path.name}.acordcs-tmp")
            try:
                temporary.unlink(
                    missing_ok=True
                )  # a leftover keeps its mode; a link is not followed
                # 0o666 less the umask, as open() applies it (mkstemp would make it private)
                descriptor = os.open(temporary, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
                staged[path] = temporary
                with open(descriptor, "wb") as handle:
                    handle.write(data)
            except OSError as err:
                raise _unwritable(path, err) from None
        for path, temporary in staged.items():
            try:
                os.replace(temporary, path)
            except OSError as err:
                raise _unwritable(path, err) from None
    finally:
        for temporary in staged.values():
            temporary.unlink(missing_ok=True)
    return set(changed)


def _bytes_of(path: Path) -> bytes | None:
    try:
        return path.read_bytes()
    except OSError:
        return None


def _refuse_foreign_metamodel(path: Path) -> None:
    """An ``acordcs.ecore`` beside the output that is not a version of ours is not replaced."""
    data = _bytes_of(path)
    if data is None:
        if path.exists() or path.is_symlink():
            raise ExportError(
                "exists and cannot be read",
                file=str(path),
                hint="move it away, or export into another directory",
            )
        return
    from acordcs import metamodel

    if f'nsURI="{metamodel.NS_URI}"'.encode() not in data[:4096]:
        raise ExportError(
            f"is not the ACORD-CS metamodel (no nsURI {metamodel.NS_URI}); not replaced, "
            "nothing written",
            file=str(path),
            hint="move it away, or export into another directory",
        )


def _unwritable(path: Path, err: OSError) -> ExportError:
    return ExportError(
        f"cannot be written: {err.strerror or err}; nothing written",
        file=str(path),
        hint="give a path in a directory you can write to",
    )
