"""Target ``python``: a Python package per application, written by the XSLT 3.0 stylesheet
``python.xsl`` (see it for the files), run from this function after one check that needs Python.

The check: every model name that becomes Python code (a class, module, method or parameter name)
is an identifier that is no Python keyword, an operation name is no name of the component API
(``acordcs.runtime.component.COMPONENT_API``: ``get``, ``properties``...) and does not start with ``_``, a
parameter is not ``self``, and a container's module does not take the name of one of the
package's own modules. Anything else is refused with G703 before the stylesheet runs: the
stylesheet writes names as they are, and string literals (names as strings, defaults,
documentation) through its own escaping (``py:str``, ``py:doc``).

The package's name is :func:`package_name` of the application's name (``WebLab`` ->
``weblab_app``): lower case, non-identifier characters replaced by ``_``, ``m`` before a leading
digit, ``_app`` appended, so it is an identifier, no keyword, no module of the standard library
(none ends in ``_app``) and not ``acordcs``.

The container modules call :func:`acordcs.runtime.assembly.assemble` on the package's copy of the
descriptor (``descriptor.xml``, the document the ``config`` target writes) with the registry of
user classes, ``only=[container]``: one source of truth for what a container holds, and the package
runs wherever it is copied.
"""

from __future__ import annotations

import re
from importlib import resources
from pathlib import Path

from acordcs.codegen.registry import Target, target
from acordcs.codegen.targets.names import NameRefused, refused
from acordcs.model.generated_names import OWN_MODULES, Named, python_name_problem

STYLESHEET = resources.files(__package__) / "python.xsl"


def package_name(application: str) -> str:
    """The generated package's name for the application ``application`` (given to python.xsl as
    its parameter ``package``)."""
    base = re.sub(r"[^A-Za-z0-9_]", "_", application).lower()
    return ("m" if base[:1].isdigit() else "") + base + "_app"


def _names(app):
    for c in app.containers:
        yield Named("container", c.name, c.id, c.qualified_name)
    for mon in app.monitors:
        yield Named("monitor", mon.name, mon.id, mon.qualified_name)
    for comp in app.components:
        yield Named("component", comp.name, comp.id, comp.qualified_name)
        for op in comp.operations:
            yield Named("operation", op.name, op.id, op.qualified_name)
            for p in op.parameters:
                yield Named("parameter", p.name, p.id or op.id, op.qualified_name)


def check_names(app) -> None:
    """Raise :class:`NameRefused` for the first name that cannot become Python code (the rules of
    :mod:`acordcs.model.generated_names`, which ``validate`` runs on the model too)."""
    for named in _names(app):
        problem = python_name_problem(named)
        if problem is not None:
            raise NameRefused(named.kind, named.name, named.id, named.qualified, problem.reason)


# The stylesheet as a target object, not registered: run by the function target below.
_STYLESHEET_TARGET = Target("python", "python.xsl", stylesheet=Path(str(STYLESHEET)))


@target(
    "python",
    description="a Python package: component base classes, user classes written once, "
    "container modules (XSLT 3.0)",
)
def python(context) -> None:
    """A Python package per application (python.xsl), after the names are checked."""
    try:
        check_names(context.application)
    except NameRefused as err:
        raise refused(context, err, "Python") from None
    from acordcs.codegen.xslt import run_stylesheet

    run_stylesheet(_STYLESHEET_TARGET, context, {"package": package_name(context.application.name)})


__all__ = ["OWN_MODULES", "STYLESHEET", "check_names", "package_name", "python"]
