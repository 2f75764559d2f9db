"""Operations that the model calls and that have no code, found when a container starts, and by
``acordcs-gen update`` before it changes a running one.

After a model changes (an operation renamed, a component given a new operation), the user's class
may lack the code of an operation something calls: every call then raises
:class:`~acordcs.runtime.errors.OperationNotImplementedError`, a fault at run time.
:func:`operations_without_code` lists them before anything runs, for one container of a running
application: the operations of the components hosted there that have no code (:func:`has_code`:
the user's class does not override the generated base's method) and that a caller reaches
(:func:`callers`, from the descriptor):

- a crisp rule of a policy set hosted there calls it (the operations its rules' actions resolved
  to, the descriptor's ``bound`` operations);
- a polling monitor hosted there polls it (its ``operation`` on its source component);
- a connection of the model joins a required port to a *synchronous* provided port of the
  component: every operation of the component can be called through that port (the model does
  not say which ones a port offers), from wherever the required end runs;
- a ``--run COMPONENT.OPERATION`` of the container's command line calls it.

Asynchronous and stream ports call no operation (they deliver to ``on_<port>`` handlers), nor do
intercepting or subscribing monitors.

:func:`operations_without_code_in_files` answers the same question for a descriptor not yet
running, from the user's files in the application's directory (``<package>/components/<C>.py``,
read, not imported: a method the class defines is code; a class deriving from anything else than
its generated base may inherit code, so it is not judged): what ``acordcs-gen update`` says
before it applies a model, in the same words as a start.
"""

from __future__ import annotations

import ast
import inspect
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.runtime.assembly import RunningApplication
from acordcs.runtime.operations import has_code

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application


@dataclass(frozen=True)
class MissingCode:
    """An operation of a component hosted in the container, without code, and what calls it;
    the class to edit is ``class_name``, at ``line`` of ``file`` (None: unknown)."""

    component: str
    operation: str
    class_name: str
    callers: tuple[str, ...]
    file: Path | None = None
    line: int | None = None

    def where(self, cwd: Path | None = None) -> str:
        """``file:line`` of the class to edit (the file relative to ``cwd`` when under it)."""
        if self.file is None:
            return f"class {self.class_name}"
        file = self.file
        base = (cwd or Path.cwd()).absolute()
        if file.absolute().is_relative_to(base):
            file = file.absolute().relative_to(base)
        return f"{file}:{self.line}" if self.line else str(file)

    def message(self, cwd: Path | None = None) -> str:
        """One warning line: where, what, what calls it and what to do."""
        return (
            f"{self.where(cwd)}: warning: {self.component}.{self.operation}() has no code, and "
            f"{'; '.join(self.callers)}: implement {self.operation}() in class "
            f"{self.class_name} (each call raises OperationNotImplementedError until then)"
        )


def hosted_here(app: Application, container: str, kind: str) -> list[str]:
    """The elements of ``kind`` (component, monitor, policy-set) that run in ``container``, in the
    descriptor's order (an element no container hosts runs in the first one)."""
    place = {r.name: c.name for c in app.containers for r in c.hosts}
    default = app.containers[0].name if app.containers else app.name
    names = {
        "component": [c.name for c in app.components],
        "monitor": [m.name for m in app.monitors],
        "policy-set": [p.name for p in app.policy_sets],
    }[kind]
    return [n for n in names if place.get(n, default) == container]


def callers(
    app: Application, container: str, runs: Iterable[tuple[str, str]] = ()
) -> dict[tuple[str, str], list[str]]:
    """What calls each operation of the components ``container`` hosts in ``app`` (see the
    module's docstring): (component, operation) -> the callers, as the warnings name them;
    ``runs``: the (component, operation) pairs the command line calls."""
    hosted = set(hosted_here(app, container, "component"))
    found: dict[tuple[str, str], list[str]] = {}

    def called(component: str, operation: str, by: str) -> None:
        if component in hosted:
            found.setdefault((component, operation), []).append(by)

    here = set(hosted_here(app, container, "policy-set"))
    for ps in app.policy_sets:
        if ps.name not in here:
            continue  # hosted in another container: it calls the operations of that one
        ops = {(b.element, b.member) for b in ps.bound if b.kind == "operation"}
        for component, operation in sorted(ops):
            called(component, operation, f"policy set {ps.name} calls it")
    monitors = {m.name: m for m in app.monitors}
    for name in sorted(hosted_here(app, container, "monitor")):
        mon = monitors[name]
        sources = [s.name for s in mon.sources if "." not in s.name]
        if mon.acquisition == "poll" and mon.operation and len(sources) == 1:
            called(sources[0], mon.operation, f"monitor {name} polls it")
    components = {c.name: c for c in app.components}
    for conn in app.connections:
        provider = components.get(conn.provided.component)
        port = (
            next((p for p in provider.ports if p.name == conn.provided.port), None)
            if provider
            else None
        )
        if provider is None or port is None or port.kind != "synchronous":
            continue
        by = (
            f"connection {conn.name} reaches it from {conn.required.component}.{conn.required.port}"
        )
        for operation in dict.fromkeys(op.name for op in provider.operations):
            called(provider.name, operation, by)
    for component, operation in runs:
        called(component, operation, "--run calls it")
    return found


def operations_without_code(
    app: RunningApplication, container: str, runs: Iterable[tuple[str, str]] = ()
) -> list[MissingCode]:
    """The operations of the components of ``container`` (a container of ``app``) that have no
    code and that something calls (see the module's docstring); ``runs``: the (component,
    operation) pairs the command line calls. Sorted by component and operation."""
    running = app.container(container)
    classes = {ref.name: type(ref.instance) for ref in running.components()}
    return [
        MissingCode(component, operation, cls.__name__, tuple(by), *_place(cls))
        for (component, operation), by in sorted(callers(app.descriptor, container, runs).items())
        if (cls := classes.get(component)) is not None and not has_code(cls, operation)
    ]


def _place(cls: type) -> tuple[Path | None, int | None]:
    try:
        file = Path(inspect.getfile(cls))
    except TypeError:
        return None, None
    try:
        return file, inspect.getsourcelines(cls)[1]
    except (OSError, TypeError):
        return file, None


def operations_without_code_in_files(
    app: Application, container: str, directory: Path, package: str
) -> list[MissingCode]:
    """The operations of the components ``container`` hosts in ``app`` that have no code in the
    user's classes of ``directory``'s package ``package`` and that something calls, from the
    files (see the module's docstring); a class whose file does not read or parse, or that
    derives from another class than its generated base, is not judged. Sorted as
    :func:`operations_without_code`."""
    out = []
    classes: dict[str, tuple[Path, int, set[str]] | None] = {}
    # A Java component's code is its Java class, which javac judges at start: not judged here.
    java = {c.name for c in app.components if c.language == "java"}
    for (component, operation), by in sorted(callers(app, container).items()):
        if component in java:
            continue
        if component not in classes:
            classes[component] = _defined(directory / package / "components", component)
        found = classes[component]
        if found is not None and operation not in found[2]:
            out.append(MissingCode(component, operation, component, tuple(by), *found[:2]))
    return out


def _defined(folder: Path, component: str) -> tuple[Path, int, set[str]] | None:
    """The user's class ``component`` in ``folder/<component>.py``: the file, the class's line
    and the names its body defines; None when it cannot be judged (see above)."""
    path = folder / f"{component}.py"
    try:
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except (OSError, SyntaxError, ValueError):
        return None
    for node in tree.body:
        if not isinstance(node, ast.ClassDef) or node.name != component:
            continue
        bases = [b.id if isinstance(b, ast.Name) else None for b in node.bases]
        if bases != [f"{component}Base"] or node.keywords:
            return None
        names: set[str] = set()
        for item in node.body:
            if isinstance(item, ast.FunctionDef | ast.AsyncFunctionDef):
                names.add(item.name)
            elif isinstance(item, ast.Assign):
                names.update(t.id for t in item.targets if isinstance(t, ast.Name))
            elif (
                isinstance(item, ast.AnnAssign)
                and isinstance(item.target, ast.Name)
                and item.value is not None
            ):
                names.add(item.target.id)
        line = min([node.lineno, *(d.lineno for d in node.decorator_list)])
        return path, line, names
    return None


__all__ = [
    "MissingCode",
    "callers",
    "hosted_here",
    "operations_without_code",
    "operations_without_code_in_files",
]
