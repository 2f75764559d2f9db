"""``acordcs-gen``: validate, inspect, build and export ACORD-CS applications modelled in UML.

The click group :data:`cli` is the executable. :func:`main` runs it and turns every outcome into an
exit code (0 ok, 1 failure found, 2 usage or unreadable input), never a traceback; tests and
library users call it. :func:`run`, the installed ``acordcs-gen``, is :func:`main` in a process
that lives for one command, with what only such a process may do (see :func:`run`).
"""

from __future__ import annotations

import os
import sys
from typing import NoReturn

import click

from acordcs import __version__
from acordcs.cli import build, export, inspect, profile_export, update, validate
from acordcs.cli import testing as scenario_testing
from acordcs.cli.convert import convert as convert_command
from acordcs.cli.serve_console import console as console_command


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="acordcs-gen")
def cli() -> None:
    """ACORD-CS toolchain: read UML models (BOUML XMI, Eclipse UML2/Papyrus), check them and
    generate the application's files from them; write the UML profile for BOUML and Papyrus, and
    a model as an instance of the ACORD-CS metamodel for EMF tools."""


cli.add_command(validate.validate)
cli.add_command(inspect.inspect)
cli.add_command(build.build)
cli.add_command(profile_export.profile)
cli.add_command(export.export)
cli.add_command(update.update)
cli.add_command(scenario_testing.test)
cli.add_command(convert_command)
cli.add_command(console_command)


def main(argv: list[str] | None = None) -> int:
    """Run ``acordcs-gen`` with ``argv`` (default: the process's arguments); return the exit code."""
    try:
        return cli.main(args=argv, prog_name="acordcs-gen", standalone_mode=False) or 0
    except click.exceptions.Exit as done:
        return done.exit_code
    except click.ClickException as err:
        err.show()
        return err.exit_code
    except click.exceptions.Abort:
        click.echo("acordcs-gen: aborted", err=True)
        return 2
    except BrokenPipeError:
        return 1
    except Exception as err:  # a bug of ours: say so plainly, no traceback
        click.echo(
            f"acordcs-gen: internal error: {type(err).__name__}: {err} (this is a bug in acordcs; "
            "please report it with the input file)",
            err=True,
        )
        return 2


def run() -> NoReturn:
    """The installed ``acordcs-gen``: :func:`main` in a process that lives for one command, which
    ends with ``os._exit`` once its output is flushed.

    Tearing the interpreter down would free the parsed tree and the tens of thousands of model
    objects one at a time: about a quarter of ``validate``'s whole time on a large model
    (docs/benchmarks.md: the benchmark measures it on and off). Commands write files only in ``with``
    blocks, so nothing they write is still buffered here; standard output and error are flushed
    below.
    """
    code = main()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more can be said
            code = code or 1
    os._exit(code)


if __name__ == "__main__":
    sys.exit(main())
