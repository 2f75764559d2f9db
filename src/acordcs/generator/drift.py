"""Drift between the model and the user's code, found when the application is built again.

The user's classes (``<pkg>/components/<Component>.py``, written once by the ``python`` target and
never again) implement the model's operations by name. When the model renames or removes an
operation, or a port whose notification handler ``on_<port>`` a class defines, the class's method
no longer matches anything: it would never be called, and the model's operation would raise
``OperationNotImplementedError`` at run time. The previous build's descriptor (the package's
``descriptor.xml``, still on disk) says what each method implemented, by the element's id: so a
rename is told apart from a removal, and the message names the new name.

A component renamed in the model keeps its id: the build writes a new class file under the new
name, and the warning says where the code is and what to move (:func:`find_drift`).

The previous descriptor is replaced by the build that reports the drift; after it, a class that
still implements the old name while the operation has no code is told so without the history:
its public methods that implement nothing the model declares are named beside the operation.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path

from acordcs.descriptor import Application, Component, DescriptorError, Operation, from_xml
from acordcs.diagnostics import Diagnostic, diagnostic
from acordcs.generator.paths import Unreadable, read_bounded


@dataclass(frozen=True)
class Drift:
    """One mismatch: the user file (relative to the output directory), the line, the message."""

    path: str
    line: int
    message: str
    element: str
    element_id: str
    column: int = 0
    code: str = "G704"


def previous_application(out: Path, package: str) -> Application | None:
    """The descriptor the package in ``out`` was last built from (None: no package there yet, or
    a descriptor that does not read, which then says nothing about drift)."""
    path = out / package / "descriptor.xml"
    try:  # a FIFO or a huge file is not read (the build reports it as an edited file)
        return from_xml(read_bounded(path), file=str(path))
    except (OSError, DescriptorError):
        return None


def _methods(source: str, class_name: str) -> dict[str, int] | None:
    """The methods ``class_name`` defines in ``source`` (name -> line), None when the file does not
    parse or has no such class (reported elsewhere: the launcher says so at start)."""
    try:
        tree = ast.parse(source)
    except (SyntaxError, ValueError):
        return None
    for node in tree.body:
        if isinstance(node, ast.ClassDef) and node.name == class_name:
            return {
                item.name: item.lineno
                for item in node.body
                if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef)
            }
    return None


# What a user class may define besides the model's operations and its ports' handlers: the
# component API and its hooks (acordcs.runtime.component.CtxComponent).
_API = frozenset(
    {"on_start", "on_stop", "on_property_changed", "save_state", "restore_state", "get", "set"}
)


def find_drift(out: Path, package: str, old: Application | None, new: Application) -> list[Drift]:
    """Every method of a user class that implemented an operation (or handled a port) the model
    has renamed or removed since ``old`` (None: no previous build), every user class of a
    component renamed since, and every operation without code in a class whose other public
    methods implement nothing the model declares (the likely old name)."""
    found: list[Drift] = []
    before = {c.id: c for c in old.components} if old is not None else {}
    for component in new.components:
        previous = before.get(component.id)
        if previous is not None and previous.name != component.name:
            found += _renamed_component(out, package, previous, component)
            continue
        path = f"{package}/components/{component.name}.py"
        try:
            source = read_bounded(out / path).decode("utf-8")
        except (OSError, UnicodeDecodeError):
            continue
        methods = _methods(source, component.name)
        if methods is None:
            continue
        stale = _stale_methods(path, methods, previous, component) if previous else []
        found += stale
        found += _without_code(path, methods, component, {d.element_id for d in stale})
    return found


def _without_code(
    path: str, methods: dict[str, int], component: Component, reported: set[str]
) -> list[Drift]:
    declared = {op.name for op in component.operations}
    handlers = {f"on_{p.name}" for p in component.ports}
    strays = sorted(
        (name, line)
        for name, line in methods.items()
        if not name.startswith("_") and name not in declared | handlers | _API
    )
    if not strays:
        return []
    out = []
    for op in component.operations:
        if op.name in methods or op.id in reported:
            continue
        listed = ", ".join(f"{name}() (line {line})" for name, line in strays)
        out.append(
            Drift(
                path,
                strays[0][1],
                f"operation {op.name} of component {component.name} has no code in class "
                f"{component.name}, which defines {listed}, implementing no operation of the "
                f"model: if one of them is {op.name} under an old name, rename it",
                component.qualified_name,
                op.id,
            )
        )
    return out


def stale_operations(
    methods: dict[str, int],
    old: Component,
    new: Component,
    code_name: Callable[[str], str] = str,
) -> Iterator[tuple[Operation, str, int, str | None]]:
    """The operations of the previous build's ``old`` whose method (by ``code_name``: the
    target's name of an operation) the user's class still defines at a line of ``methods``,
    though ``new`` has no operation of that name: each with its method's name, line, and the
    name the model gives it now (found by id), or None where it is gone."""
    current = {code_name(op.name) for op in new.operations}
    by_id = {op.id: code_name(op.name) for op in new.operations}
    for old_op in old.operations:
        name = code_name(old_op.name)
        line = methods.get(name)
        if line is not None and name not in current:
            yield old_op, name, line, by_id.get(old_op.id)


def _stale_methods(
    path: str, methods: dict[str, int], old: Component, new: Component
) -> list[Drift]:
    out: list[Drift] = []
    current_ports = {p.name for p in new.ports}
    ports_by_id = {p.id: p.name for p in new.ports}
    for old_op, _name, line, now in stale_operations(methods, old, new):
        if now is not None:
            message = (
                f"method {old_op.name}() of class {new.name} implements operation "
                f"{old_op.name}, which the model now names {now} (id {old_op.id}): rename the "
                f"method to {now}, or it is never called and {now}() has no code"
            )
        else:
            message = (
                f"method {old_op.name}() of class {new.name} implements operation "
                f"{old_op.name} (id {old_op.id}), which is no longer in the model: remove the "
                "method, or put the operation back in the model"
            )
        out.append(Drift(path, line, message, new.qualified_name, old_op.id))
    for old_port in old.ports:
        handler = f"on_{old_port.name}"
        at = methods.get(handler)
        if at is None or old_port.name in current_ports:
            continue
        now = ports_by_id.get(old_port.id)
        if now is not None:
            message = (
                f"method {handler}() of class {new.name} handles port {old_port.name}, which the "
                f"model now names {now} (id {old_port.id}): rename the method to on_{now}"
            )
        else:
            message = (
                f"method {handler}() of class {new.name} handles port {old_port.name} (id "
                f"{old_port.id}), which is no longer in the model: remove the method"
            )
        out.append(Drift(path, at, message, new.qualified_name, old_port.id))
    return out


def _renamed_component(out: Path, package: str, old: Component, new: Component) -> list[Drift]:
    old_path = f"{package}/components/{old.name}.py"
    if not (out / old_path).is_file():
        return []
    return [
        Drift(
            old_path,
            1,
            f"{old_path} is your code for component {old.name}, which the model now names "
            f"{new.name} (id {new.id}); the build wrote a new class file for {new.name}: move "
            f"your code into {package}/components/{new.name}.py (class {new.name}, derived "
            f"from {new.name}Base imported from {package}.base.{new.name}) and delete "
            f"{old_path}",
            new.qualified_name,
            new.id,
        )
    ]


def not_compiling(out: Path, package: str, app: Application) -> list[Drift]:
    """Every user class of ``app`` (``components/<Component>.py``, ``monitors/<Monitor>.py``:
    what the package's registry imports when a container starts) that does not compile, as the
    container's start finds it (``compile``, nothing run: the SyntaxError's line and column), or
    that a build does not read (a FIFO, a file over 64 MiB): warnings G705. A class file that is
    missing is not one: the build writes it again."""
    found: list[Drift] = []
    kinds = [("components", c) for c in app.components] + [("monitors", m) for m in app.monitors]
    for folder, element in kinds:
        path = f"{package}/{folder}/{element.name}.py"
        what = f"{'component' if folder == 'components' else 'monitor'} {element.name}"
        try:
            source = read_bounded(out / path)
        except FileNotFoundError:
            continue
        except Unreadable as err:
            message = (
                f"{path}, the class of {what}, is {err.what}: a build does not read it, and a "
                "container hosting it cannot import it; make it a regular file of your code"
            )
            found.append(Drift(path, 0, message, element.qualified_name, element.id, 0, "G705"))
            continue
        except OSError:
            continue
        try:
            compile(source, str(out / path), "exec", dont_inherit=True)
        except SyntaxError as err:  # IndentationError, a bad encoding too
            message = (
                f"class of {what} does not compile: {err.msg}; a container hosting it stops at "
                "start (exit 2) until this is fixed"
            )
            found.append(
                Drift(
                    path,
                    err.lineno or 1,
                    message,
                    element.qualified_name,
                    element.id,
                    err.offset or 0,
                    "G705",
                )
            )
        except ValueError as err:  # a NUL byte in the source
            message = f"class of {what} does not compile: {err}"
            found.append(Drift(path, 1, message, element.qualified_name, element.id, 0, "G705"))
    return found


def as_diagnostics(drift: list[Drift], out: Path) -> list[Diagnostic]:
    """The drift as warnings G704 (G705: a class that does not compile), located in the user's
    files."""
    return [
        diagnostic(
            d.code,
            d.message,
            file=str(out / d.path),
            line=d.line,
            column=d.column,
            element=d.element,
            xmi_id=d.element_id,
        )
        for d in drift
    ]
