"""Operations that the model calls and that have no code, found when a container starts.

After a model changes (an operation renamed, a component given a new operation), the user's class
may lack the code of an operation something calls: every call then raises
:class:`~acordcs.runtime.errors.OperationNotImplementedError`, a fault at run time.
:func:`operations_without_code` lists them before anything runs, for one container of a running
application: the operations of the components hosted there that have no code (:func:`has_code`:
the user's class does not override the generated base's method) and that a caller reaches:

- a crisp rule of a policy set hosted there calls it (the operations the running policy set
  resolved from its rules' actions);
- a polling monitor hosted there polls it (its ``operation`` on its source component);
- a connection of the model joins a required port to a *synchronous* provided port of the
  component: every operation of the component can be called through that port (the model does
  not say which ones a port offers), from wherever the required end runs;
- a ``--run COMPONENT.OPERATION`` of the container's command line calls it.

Asynchronous and stream ports call no operation (they deliver to ``on_<port>`` handlers), nor do
intercepting or subscribing monitors.
"""

from __future__ import annotations

import inspect
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from acordcs.runtime.acquisition import PollingMonitor
from acordcs.runtime.assembly import RunningApplication
from acordcs.runtime.errors import ComponentNotFoundError
from acordcs.runtime.operations import has_code


@dataclass(frozen=True)
class MissingCode:
    """An operation of a component hosted in the container, without code, and what calls it."""

    component: str
    operation: str
    cls: type
    callers: tuple[str, ...]

    def where(self, cwd: Path | None = None) -> str:
        """``file:line`` of the class to edit (the file relative to ``cwd`` when under it)."""
        try:
            file = Path(inspect.getfile(self.cls))
        except TypeError:
            return f"class {self.cls.__qualname__}"
        base = cwd or Path.cwd()
        if file.is_relative_to(base):
            file = file.relative_to(base)
        try:
            line = inspect.getsourcelines(self.cls)[1]
        except (OSError, TypeError):
            return str(file)
        return f"{file}:{line}"

    def message(self, cwd: Path | None = None) -> str:
        """One warning line: where, what, what calls it and what to do."""
        return (
            f"{self.where(cwd)}: warning: {self.component}.{self.operation}() has no code, and "
            f"{'; '.join(self.callers)}: implement {self.operation}() in class "
            f"{self.cls.__name__} (each call raises OperationNotImplementedError until then)"
        )


def operations_without_code(
    app: RunningApplication, container: str, runs: Iterable[tuple[str, str]] = ()
) -> list[MissingCode]:
    """The operations of the components of ``container`` (a container of ``app``) that have no
    code and that something calls (see the module's docstring); ``runs``: the (component,
    operation) pairs the command line calls. Sorted by component and operation."""
    running = app.container(container)
    classes = {ref.name: type(ref.instance) for ref in running.components()}
    callers: dict[tuple[str, str], list[str]] = {}

    def called(component: str, operation: str, by: str) -> None:
        if component in classes:
            callers.setdefault((component, operation), []).append(by)

    for ps in app.descriptor.policy_sets:
        try:
            policy_set = running.policy_set(ps.name)
        except ComponentNotFoundError:
            continue  # hosted in another container: it calls the operations of that one
        for component, operation in sorted(set(policy_set.operations.values())):
            called(component, operation, f"policy set {ps.name} calls it")
    for name in running.monitors():
        monitor = running.monitor(name)
        if isinstance(monitor, PollingMonitor):
            called(monitor.component, monitor.operation, f"monitor {name} polls it")
    components = {c.name: c for c in app.descriptor.components}
    for conn in app.descriptor.connections:
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
    return [
        MissingCode(component, operation, classes[component], tuple(by))
        for (component, operation), by in sorted(callers.items())
        if not has_code(classes[component], operation)
    ]


__all__ = ["MissingCode", "operations_without_code"]
