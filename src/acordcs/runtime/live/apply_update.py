"""Applying an update to a running container: its part of the plan between two descriptors.

:func:`apply_part` takes the running application, one of its containers, the descriptor it runs
(``old``) and the new one, and carries out the changes of :func:`acordcs.descriptor.diff.diff`
that are that container's (:meth:`~acordcs.descriptor.diff.ModelChanges.part`), each through the runtime's own mechanisms:
components created, destroyed (stopped cleanly) or replaced keeping their state
(:meth:`Container.replace`), connections made and removed, monitors added, removed or replaced
keeping their attributes' values, the replicas and relays of monitors feeding another container,
properties' defaults set where the property was never changed at run time (``touched``; all with
``reset``), policy sets added, removed, or given their new plan (:meth:`PolicySet.replan`: the new
engine replaces the old between two firings).

The part is atomic: each step records what undoes it, and when a step fails, what was done is
undone in reverse order and :class:`UpdateFailed` says what failed and what was rolled back. The
elements are built as :func:`~acordcs.runtime.assembly.assemble` builds them
(:class:`~acordcs.runtime.assembly.Assembler`); their classes come from ``classes``
(:class:`Classes`: the application's package, imported afresh for the elements whose code the
build changed).

Order within a part: what goes first is what the rest needs gone or there (policy sets removed,
then connections, monitors and components removed; components added or replaced, then
connections, monitors, replicas and relays, properties; policy sets added or replanned last, once
every element they read is there). Across containers (:func:`container_order`), a container that
receives (the provided end of a new connection, a replica of a monitor feeding its policy sets)
applies its part before the one that sends.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from acordcs.descriptor.diff import Change
from acordcs.errors import AcordError
from acordcs.runtime.assembly import MonitorMaker, RunningApplication
from acordcs.runtime.errors import RuntimeFailure
from acordcs.runtime.live.update_steps import Classes, Factories, Outcome, Part

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application


@dataclass
class GivenClasses:
    """Classes given as they are (an application assembled in Python: nothing to read afresh)."""

    factories: Factories = field(default_factory=dict)
    monitors: Mapping[str, MonitorMaker] = field(default_factory=dict)

    def load(self, changed: Collection[str]) -> tuple[Factories, Mapping[str, MonitorMaker]]:
        return self.factories, self.monitors

    def keep(self) -> None:
        pass

    def restore(self) -> None:
        pass

    def code(self, names: Collection[str]) -> dict[str, dict[str, str]]:
        return {}  # no file: classes given in Python


class UpdateFailed(RuntimeFailure):
    """A part that failed: ``failed`` the change (its plan line) and why; ``rolled_back`` the
    plan lines undone; ``unrolled`` what could not be undone (with why)."""

    def __init__(
        self,
        message: str,
        *,
        failed: str,
        rolled_back: Sequence[str],
        unrolled: Sequence[str] = (),
        where: str | None = None,
    ) -> None:
        super().__init__(message, where=where, hint="the container runs as before the update")
        self.failed = failed
        self.rolled_back = tuple(rolled_back)
        self.unrolled = tuple(unrolled)


def container_order(
    new: Application, containers: Collection[str], changes: Sequence[Change]
) -> list[str]:
    """``containers`` in the order their parts apply: those with changes first (a failing part
    then stops the update before a container without changes takes the new descriptor); among
    them, one that receives from another through a change (the provided end of a connection,
    the policy sets a monitor feeds) before it, else in the descriptor's order (and so for a
    cycle)."""
    place = {r.name: c.name for c in new.containers for r in c.hosts}
    order = [c.name for c in new.containers if c.name in containers]
    order += sorted(set(containers) - set(order))
    before: dict[str, set[str]] = {c: set() for c in order}  # receiver -> senders after it
    touched = {(c.kind, c.element) for c in changes}
    for conn in new.connections:
        if ("connection", conn.name) in touched:
            sender, receiver = (
                place.get(conn.required.component),
                place.get(conn.provided.component),
            )
            if sender in before and receiver in before and sender != receiver:
                before[receiver].add(sender)  # type: ignore[index]
    for mon in new.monitors:
        if ("monitor", mon.name) in touched:
            sender = place.get(mon.name)
            for fed in mon.feeds:
                receiver = place.get(fed.name)
                if sender in before and receiver in before and sender != receiver:
                    before[receiver].add(sender)  # type: ignore[index]
    out: list[str] = []
    waiting = list(order)
    while waiting:
        # the first container no waiting one must go before (a cycle: the first waiting one)
        ready = [c for c in waiting if not any(c in before[o] for o in waiting if o != c)]
        chosen = ready[0] if ready else waiting[0]
        out.append(chosen)
        waiting.remove(chosen)
    changing = {c for change in changes for c in change.containers}
    return [c for c in out if c in changing] + [c for c in out if c not in changing]


def apply_part(
    running: RunningApplication,
    container: str,
    old: Application,
    new: Application,
    changes: Sequence[Change],
    *,
    classes: Classes,
    touched: Callable[[str, str], bool],
    remote: Mapping[str, str] | None = None,
    reset: bool = False,
    remote_timeout: float = 5.0,
    token: str | None = None,
) -> Outcome:
    """Apply ``changes`` (the part of container ``container``, all live) to ``running``; see the
    module docstring. Raises :class:`UpdateFailed` (everything undone) when a step fails."""
    started = time.perf_counter()
    part = Part(
        running,
        container,
        old,
        new,
        changes,
        classes,
        touched,
        dict(remote or {}),
        reset,
        remote_timeout,
        token,
    )
    try:
        part.run()
    except Exception as exc:
        rolled, unrolled = part.undo()
        classes.restore()
        failed = part.current.line if part.current is not None else "loading the classes"
        why = exc.message if isinstance(exc, AcordError) else f"{type(exc).__name__}: {exc}"
        if isinstance(exc, SyntaxError):  # the user's file: where, and what to do
            why = (
                f"{exc.filename}:{exc.lineno}: {type(exc).__name__}: {exc.msg}: fix the syntax "
                "there, then update again"
            )
        raise UpdateFailed(
            f"{failed}: {why}",
            failed=failed,
            rolled_back=[line for line in rolled if line != failed],
            unrolled=unrolled,
            where=f"container {container!r}",
        ) from exc
    classes.keep()
    running.descriptor = new
    part.outcome.seconds = time.perf_counter() - started
    return part.outcome


__all__ = [
    "Classes",
    "GivenClasses",
    "Outcome",
    "UpdateFailed",
    "apply_part",
    "container_order",
]
