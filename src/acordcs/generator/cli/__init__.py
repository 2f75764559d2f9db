"""``acordcs-gen``: validate, inspect and build ACORD-CS applications from UML models."""

from __future__ import annotations

import sys

import click

from acordcs import __version__


@click.group(context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="acordcs-gen")
def cli() -> None:
    """ACORD-CS toolchain: read UML models (BOUML XMI, Eclipse UML2/Papyrus), check, generate."""


def _register() -> None:
    from acordcs.generator.cli import inspect, validate

    cli.add_command(validate.validate)
    cli.add_command(inspect.inspect)


_register()


def main(argv: list[str] | None = None) -> int:
    """Entry point: never a traceback; exit 0 ok, 1 failure found, 2 usage or unreadable input."""
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


if __name__ == "__main__":
    sys.exit(main())
