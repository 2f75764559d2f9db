"""Which model names the generated files can take: as part of a file name (G701) and as Python
code (G703).

One set of rules with two callers: ``validate`` runs them on the model (the check
``generated_names`` in :mod:`acordcs.model.checks.element_names`), so that a model ``validate`` passes is one
``build`` (which validates first) can generate; the ``python`` target runs them on the descriptor it
is given (:func:`acordcs.generator.targets.python.check_names`: a descriptor may be made otherwise).
Names that are no identifier, keywords and names of the component API are N601, N602 and N604 in
``validate`` (:mod:`acordcs.model.checks.element_names`); the ``python`` target refuses them too (G703).
The paths the targets make are checked whole after they ran (:mod:`acordcs.generator.paths`).

A leaf: the standard library only.
"""

from __future__ import annotations

import keyword
import re
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

COMPONENT_API = frozenset(
    {
        "alive",
        "call",
        "clock",
        "get",
        "instance",
        "name",
        "on_property_changed",
        "on_start",
        "on_stop",
        "operation_names",
        "port",
        "ports",
        "properties",
        "publish_context",
        "restore_state",
        "save_state",
        "set",
        "state_fields",
        "type_name",
    }
)
"""The public names every component has at run time, on itself and on the handles callers hold
(the members of :class:`acordcs.runtime.component.CtxComponent` and ``ComponentRef`` not starting
with ``_``): a model operation of the same name would hide one (the check N604 and the code
generators refuse it). Declared here, where the rules on generated names are, so that checking and
generating never import the runtime; a test holds it equal to the classes' members."""

COMPONENT_ATTRIBUTES = frozenset(
    {
        "alive",
        "container",
        "factory",
        "name",
        "port_map",
        "ports",
        "properties",
        "props",
        "state_fields",
    }
)
"""What the container sets on a component instance (``CtxComponent``'s annotations): a generated
property attribute cannot take one of these names either; a test holds it equal to the class's."""

# Characters no portable file name holds: separators, NUL and other controls, and what Windows
# refuses (a generated tree is copied, committed, checked out elsewhere).
_BAD_CHARS = re.compile(r'[\x00-\x1f\x7f/\\<>:"|?*]')
DEVICE_NAMES = frozenset(
    ["CON", "PRN", "AUX", "NUL"]
    + [f"COM{n}" for n in range(1, 10)]
    + [f"LPT{n}" for n in range(1, 10)]
)
"""Device names Windows reserves whatever the extension (``CON.txt`` is ``CON``), in upper case."""
RULE = (
    "a file name: not empty, not '.' or '..', no '/', '\\', control characters or <>:\"|?*, "
    "not ending in a dot or space, not a Windows device name such as CON or NUL, at most 200 bytes"
)

NAME_BYTES = 200
"""The longest model name the build lets become part of a file name: a target adds to it (an
extension, ``.descriptor.xml``), and file systems allow 255 bytes per component."""

# ASCII only: the same name must be a Python and a Java identifier and a shell word without quoting.
IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
NOT_AN_IDENTIFIER = "it is not an identifier (letters, digits and _, not starting with a digit)"

OWN_MODULES = frozenset(
    {
        "__init__",
        "__main__",
        "registry",
        "base",
        "components",
        "monitors",
        "descriptor",
        "model_types",
    }
)
"""Modules and packages of the generated Python package: no container's module may take one of
these names (in any letter case: one file on case-insensitive file systems)."""

CLASS_SCOPE = frozenset(
    {
        "CtxComponent", "ModelProperty", "PortSpec", "OperationNotImplementedError",
        "unimplemented", "model_types", "annotations", "int", "float", "bool", "str", "object",
        "tuple",
    }
)  # fmt: skip
"""The names a generated base module binds and uses in its class's scope (imports, annotations):
no operation may take one (it would hide them)."""

SUBPACKAGE_MODULES = frozenset({"__init__"})
"""What a component's or monitor's modules (``base/<Name>.py``, ``components/<Name>.py``,
``monitors/<Name>.py``) must not be called: the subpackage's own ``__init__.py``."""

FILE_KINDS = frozenset(
    {"model", "container", "component", "connection", "monitor", "policy set", "port", "policy"}
)
"""The kinds of element whose name may become part of a generated file's name."""


@dataclass(frozen=True, slots=True)
class Named:
    """A name of the model: ``kind`` (``model``, ``container``, ``component``, ``operation``,
    ``parameter``...), the ``name``, the ``id`` of its element and the element's qualified name."""

    kind: str
    name: str
    id: str
    qualified: str


@dataclass(frozen=True, slots=True)
class NameProblem:
    code: str  # G701 or G703
    message: str  # the diagnostic's message
    named: Named
    reason: str  # why, in a few words (the message holds it)


def segment_problem(name: str, limit: int = 255) -> str | None:
    """Why ``name`` cannot be one component of a generated path, at most ``limit`` bytes long
    (None when it can)."""
    if not name:
        return "it is empty"
    if name in (".", ".."):
        return f"{name!r} names a directory, not a file"
    bad = _BAD_CHARS.search(name)
    if bad:
        char = bad.group()
        shown = repr(char) if char.isprintable() else f"U+{ord(char):04X}"
        return f"it contains {shown}"
    if name[-1] in ". ":
        return "it ends in a dot or a space"
    if len(name.encode("utf-8", "surrogatepass")) > limit:
        room = "" if limit == 255 else ", to leave room for what a target adds to it"
        return f"it is longer than {limit} bytes (file systems allow 255{room})"
    if name.split(".", 1)[0].rstrip(" ").upper() in DEVICE_NAMES:
        return f"{name.split('.', 1)[0]!r} is a device name on Windows"
    return None


def _what(named: Named) -> str:
    if named.kind == "model" or named.qualified == named.name:
        return f"the {named.kind}"
    return f"{named.kind} {named.qualified!r}"


def file_name_problem(named: Named) -> NameProblem | None:
    """G701 when ``named`` may become part of a file name but cannot."""
    if named.kind not in FILE_KINDS:
        return None
    problem = segment_problem(named.name, NAME_BYTES)
    if problem is None:
        return None
    return NameProblem(
        "G701",
        f"the name {named.name!r} of {_what(named)} cannot become part of a file name: "
        f"{problem}; rename it ({RULE})",
        named,
        problem,
    )


def _python_reason(named: Named, identifiers: bool) -> str | None:
    name, kind = named.name, named.kind
    if identifiers:
        if not IDENTIFIER.match(name):
            return NOT_AN_IDENTIFIER
        if keyword.iskeyword(name):
            return "it is a Python keyword"
    if kind == "operation":
        if identifiers and name in COMPONENT_API:
            return (
                "it is a name of the component API, which every component has "
                f"({', '.join(sorted(COMPONENT_API))})"
            )
        if name.startswith("_"):
            return "it starts with _: private to the generated base class and the runtime"
        if name in CLASS_SCOPE:
            return "it is a name the generated base class uses (an import or a type in its scope)"
    if kind == "parameter" and name == "self":
        return "'self' is the method's own first parameter"
    if kind == "container" and name.lower() in OWN_MODULES:
        return (
            f"its module {name}.py would be a module of the generated package already (the "
            f"package's own: {', '.join(sorted(OWN_MODULES))}, in any letter case)"
        )
    if kind in ("component", "monitor") and name in SUBPACKAGE_MODULES:
        folder = "components" if kind == "component" else "monitors"
        return (
            f"its modules base/{name}.py and {folder}/{name}.py would be those subpackages' own "
            f"{name}.py"
        )
    return None


def python_name_problem(named: Named, *, identifiers: bool = True) -> NameProblem | None:
    """G703 when ``named`` (a container, component, monitor, operation or parameter) cannot be
    written into the generated Python package. ``identifiers`` False leaves out what ``validate``
    reports with its own codes (no identifier: N601, a keyword: N602, the component API: N604)."""
    if named.kind not in ("container", "component", "monitor", "operation", "parameter"):
        return None
    reason = _python_reason(named, identifiers)
    if reason is None:
        return None
    return NameProblem(
        "G703",
        f"{named.kind} {named.name!r} cannot be written into the generated Python files: "
        f"{reason}; rename it",
        named,
        reason,
    )


def name_problems(names: Iterable[Named], *, identifiers: bool = True) -> Iterator[NameProblem]:
    """Every G701 and G703 problem of ``names`` (see :func:`python_name_problem` for
    ``identifiers``)."""
    for named in names:
        for problem in (
            file_name_problem(named),
            python_name_problem(named, identifiers=identifiers),
        ):
            if problem is not None:
                yield problem


__all__ = [
    "CLASS_SCOPE",
    "DEVICE_NAMES",
    "FILE_KINDS",
    "IDENTIFIER",
    "NAME_BYTES",
    "NOT_AN_IDENTIFIER",
    "OWN_MODULES",
    "RULE",
    "SUBPACKAGE_MODULES",
    "NameProblem",
    "Named",
    "file_name_problem",
    "name_problems",
    "python_name_problem",
    "segment_problem",
]
