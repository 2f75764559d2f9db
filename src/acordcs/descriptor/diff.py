"""The difference between two application descriptors: the plan of an update.

:func:`diff` compares the descriptor a running application was started from with a new one and
returns :class:`ModelChanges`, the plan of an update: one :class:`Change` per difference that matters to the running
application, each with its plan line (``+`` added, ``-`` removed, ``~`` changed, the element and
what changes), the containers whose part it is, how it applies (:attr:`Change.action`) and
whether it can apply live (:attr:`Change.live`, and :attr:`Change.why` when not).

Elements are matched by name (names are unique in a model, and they are what the runtime knows
elements by): a renamed element is one removed and one added. Ids, qualified names and
documentation are not compared: they change nothing that runs.

What applies live, and how (``action``):

- ``add``, ``remove``: a component, connection, monitor or policy set;
- ``replace``: a component whose class changes (operations, properties added or removed, ports),
  replaced keeping its state; a monitor whose acquisition changes (frequency, xpath, sources,
  operation, attributes added or removed), replaced keeping its attributes' values;
- ``reconnect``: a connection whose connector, ends or QoS attributes change;
- ``replan``: a policy set whose rules, terms, variables, trigger, frequency, engine, semantics,
  adapted elements or feeding monitors change: its engine rebuilt from the new plan;
- ``default``: a property's default (component, port, connection QoS, monitor attribute,
  container property): applied to a property never changed at run time;
- ``property``: a container property added or removed;
- ``code``: the user's code of a component or monitor changed while the model did not
  (``~ code of component Ventilation``: :func:`code_change`, found by ``acordcs-gen update``
  from the digests of the files a container loaded): replaced by its class read afresh, as
  ``replace``, keeping its state.

What does not (``action`` ``restart``): a container added or removed, a container's host or
endpoint changed, an element moved to another container, a component's ``persistent`` tag
changed (its container sets up its store as it starts), the application renamed. Those need
new processes: build, then stop and start the application.

Pure: no toolchain, no runtime (this package is a leaf).
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Sequence
from dataclasses import dataclass
from typing import Protocol, TypeVar

from acordcs.descriptor.application import (
    Application,
    Component,
    Connection,
    Container,
    Monitor,
    Operation,
    PolicySet,
    Port,
    Property,
    Value,
)
from acordcs.descriptor.formatting import elided, hz, names, shown, signature
from acordcs.descriptor.policy_diff import policy_set_changes

RESTART = (
    "build, then stop and start the application (bin/stop-all, bin/start-all): a running "
    "process cannot take it"
)


@dataclass(frozen=True, slots=True)
class Change:
    """One difference. ``kind`` and ``element`` name what changes (``component Locomotion``);
    ``what`` says how (empty for an element added or removed as a whole). ``target`` and
    ``attribute`` name the runtime property a ``default`` or ``property`` change sets (the
    element as the container knows it: a component, ``Component.Port``, a connection, a monitor,
    the container), with ``old`` and ``value`` its defaults."""

    sign: str
    kind: str
    element: str
    what: str
    containers: tuple[str, ...]
    action: str
    live: bool = True
    why: str = ""
    target: str = ""
    attribute: str = ""
    old: Value | None = None
    value: Value | None = None

    @property
    def line(self) -> str:
        """The plan line: ``~ policy set SpeedLimiting: rule smallNarrow: ... -> ...``."""
        head = f"{self.sign} {self.kind} {self.element}"
        return f"{head}: {self.what}" if self.what else head


@dataclass(frozen=True, slots=True)
class ModelChanges:
    """The changes from ``old`` to ``new``, in a stable order (kinds in the order containers,
    components, connections, monitors, policy sets; elements in descriptor order)."""

    changes: tuple[Change, ...] = ()

    @property
    def live(self) -> bool:
        """Whether every change applies to the running application."""
        return all(c.live for c in self.changes)

    @property
    def lines(self) -> tuple[str, ...]:
        return tuple(c.line for c in self.changes)

    def part(self, container: str) -> tuple[Change, ...]:
        """The changes container ``container`` applies."""
        return tuple(c for c in self.changes if container in c.containers)

    def __bool__(self) -> bool:
        return bool(self.changes)


def code_change(kind: str, element: str, container: str) -> Change:
    """The change of the code of ``element`` (``kind`` ``component`` or ``monitor``), in the
    user's file, that container ``container`` runs: ``~ code of component Ventilation``."""
    return Change("~", f"code of {kind}", element, "", (container,), "code")


def diff(old: Application, new: Application) -> ModelChanges:
    """The plan taking a running application from ``old`` to ``new`` (see the module docstring)."""
    out = _Differ(old, new)
    out.application()
    out.containers()
    out.components()
    out.connections()
    out.monitors()
    out.policy_sets()
    return ModelChanges(tuple(out.changes))


class _Named(Protocol):
    @property
    def name(self) -> str: ...


N = TypeVar("N", bound=_Named)


def pairs(old: Sequence[N], new: Sequence[N]) -> Iterator[tuple[str, N | None, N | None]]:
    """(name, old or None, new or None) of the elements of ``old`` and ``new``, matched by
    name: the old ones in their order, then the added ones."""
    before = {i.name: i for i in old}
    after = {i.name: i for i in new}
    for name, item in before.items():
        yield name, item, after.get(name)
    for name, item in after.items():
        if name not in before:
            yield name, None, item


# ------------------------------------------------------------------------------------ the diff
class _Differ:
    def __init__(self, old: Application, new: Application) -> None:
        self.old, self.new = old, new
        self.changes: list[Change] = []
        self.old_place = {r.name: c.name for c in old.containers for r in c.hosts}
        self.new_place = {r.name: c.name for c in new.containers for r in c.hosts}
        self.old_default = old.containers[0].name if old.containers else old.name
        self.new_default = new.containers[0].name if new.containers else new.name

    def where(self, name: str, *, new: bool) -> str:
        if new:
            return self.new_place.get(name, self.new_default)
        return self.old_place.get(name, self.old_default)

    def add(
        self,
        sign: str,
        kind: str,
        element: str,
        what: str,
        containers: Iterable[str],
        action: str,
        *,
        target: str = "",
        attribute: str = "",
        old: Value | None = None,
        value: Value | None = None,
    ) -> None:
        restart = action == "restart"
        self.changes.append(
            Change(
                sign,
                kind,
                element,
                what,
                tuple(dict.fromkeys(containers)),
                action,
                live=not restart,
                why=RESTART if restart else "",
                target=target,
                attribute=attribute,
                old=old,
                value=value,
            )
        )

    # ------------------------------------------------------------------------ application
    def application(self) -> None:
        if self.old.name != self.new.name:
            everywhere = [c.name for c in self.old.containers] or [self.old.name]
            self.add(
                "~", "application", self.old.name, f"renamed {self.new.name}", everywhere, "restart"
            )

    # ------------------------------------------------------------------------- containers
    def containers(self) -> None:
        for name, a, b in pairs(self.old.containers, self.new.containers):
            if a is None:
                self.add("+", "container", name, "", [name], "restart")
            elif b is None:
                self.add("-", "container", name, "", [name], "restart")
            else:
                self.container(a, b)

    def container(self, a: Container, b: Container) -> None:
        if a.host != b.host:
            self.add("~", "container", a.name, f"host {a.host} -> {b.host}", [a.name], "restart")
        if a.endpoint != b.endpoint:
            self.add("~", "container", a.name, "remote endpoint changed", [a.name], "restart")
        for name, p, q in pairs(a.properties, b.properties):
            if p is not None and q is not None and p.kind == q.kind:
                self.default("container", a.name, a.name, p, q, [a.name])
                continue
            how = "added" if p is None else "removed" if q is None else "retyped"
            self.add(
                "~",
                "container",
                a.name,
                f"property {name} {how}",
                [a.name],
                "property",
                target=a.name,
                attribute=name,
                old=p.default if p is not None else None,
                value=q.default if q is not None else None,
            )

    def default(
        self,
        kind: str,
        element: str,
        target: str,
        p: Property,
        q: Property,
        containers: Iterable[str],
        label: str = "property",
    ) -> None:
        if p.default != q.default or type(p.default) is not type(q.default):
            what = f"{label} {p.name}: default {shown(p.default)} -> {shown(q.default)}"
            self.add(
                "~",
                kind,
                element,
                what,
                containers,
                "default",
                target=target,
                attribute=p.name,
                old=p.default,
                value=q.default,
            )

    def moved(self, kind: str, name: str) -> bool:
        """Whether element ``name`` runs in another container now (a change that cannot apply)."""
        was, now = self.where(name, new=False), self.where(name, new=True)
        if was == now:
            return False
        self.add("~", kind, name, f"container {was} -> {now}", [was, now], "restart")
        return True

    # ------------------------------------------------------------------------- components
    def components(self) -> None:
        for name, a, b in pairs(self.old.components, self.new.components):
            if a is None:
                here = self.where(name, new=True)
                self.add("+", "component", name, f"in container {here}", [here], "add")
            elif b is None:
                self.add("-", "component", name, "", [self.where(name, new=False)], "remove")
            elif not self.moved("component", name):
                self.component(a, b)

    def component(self, a: Component, b: Component) -> None:
        here = [self.where(a.name, new=True)]
        replaced: list[str] = []
        if a.language != b.language:
            replaced.append(f"language {a.language} -> {b.language}")
        replaced += self.operations(a.operations, b.operations)
        if a.persistent != b.persistent:  # its store is set up as its container starts
            what = f"persistent {str(a.persistent).lower()} -> {str(b.persistent).lower()}"
            self.add("~", "component", a.name, what, here, "restart")
        for name, p, q in pairs(a.properties, b.properties):
            if p is None:
                replaced.append(f"property {name} added")
            elif q is None:
                replaced.append(f"property {name} removed")
            elif p.kind != q.kind:
                replaced.append(f"property {name}: type {p.type} -> {q.type}")
        for name, r, s in pairs(a.ports, b.ports):
            if r is None:
                replaced.append(f"port {name} added")
            elif s is None:
                replaced.append(f"port {name} removed")
            else:
                replaced += self.port(r, s)
        for what in replaced:
            self.add("~", "component", a.name, what, here, "replace")
        for _, p, q in pairs(a.properties, b.properties):
            if p is not None and q is not None and p.kind == q.kind:
                self.default("component", a.name, a.name, p, q, here)
        for name, r, s in pairs(a.ports, b.ports):
            if r is None or s is None:
                continue
            for _, p, q in pairs(r.properties, s.properties):
                if p is not None and q is not None and p.kind == q.kind:
                    label = f"port {name}: property"
                    self.default("component", a.name, f"{a.name}.{name}", p, q, here, label)

    def operations(self, old: Sequence[Operation], new: Sequence[Operation]) -> list[str]:
        """What differs between two lists of operations: one operation in each of the same name,
        or else of the same model id (renamed), whose signature changed is one change,
        ``operation watch(seconds: int) -> watch()``; the others are removed or added."""
        pairs = _matched(old, new, lambda o: o.name)
        rest_old = [o for o in old if all(o is not a for a, _ in pairs)]
        rest_new = [o for o in new if all(o is not b for _, b in pairs)]
        pairs += _matched(rest_old, rest_new, lambda o: o.id)
        paired = {id(o) for pair in pairs for o in pair}
        before = [signature(o) for o in old]
        after = [signature(o) for o in new]
        changed = [
            f"operation {signature(a)} -> {signature(b)}"
            for a, b in sorted(pairs, key=lambda p: old.index(p[0]))
            if signature(a) != signature(b)
        ]
        gone = [signature(o) for o in old if id(o) not in paired]
        came = [signature(o) for o in new if id(o) not in paired]
        return (
            changed
            + [f"operation {s} removed" for s in gone if s not in after]
            + [f"operation {s} added" for s in came if s not in before]
        )

    def port(self, r: Port, s: Port) -> list[str]:
        out = []
        if (r.kind, r.role) != (s.kind, s.role):
            out.append(f"port {r.name}: {r.kind} {r.role} -> {s.kind} {s.role}")
        out += [f"port {r.name}: {w}" for w in self.operations(r.operations, s.operations)]
        for name, p, q in pairs(r.properties, s.properties):
            if p is None or q is None or p.kind != q.kind:
                how = "added" if p is None else "removed" if q is None else "retyped"
                out.append(f"port {r.name}: property {name} {how}")
        return out

    # ------------------------------------------------------------------------ connections
    def ends(self, conn: Connection, *, new: bool) -> list[str]:
        return [self.where(e.component, new=new) for e in (conn.required, conn.provided)]

    def connections(self) -> None:
        for name, a, b in pairs(self.old.connections, self.new.connections):
            if a is None and b is not None:
                what = f"{_end(b.required)} -> {_end(b.provided)} ({b.connector})"
                self.add("+", "connection", name, what, self.ends(b, new=True), "add")
            elif b is None and a is not None:
                self.add("-", "connection", name, "", self.ends(a, new=False), "remove")
            elif a is not None and b is not None:
                self.connection(a, b)

    def connection(self, a: Connection, b: Connection) -> None:
        where = self.ends(a, new=False) + self.ends(b, new=True)
        redo: list[str] = []
        if a.connector != b.connector:
            redo.append(f"connector {a.connector} -> {b.connector}")
        if (a.required, a.provided) != (b.required, b.provided):
            redo.append(
                f"{_end(a.required)} -> {_end(a.provided)} becomes "
                f"{_end(b.required)} -> {_end(b.provided)}"
            )
        for name, p, q in pairs(a.qos, b.qos):
            if p is None or q is None or p.kind != q.kind:
                how = "added" if p is None else "removed" if q is None else "retyped"
                redo.append(f"qos {name} {how}")
        for what in redo:
            self.add("~", "connection", a.name, what, where, "reconnect")
        if not redo:
            for _, p, q in pairs(a.qos, b.qos):
                if p is not None and q is not None:
                    self.default("connection", a.name, a.name, p, q, where, label="qos")

    # --------------------------------------------------------------------------- monitors
    def fed(self, mon: Monitor, *, new: bool) -> list[str]:
        """The monitor's container and those of the policy sets it feeds (replicas there)."""
        return [self.where(mon.name, new=new)] + [self.where(f.name, new=new) for f in mon.feeds]

    def monitors(self) -> None:
        for name, a, b in pairs(self.old.monitors, self.new.monitors):
            if a is None and b is not None:
                here = self.where(name, new=True)
                self.add("+", "monitor", name, f"in container {here}", self.fed(b, new=True), "add")
            elif b is None and a is not None:
                self.add("-", "monitor", name, "", self.fed(a, new=False), "remove")
            elif a is not None and b is not None and not self.moved("monitor", name):
                self.monitor(a, b)

    def monitor(self, a: Monitor, b: Monitor) -> None:
        here = [self.where(a.name, new=True)]
        redo: list[str] = []
        for label, x, y in (
            ("acquisition", a.acquisition, b.acquisition),
            ("frequency", hz(a.frequency), hz(b.frequency)),
            ("xpath", a.xpath or "(none)", b.xpath or "(none)"),
            ("operation", a.operation or "(none)", b.operation or "(none)"),
            ("sources", names(a.sources), names(b.sources)),
        ):
            if x != y:
                redo.append(f"{label} {x} -> {y}")
        for name, p, q in pairs(a.properties, b.properties):
            if p is None or q is None or p.kind != q.kind:
                how = "added" if p is None else "removed" if q is None else "retyped"
                redo.append(f"attribute {name} {how}")
        for what in redo:
            self.add("~", "monitor", a.name, what, here, "replace")
        feeds = (names(a.feeds), names(b.feeds))
        if feeds[0] != feeds[1]:
            where = self.fed(a, new=False) + self.fed(b, new=True)
            self.add("~", "monitor", a.name, f"feeds {feeds[0]} -> {feeds[1]}", where, "feeds")
        for _, p, q in pairs(a.properties, b.properties):
            if p is not None and q is not None and p.kind == q.kind:
                self.default("monitor", a.name, a.name, p, q, here, label="attribute")

    # ------------------------------------------------------------------------ policy sets
    def policy_sets(self) -> None:
        for name, a, b in pairs(self.old.policy_sets, self.new.policy_sets):
            if a is None and b is not None:
                here = self.where(name, new=True)
                count = len(b.rules())
                what = f"in container {here}, {count} rule{'s' if count != 1 else ''}"
                self.add("+", "policy set", name, what, [here], "add")
            elif b is None:
                self.add("-", "policy set", name, "", [self.where(name, new=False)], "remove")
            elif a is not None and not self.moved("policy set", name):
                self.policy_set(a, b)

    def policy_set(self, a: PolicySet, b: PolicySet) -> None:
        fed = (self.old.fed_by(a.name), self.new.fed_by(b.name))
        for what in policy_set_changes(a, b, fed):
            self.add("~", "policy set", a.name, what, [self.where(a.name, new=True)], "replan")


def _matched(
    old: Sequence[Operation], new: Sequence[Operation], key: Callable[[Operation], str]
) -> list[tuple[Operation, Operation]]:
    """The (old, new) operations whose ``key`` (a name, an id) is that of exactly one in each
    (an empty key matches nothing)."""
    a: dict[str, list[Operation]] = {}
    b: dict[str, list[Operation]] = {}
    for o in old:
        a.setdefault(key(o), []).append(o)
    for o in new:
        b.setdefault(key(o), []).append(o)
    return [(a[k][0], b[k][0]) for k in a if k and k in b and len(a[k]) == 1 and len(b[k]) == 1]


def _end(end) -> str:
    return f"{end.component}.{end.port}"


__all__ = [
    "RESTART",
    "Change",
    "ModelChanges",
    "code_change",
    "diff",
    "elided",
    "pairs",
    "shown",
]
