"""Target ``shell``: POSIX ``sh`` scripts running the ``python`` target's package, one process per
container, written by the XSLT 3.0 stylesheet ``shell.xsl`` (see it for the files; the functions the
scripts share are in ``shell-functions.xsl``, which it includes) after one check that needs Python.

Files (in ``bin/``): ``env.sh``, sourced by every script (the interpreter, ``PYTHONPATH``, the
run directory, each container's host and port; protected regions for the user's lines, keyed by
the application and by each container's model id, kept by every build:
:mod:`acordcs.codegen.regions`; then the functions the scripts share and the checks of the
settings); per container ``<C>-start``, ``<C>-stop`` and ``<C>-status``; ``start-all`` and
``stop-all``. What the scripts promise (which process a stop signals, the run directory, the
token file) is in docs/build.md, "The scripts' security model".

The check: the names are checked with the ``python`` target's own check (the scripts run its
modules, and a container's name becomes part of shell variable names: an ASCII identifier). Every
other model string that reaches a script goes through the stylesheet's one quoting function,
``sh:quote`` (single quotes, ``'`` written ``'\\''``, a line break followed by ``''`` so that no
line starts with model text), or only into comments through ``sh:comment`` (line breaks and
control characters escaped).

Three values the stylesheet is given, decided here once: the package's name
(:func:`acordcs.codegen.targets.python.package_name`), the interpreter that runs this build
(``sys.executable``: the scripts' default ``PYTHON``, named in ``env.sh``'s header; it is part of
the target's fingerprint, so another interpreter rebuilds) and each container's region key
(:func:`acordcs.codegen.regions.key`).
"""

from __future__ import annotations

import sys
from importlib import resources
from pathlib import Path

from acordcs.codegen import regions
from acordcs.codegen.context import TargetContext
from acordcs.codegen.registry import Target, target
from acordcs.codegen.targets.names import NameRefused, refused
from acordcs.codegen.targets.python import check_names, package_name

STYLESHEET = resources.files(__package__) / "shell.xsl"

ENV_FILE = "bin/env.sh"
"""The one file with protected regions, sourced by the others; every other file is a script."""


def interpreter() -> str:
    """The Python the scripts run by default: the one running this build."""
    return sys.executable or "python3"


# The stylesheet as a target object, not registered: run by the function target below.
_STYLESHEET_TARGET = Target("shell", "shell.xsl", stylesheet=Path(str(STYLESHEET)))


@target(
    "shell",
    description="POSIX sh scripts starting, stopping and checking each container of the python "
    "package, and an environment file with protected regions (XSLT 3.0)",
    version=f"interpreter {interpreter()}",
)
def shell(context) -> None:
    """POSIX sh scripts per container (start, stop, status), start-all, stop-all, env.sh
    (shell.xsl), after the names are checked."""
    app = context.application
    try:
        check_names(app)
    except NameRefused as err:
        raise refused(context, err, "shell") from None
    from acordcs.codegen.xslt import run_stylesheet

    # The stylesheet's listing says which files it wrote; whether a file is a script or has
    # regions is this target's to say (ENV_FILE), so its files are emitted again with that.
    made = TargetContext(
        context.target,
        app,
        context.descriptor_xml,
        context.source,
        context.workdir,
        context.generator,
        locate=context.locate,
    )
    run_stylesheet(
        _STYLESHEET_TARGET,
        made,
        {
            "package": package_name(app.name),
            "python": interpreter(),
            "region-keys": " ".join(regions.key(c.id) for c in app.containers),
        },
    )
    context.messages.extend(made.messages)
    for f in made.files:
        env = f.path == ENV_FILE
        context.emit(
            f.path,
            f.data,
            element=f.element,
            ids=f.ids,
            regions="hash" if env else "",
            executable=not env,
        )


__all__ = ["ENV_FILE", "STYLESHEET", "interpreter", "shell"]
