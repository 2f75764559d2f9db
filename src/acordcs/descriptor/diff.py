"""The difference between two application descriptors: the plan of an update.

:func:`diff` compares the descriptor a running application was started from with a new one and
returns a :class:`Plan`: one :class:`Change` per difference that matters to the running
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
- ``property``: a container property added or removed.

What does not (``action`` ``restart``): a container added or removed, a container's host or
endpoint changed, an element moved to another container, the application renamed. Those need
new processes: build, then stop and start the application.

Pure: no toolchain, no runtime (this package is a leaf).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

from acordcs.descriptor.model import (
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
    Variable,
)

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
class Plan:
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


def diff(old: Application, new: Application) -> Plan:
    """The plan taking a running application from ``old`` to ``new`` (see the module docstring)."""
    out = _Differ(old, new)
    out.application()
    out.containers()
    out.components()
    out.connections()
    out.monitors()
    out.policy_sets()
    return Plan(tuple(out.changes))


# ------------------------------------------------------------------------------------ showing
def shown(value: object) -> str:
    """A default as a plan line shows it: numbers as written (``200``, ``0.5``), text quoted."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return f"{value:g}" if value == float(f"{value:g}") else repr(value)
    if isinstance(value, int):
        return str(value)
    if value is None:
        return "(none)"
    return repr(str(value))


def elided(old: str, new: str) -> str:
    """``old -> new`` with the words both start and end with left out (``...``), keeping one
    word of context before the first difference: ``... is slow -> ... is fast``."""
    a, b = old.split(" "), new.split(" ")
    head = 0
    while head < min(len(a), len(b)) and a[head] == b[head]:
        head += 1
    tail = 0
    while tail < min(len(a), len(b)) - head and a[-1 - tail] == b[-1 - tail]:
        tail += 1
    keep = max(head - 1, 0)
    if keep < 2:  # too little in common to be worth leaving out
        keep = 0
    left = "... " if keep else ""
    right = " ..." if tail > 1 else ""
    tail = tail if tail > 1 else 0
    mid_a = " ".join(a[keep : len(a) - tail])
    mid_b = " ".join(b[keep : len(b) - tail])
    return f"{left}{mid_a}{right} -> {left}{mid_b}{right}"


def _names(items: Iterable[object]) -> str:
    listed = [getattr(i, "name", str(i)) for i in items]
    return ", ".join(listed) if listed else "(none)"


def _hz(value: float | None) -> str:
    return "(none)" if value is None else f"{shown(value)} Hz"


def _signature(op: Operation) -> str:
    params = ", ".join(
        (f"{p.direction} " if p.direction != "in" else "") + f"{p.name}: {p.type or '?'}"
        for p in op.parameters
    )
    return f"{op.name}({params})" + (f": {op.return_type}" if op.return_type else "")


def _by_name(items: Iterable[object]) -> dict[str, object]:
    return {getattr(i, "name"): i for i in items}  # noqa: B009 (any named element)


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

    def add(self, sign: str, kind: str, element: str, what: str, containers: Iterable[str],
            action: str, **more: object) -> None:  # fmt: skip
        found = tuple(dict.fromkeys(containers))
        if action == "restart":
            more.setdefault("live", False)
            more.setdefault("why", RESTART)
        self.changes.append(Change(sign, kind, element, what, found, action, **more))  # type: ignore[arg-type]

    def pairs(self, old: Sequence[object], new: Sequence[object]):
        """(name, old or None, new or None): the old ones in their order, then the added ones."""
        before, after = _by_name(old), _by_name(new)
        for name, item in before.items():
            yield name, item, after.get(name)
        for name, item in after.items():
            if name not in before:
                yield name, None, item

    # ------------------------------------------------------------------------ application
    def application(self) -> None:
        if self.old.name != self.new.name:
            everywhere = [c.name for c in self.old.containers] or [self.old.name]
            self.add("~", "application", self.old.name, f"renamed {self.new.name}",
                     everywhere, "restart")  # fmt: skip

    # ------------------------------------------------------------------------- containers
    def containers(self) -> None:
        for name, a, b in self.pairs(self.old.containers, self.new.containers):
            if a is None:
                self.add("+", "container", name, "", [name], "restart")
            elif b is None:
                self.add("-", "container", name, "", [name], "restart")
            else:
                self.container(a, b)  # type: ignore[arg-type]

    def container(self, a: Container, b: Container) -> None:
        if a.host != b.host:
            self.add("~", "container", a.name, f"host {a.host} -> {b.host}", [a.name], "restart")
        if a.endpoint != b.endpoint:
            self.add("~", "container", a.name, "remote endpoint changed", [a.name], "restart")
        for name, p, q in self.pairs(a.properties, b.properties):
            if p is None or q is None or p.kind != q.kind:  # type: ignore[union-attr]
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
                    old=None if p is None else p.default,  # type: ignore[union-attr]
                    value=None if q is None else q.default,  # type: ignore[union-attr]
                )
            else:
                self.default("container", a.name, a.name, p, q, [a.name])  # type: ignore[arg-type]

    def default(self, kind: str, element: str, target: str, p: Property, q: Property,
                containers: Iterable[str], label: str = "property") -> None:  # fmt: skip
        if p.default != q.default or type(p.default) is not type(q.default):
            what = f"{label} {p.name}: default {shown(p.default)} -> {shown(q.default)}"
            self.add("~", kind, element, what, containers, "default", target=target,
                     attribute=p.name, old=p.default, value=q.default)  # fmt: skip

    def moved(self, kind: str, name: str) -> bool:
        """Whether element ``name`` runs in another container now (a change that cannot apply)."""
        was, now = self.where(name, new=False), self.where(name, new=True)
        if was == now:
            return False
        self.add("~", kind, name, f"container {was} -> {now}", [was, now], "restart")
        return True

    # ------------------------------------------------------------------------- components
    def components(self) -> None:
        for name, a, b in self.pairs(self.old.components, self.new.components):
            if a is None:
                here = self.where(name, new=True)
                self.add("+", "component", name, f"in container {here}", [here], "add")
            elif b is None:
                self.add("-", "component", name, "", [self.where(name, new=False)], "remove")
            elif not self.moved("component", name):
                self.component(a, b)  # type: ignore[arg-type]

    def component(self, a: Component, b: Component) -> None:
        here = [self.where(a.name, new=True)]
        replaced: list[str] = []
        if a.language != b.language:
            replaced.append(f"language {a.language} -> {b.language}")
        replaced += self.operations(a.operations, b.operations)
        for name, p, q in self.pairs(a.properties, b.properties):
            if p is None:
                replaced.append(f"property {name} added")
            elif q is None:
                replaced.append(f"property {name} removed")
            elif p.kind != q.kind:  # type: ignore[union-attr]
                replaced.append(f"property {name}: type {p.type} -> {q.type}")  # type: ignore[union-attr]
        for name, p, q in self.pairs(a.ports, b.ports):
            if p is None:
                replaced.append(f"port {name} added")
            elif q is None:
                replaced.append(f"port {name} removed")
            else:
                replaced += self.port(p, q)  # type: ignore[arg-type]
        for what in replaced:
            self.add("~", "component", a.name, what, here, "replace")
        for _, p, q in self.pairs(a.properties, b.properties):
            if p is not None and q is not None and p.kind == q.kind:  # type: ignore[union-attr]
                self.default("component", a.name, a.name, p, q, here)  # type: ignore[arg-type]
        for name, p, q in self.pairs(a.ports, b.ports):
            if p is None or q is None:
                continue
            for _, r, s in self.pairs(p.properties, q.properties):  # type: ignore[union-attr]
                if r is not None and s is not None and r.kind == s.kind:  # type: ignore[union-attr]
                    self.default("component", a.name, f"{a.name}.{name}", r, s, here,  # type: ignore[arg-type]
                                 label=f"port {name}: property")  # fmt: skip

    def operations(self, old: Sequence[Operation], new: Sequence[Operation]) -> list[str]:
        before = [_signature(o) for o in old]
        after = [_signature(o) for o in new]
        return [f"operation {s} removed" for s in before if s not in after] + [
            f"operation {s} added" for s in after if s not in before
        ]

    def port(self, p: Port, q: Port) -> list[str]:
        out = []
        if (p.kind, p.role) != (q.kind, q.role):
            out.append(f"port {p.name}: {p.kind} {p.role} -> {q.kind} {q.role}")
        out += [f"port {p.name}: {w}" for w in self.operations(p.operations, q.operations)]
        for name, r, s in self.pairs(p.properties, q.properties):
            if r is None or s is None or r.kind != s.kind:  # type: ignore[union-attr]
                how = "added" if r is None else "removed" if s is None else "retyped"
                out.append(f"port {p.name}: property {name} {how}")
        return out

    # ------------------------------------------------------------------------ connections
    def ends(self, conn: Connection, *, new: bool) -> list[str]:
        return [self.where(e.component, new=new) for e in (conn.required, conn.provided)]

    def connections(self) -> None:
        for name, a, b in self.pairs(self.old.connections, self.new.connections):
            if a is None:
                what = f"{_end(b.required)} -> {_end(b.provided)} ({b.connector})"  # type: ignore[union-attr]
                self.add("+", "connection", name, what, self.ends(b, new=True), "add")  # type: ignore[arg-type]
            elif b is None:
                self.add("-", "connection", name, "", self.ends(a, new=False), "remove")  # type: ignore[arg-type]
            else:
                self.connection(a, b)  # type: ignore[arg-type]

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
        for name, p, q in self.pairs(a.qos, b.qos):
            if p is None or q is None or p.kind != q.kind:  # type: ignore[union-attr]
                how = "added" if p is None else "removed" if q is None else "retyped"
                redo.append(f"qos {name} {how}")
        for what in redo:
            self.add("~", "connection", a.name, what, where, "reconnect")
        if not redo:
            for _, p, q in self.pairs(a.qos, b.qos):
                self.default("connection", a.name, a.name, p, q, where, label="qos")  # type: ignore[arg-type]

    # --------------------------------------------------------------------------- monitors
    def fed(self, mon: Monitor, *, new: bool) -> list[str]:
        """The monitor's container and those of the policy sets it feeds (replicas there)."""
        return [self.where(mon.name, new=new)] + [self.where(f.name, new=new) for f in mon.feeds]

    def monitors(self) -> None:
        for name, a, b in self.pairs(self.old.monitors, self.new.monitors):
            if a is None:
                here = self.where(name, new=True)
                self.add("+", "monitor", name, f"in container {here}", self.fed(b, new=True), "add")  # type: ignore[arg-type]
            elif b is None:
                self.add("-", "monitor", name, "", self.fed(a, new=False), "remove")  # type: ignore[arg-type]
            elif not self.moved("monitor", name):
                self.monitor(a, b)  # type: ignore[arg-type]

    def monitor(self, a: Monitor, b: Monitor) -> None:
        here = [self.where(a.name, new=True)]
        redo: list[str] = []
        for label, x, y in (
            ("acquisition", a.acquisition, b.acquisition),
            ("frequency", _hz(a.frequency), _hz(b.frequency)),
            ("xpath", a.xpath or "(none)", b.xpath or "(none)"),
            ("operation", a.operation or "(none)", b.operation or "(none)"),
            ("sources", _names(a.sources), _names(b.sources)),
        ):
            if x != y:
                redo.append(f"{label} {x} -> {y}")
        for name, p, q in self.pairs(a.properties, b.properties):
            if p is None or q is None or p.kind != q.kind:  # type: ignore[union-attr]
                how = "added" if p is None else "removed" if q is None else "retyped"
                redo.append(f"attribute {name} {how}")
        for what in redo:
            self.add("~", "monitor", a.name, what, here, "replace")
        feeds = (_names(a.feeds), _names(b.feeds))
        if feeds[0] != feeds[1]:
            where = self.fed(a, new=False) + self.fed(b, new=True)
            self.add("~", "monitor", a.name, f"feeds {feeds[0]} -> {feeds[1]}", where, "feeds")
        for _, p, q in self.pairs(a.properties, b.properties):
            if p is not None and q is not None and p.kind == q.kind:  # type: ignore[union-attr]
                self.default("monitor", a.name, a.name, p, q, here, label="attribute")  # type: ignore[arg-type]

    # ------------------------------------------------------------------------ policy sets
    def policy_sets(self) -> None:
        for name, a, b in self.pairs(self.old.policy_sets, self.new.policy_sets):
            if a is None:
                here = self.where(name, new=True)
                rules = len(b.rules())  # type: ignore[union-attr]
                what = f"in container {here}, {rules} rule{'s' if rules != 1 else ''}"
                self.add("+", "policy set", name, what, [here], "add")
            elif b is None:
                self.add("-", "policy set", name, "", [self.where(name, new=False)], "remove")
            elif not self.moved("policy set", name):
                self.policy_set(a, b)  # type: ignore[arg-type]

    def policy_set(self, a: PolicySet, b: PolicySet) -> None:
        found: list[str] = []
        for label, x, y in (
            ("engine", a.engine, b.engine),
            ("semantics", a.semantics, b.semantics),
            ("trigger", a.trigger, b.trigger),
            ("frequency", _hz(a.frequency), _hz(b.frequency)),
            ("adapts", _names(a.adapts), _names(b.adapts)),
            ("fed by", ", ".join(self.old.fed_by(a.name)) or "(none)",
             ", ".join(self.new.fed_by(b.name)) or "(none)"),
        ):  # fmt: skip
            if x != y:
                found.append(f"{label} {x} -> {y}")
        found += self.rules(a, b)
        found += self.variables(a.variables, b.variables)
        for label, x, y in (
            ("reads", a.inputs, b.inputs),
            ("writes", a.outputs, b.outputs),
            ("fires on", a.triggers, b.triggers),
        ):
            if x != y:
                found.append(f"{label} {', '.join(x) or '(none)'} -> {', '.join(y) or '(none)'}")
        if not found and _bound(a) != _bound(b):
            found.append("what its rules name is bound differently (types, defaults, arities)")
        for what in found:
            self.add("~", "policy set", a.name, what, [self.where(a.name, new=True)], "replan")

    def rules(self, a: PolicySet, b: PolicySet) -> list[str]:
        out = []
        owners: dict[str, set[str]] = {}
        for policy in (*a.policies, *b.policies):
            for r in policy.rules:
                owners.setdefault(r.label, set()).add(policy.name)

        def rule(policy: str, label: str) -> str:
            # a label is unique in its policy; the policy is named when another has it too
            return f"rule {label}" if len(owners[label]) == 1 else f"rule {policy}.{label}"

        for name, p, q in self.pairs(a.policies, b.policies):
            if p is None:
                count = len(q.rules)  # type: ignore[union-attr]
                out.append(f"policy {name} added ({count} rule{'s' if count != 1 else ''})")
                continue
            if q is None:
                out.append(f"policy {name} removed")
                continue
            for label, r, s in self.pairs_by_label(p.rules, q.rules):  # type: ignore[union-attr]
                if r is None:
                    out.append(f"{rule(name, label)} added: {s.text}")
                elif s is None:
                    out.append(f"{rule(name, label)} removed")
                else:
                    if r.text != s.text:
                        out.append(f"{rule(name, label)}: {elided(r.text, s.text)}")
                    if r.priority != s.priority:
                        out.append(f"{rule(name, label)}: priority {r.priority} -> {s.priority}")
        return out

    @staticmethod
    def pairs_by_label(old, new):
        before = {r.label: r for r in old}
        after = {r.label: r for r in new}
        for label, r in before.items():
            yield label, r, after.get(label)
        for label, s in after.items():
            if label not in before:
                yield label, None, s

    def variables(self, old: Sequence[Variable], new: Sequence[Variable]) -> list[str]:
        out = []
        before = {v.name: v for v in old}
        after = {v.name: v for v in new}
        for name, v in before.items():
            w = after.get(name)
            if w is None:
                out.append(f"variable {name} removed")
                continue
            if (v.minimum, v.maximum) != (w.minimum, w.maximum):
                out.append(
                    f"variable {name}: range {shown(v.minimum)}..{shown(v.maximum)} -> "
                    f"{shown(w.minimum)}..{shown(w.maximum)}"
                )
            terms_before = {t.name: t for t in v.terms}
            terms_after = {t.name: t for t in w.terms}
            for term, t in terms_before.items():
                u = terms_after.get(term)
                if u is None:
                    out.append(f"variable {name}: term {term} removed")
                elif t.fcl != u.fcl:
                    out.append(f"variable {name}: term {term}: {t.fcl} -> {u.fcl}")
            for term, u in terms_after.items():
                if term not in terms_before:
                    out.append(f"variable {name}: term {term} added: {u.fcl}")
        for name, w in after.items():
            if name not in before:
                out.append(f"variable {name} added: {w.terms_text}")
        return out


def _bound(ps: PolicySet) -> list[tuple[object, ...]]:
    """What the set's rules name, as bound, without the ids (which say nothing that runs)."""
    return [
        (b.kind, b.element, b.member, b.names, b.value_kind, b.type, b.default, b.arity)
        for b in ps.bound
    ]


def _end(end) -> str:
    return f"{end.component}.{end.port}"


__all__ = ["RESTART", "Change", "Plan", "diff", "elided", "shown"]
