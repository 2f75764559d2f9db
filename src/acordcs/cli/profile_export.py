"""``acordcs-gen profile export``: write the ACORDCS profile files a modeller imports."""

from __future__ import annotations

from pathlib import Path

import click

from acordcs.profile.profile_files import BOUML_FILE, ECLIPSE_FILE, write_profiles

_TOOLS = {"bouml": BOUML_FILE, "papyrus": ECLIPSE_FILE}
_NEXT_STEP = {
    BOUML_FILE: "BOUML: select the project, Tools > Import Xmi 2.1, pick this file",
    ECLIPSE_FILE: "Papyrus: copy it into the workspace project, then on the model's root "
    "Properties > Profile > Apply profile (from workspace); it is already defined",
}


@click.group()
def profile() -> None:
    """The ACORDCS UML profile."""


@profile.command()
@click.argument("directory", type=click.Path(file_okay=True, dir_okay=True))
@click.option(
    "--tool",
    type=click.Choice(sorted(_TOOLS)),
    help="Write only the file for this tool (default: both).",
)
def export(directory: str, tool: str | None) -> None:
    """Write the profile files into DIRECTORY (created if missing): ACORDCS.xmi for BOUML and
    ACORDCS.profile.uml (already defined) for Papyrus. A file already up to date is left as is.

    Exit 0 when written, 2 when DIRECTORY cannot be made or written.

    \b
    Example:
      acordcs-gen profile export profiles --tool papyrus
    """
    target = Path(directory)
    names = [_TOOLS[tool]] if tool else list(_TOOLS.values())
    try:
        if target.exists() and not target.is_dir():
            raise NotADirectoryError(f"{target} is a file")
        target.mkdir(parents=True, exist_ok=True)
        written = {p.name for p in write_profiles(target, names)}
    except OSError as err:
        what = err.strerror or str(err)
        click.echo(
            f"acordcs-gen profile export: error: cannot write the profile files into {directory}: "
            f"{what}; give a directory you can write to (it is created if missing)",
            err=True,
        )
        raise click.exceptions.Exit(2) from None
    for name in names:
        state = "wrote" if name in written else "up to date"
        click.echo(f"{state} {target / name} ({_NEXT_STEP[name]})")
