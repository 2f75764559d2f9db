"""Target ``python``: a Python package per application, written by the XSLT 3.0 stylesheet
``python.xsl`` (see it for the files), run from this function after one check that needs Python.

The check: every model name that becomes Python code (a class, module, method or parameter name)
is an identifier that is no Python keyword, an operation name is no name of the component API
(``acordcs.model.generated_names.COMPONENT_API``: ``get``, ``properties``...) and does not start with ``_``, a
parameter is not ``self``, and a container's module does not take the name of one of the
package's own modules. Anything else is refused with G703 before the stylesheet runs: the
stylesheet writes names as they are, and string literals (names as strings, defaults,
documentation) through its own escaping (``py:str``, ``py:doc``).

The package's name is :func:`package_name` of the application's name (``WebLab`` ->
``weblab_app``): lower case, non-identifier characters replaced by ``_``, ``m`` before a leading
digit, ``_app`` appended, so it is an identifier, no keyword, no module of the standard library
(none ends in ``_app``) and not ``acordcs``.

A container module names its package and container and hands over to
:class:`acordcs.runtime.launcher.Launcher`, which assembles the container from the package's copy
of the descriptor (``descriptor.xml``, the document the ``config`` target writes) with the
registry of user classes: one source of truth for what a container holds, and the package runs
wherever it is copied.

The types (:func:`typing_plan`, given to the stylesheet as JSON): a property's Python type is its
kind's (``int``, ``float``, ``bool``; ``str`` for a string-typed one); a parameter's or return
value's is its UML type's by the table of :func:`python_type` (the one
:func:`acordcs.descriptor.value_kind` reads defaults by); any other UML type is ``object``, named
in ``model_types.py`` (``model_types.Image``) when its name can be a Python name. A property
becomes a typed attribute of the base class (``self.maxSpeed: float``,
:class:`acordcs.runtime.component.ModelProperty`) unless its name is taken (:data:`TAKEN`, an
operation of the component, ``on_<port>``) or is no identifier: code reads those with ``get``.
"""

from __future__ import annotations

import builtins
import json
import keyword
import re
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

from acordcs.generator.target import Target, target
from acordcs.generator.targets.refused_names import NameRefused, refused
from acordcs.model.generated_names import (
    CLASS_SCOPE,
    COMPONENT_API,
    COMPONENT_ATTRIBUTES,
    OWN_MODULES,
    Named,
    python_name_problem,
)
from acordcs.vocabularies import ARGUMENT_DIRECTIONS, RESULT_DIRECTIONS

if TYPE_CHECKING:
    from acordcs.descriptor import Application, Component

STYLESHEET = resources.files("acordcs.transforms") / "python.xsl"

# A UML type read as a number or a truth value (acordcs.descriptor.value_kind's kinds) -> Python.
KIND_TYPES = {"int": "int", "double": "float", "bool": "bool"}


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


def python_type(uml: str) -> str:
    """The annotation of a value of UML type ``uml``: ``int``, ``float``, ``bool``, ``str``,
    ``model_types.<uml>`` for another type whose name can be a Python name, else ``object``."""
    from acordcs.descriptor import value_kind

    text = uml.strip()
    kind = value_kind(text) if text else ""
    if kind in KIND_TYPES:
        return KIND_TYPES[kind]
    if text.lower() == "string":
        return "str"
    return f"model_types.{text}" if alias_allowed(text) else "object"


def alias_allowed(uml: str) -> bool:
    """Whether model_types.py names the UML type ``uml``: an ASCII identifier, no keyword, not
    private, no name of Python's builtins (a type ``bytes`` stays ``object``, not bytes)."""
    return (
        uml.isascii()
        and uml.isidentifier()
        and not keyword.iskeyword(uml)
        and not uml.startswith("_")
        and uml not in dir(builtins)
        and uml.lower() != "void"
    )


def taken() -> frozenset[str]:
    """The names a property attribute cannot take: the component API (its members, and what the
    container sets on an instance) and the names the class scope uses."""
    return COMPONENT_API | COMPONENT_ATTRIBUTES | CLASS_SCOPE


def _attribute_allowed(name: str, component: Component, reserved: frozenset[str]) -> bool:
    return (
        name.isascii()  # Python folds other identifiers (NFKC): the attribute would be renamed
        and name.isidentifier()
        and not keyword.iskeyword(name)
        and not name.startswith("_")
        and name not in reserved
        and name not in {op.name for op in component.operations}
        and name not in {f"on_{port.name}" for port in component.ports}
    )


def typing_plan(app: Application) -> dict[str, Any]:
    """The Python types of the package's signatures, for python.xsl (see the module's docstring):
    ``types`` (UML type -> annotation), ``returns`` (UML return type, ``""`` for none ->
    annotation), ``attributes`` (component -> property -> annotation, the typed attributes) and
    ``aliases`` (UML type -> where model_types.py says it is used)."""
    types: dict[str, str] = {}
    returns: dict[str, str] = {"": "None"}
    attributes: dict[str, dict[str, str]] = {}
    aliases: dict[str, list[str]] = {}
    reserved = taken()

    def note(annotation: str, where: str) -> str:
        if annotation.startswith("model_types."):
            aliases.setdefault(annotation.partition(".")[2], []).append(where)
        return annotation

    for comp in app.components:
        typed = attributes.setdefault(comp.name, {})
        for prop in comp.properties:
            annotation = KIND_TYPES.get(prop.kind) or python_type(prop.type)
            if _attribute_allowed(prop.name, comp, reserved) and prop.name not in typed:
                typed[prop.name] = note(annotation, f"{comp.name}.{prop.name}")
        for op in comp.operations:
            for param in op.parameters:
                types[param.type] = note(python_type(param.type), f"{comp.name}.{op.name}")
            text = op.return_type or ""
            blank = text.strip().lower() in ("", "void")
            returns[text] = "None" if blank else note(python_type(text), f"{comp.name}.{op.name}")
    return {
        "types": types,
        "returns": returns,
        "attributes": attributes,
        "aliases": {name: list(dict.fromkeys(uses)) for name, uses in aliases.items()},
    }


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
    from acordcs.generator.xslt import run_stylesheet

    run_stylesheet(
        _STYLESHEET_TARGET,
        context,
        {
            "package": package_name(context.application.name),
            "typing": json.dumps(typing_plan(context.application)),
            "argument-directions": " ".join(ARGUMENT_DIRECTIONS),
            "result-directions": " ".join(RESULT_DIRECTIONS),
        },
    )


__all__ = [
    "CLASS_SCOPE",
    "OWN_MODULES",
    "STYLESHEET",
    "check_names",
    "package_name",
    "python",
    "python_type",
    "taken",
    "typing_plan",
]
