"""The steps of one container's part of an update (:func:`acordcs.runtime.live.apply_update.apply_part`),
each recording what undoes it: :class:`Part`."""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping, Sequence
from dataclasses import dataclass, field
from functools import partial
from typing import TYPE_CHECKING, Protocol

from acordcs.descriptor.diff import Change, shown
from acordcs.engines.plan import plan_from_descriptor
from acordcs.runtime import events as ev
from acordcs.runtime.assembly import Assembler, Feed, MonitorMaker, RunningApplication
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.remote import RemotePort
from acordcs.runtime.operations import OutParameters

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application
    from acordcs.runtime.container import Container
    from acordcs.runtime.monitor import Monitor


Factories = Mapping[str, type[CtxComponent] | ComponentFactory]


class Classes(Protocol):
    """Where the code of components and monitors comes from during an update."""

    def load(self, changed: Collection[str]) -> tuple[Factories, Mapping[str, MonitorMaker]]:
        """The classes by element name, those of ``changed`` (names of components and monitors
        added or replaced) read afresh."""
        ...

    def keep(self) -> None:
        """The update is done: what :meth:`load` read stays."""
        ...

    def restore(self) -> None:
        """The update was rolled back: the classes as they were before :meth:`load`."""
        ...

    def code(self, names: Collection[str]) -> dict[str, dict[str, str]]:
        """The user's files of the elements ``names`` as they are now (their ``kind``, ``file``
        and ``sha256``; an element without a file of the user's is left out): what a container
        reports it loaded, so that ``acordcs-gen update`` finds the code changed since."""
        ...


@dataclass
class Outcome:
    """What a part did: the plan lines ``applied``, the property defaults ``kept`` (changed at
    run time: each line says the current value), how long the container took (``seconds``), and
    the user's files of the elements whose classes it read afresh (``code``: see
    :meth:`Classes.code`)."""

    applied: list[str] = field(default_factory=list)
    kept: list[str] = field(default_factory=list)
    seconds: float = 0.0
    code: dict[str, dict[str, str]] = field(default_factory=dict)  # the files read afresh


class Part:
    """Container ``name``'s part of the update from ``old`` to ``new`` (``changes``): :meth:`run`
    carries it out in the order of :mod:`acordcs.runtime.live.apply_update`'s docstring, :meth:`undo` takes
    back what was done, newest first."""

    def __init__(
        self,
        running: RunningApplication,
        name: str,
        old: Application,
        new: Application,
        changes: Sequence[Change],
        classes: Classes,
        touched: Callable[[str, str], bool],
        remote: dict[str, str],
        reset: bool,
        remote_timeout: float,
        token: str | None,
    ) -> None:
        self.running, self.name, self.old, self.new = running, name, old, new
        self.container: Container = running.container(name)
        self.changes = [c for c in changes if name in c.containers]
        self.classes, self.touched, self.reset = classes, touched, reset
        self.remote, self.remote_timeout, self.token = remote, remote_timeout, token
        self.undos: list[tuple[str, Callable[[], None]]] = []
        self.current: Change | None = None
        self.outcome = Outcome()
        self.done: set[str] = set()  # plan lines carried out

    # ---------------------------------------------------------------------------- helpers
    def did(self, undo: Callable[[], None]) -> None:
        assert self.current is not None
        self.undos.append((self.current.line, undo))

    def undo(self) -> tuple[list[str], list[str]]:
        rolled: list[str] = []
        unrolled: list[str] = []
        for line, undo in reversed(self.undos):
            try:
                undo()
            except Exception as exc:  # reported: the container keeps what could not be undone
                unrolled.append(f"{line}: {type(exc).__name__}: {exc}")
            else:
                if line not in rolled:
                    rolled.append(line)
        self.undos.clear()
        return rolled, unrolled

    def of(self, kind: str, *actions: str) -> list[Change]:
        return [c for c in self.changes if c.kind == kind and c.action in actions]

    def elements(self, kind: str, *actions: str) -> dict[str, list[Change]]:
        """The elements of ``kind`` with changes of ``actions``, each with its changes."""
        out: dict[str, list[Change]] = {}
        for c in self.of(kind, *actions):
            out.setdefault(c.element, []).append(c)
        return out

    def step(self, changes: list[Change]) -> None:
        """Mark ``changes`` as the one under way (its first line names it in a failure)."""
        self.current = changes[0]
        for c in changes:
            if c.line not in self.done:
                self.done.add(c.line)
                self.outcome.applied.append(c.line)

    def here(self, app: Application, name: str) -> bool:
        place = {r.name: c.name for c in app.containers for r in c.hosts}
        default = app.containers[0].name if app.containers else app.name
        return place.get(name, default) == self.name

    def assembler(
        self, app: Application, factories: Factories, monitors: Mapping[str, MonitorMaker]
    ) -> Assembler:
        asm = Assembler(
            app,
            factories=dict(factories),
            monitors=dict(monitors),
            clock=self.running.clock,
            only=None,
            remote=self.remote,
            remote_timeout=self.remote_timeout,
            context=self.container.context,
            token=self.token,
            containers=self.running.containers,
            java_sources=self.running.java_sources,
        )
        return asm

    # ------------------------------------------------------------------------------- run
    def merged(self, kind: str, *actions: str) -> dict[str, list[Change]]:
        """:meth:`elements`, with the changes of the code of those elements (``code of
        <kind>``, applied as a replacement) after each element's own."""
        out = self.elements(kind, *actions)
        for name, changes in self.elements(f"code of {kind}", "code").items():
            out.setdefault(name, []).extend(changes)
        return out

    def run(self) -> None:
        comps = self.merged("component", "add", "replace")
        mons = self.merged("monitor", "add", "replace")
        fresh = [n for n in {**comps, **mons} if self.here(self.new, n)]
        factories, monitors = self.classes.load(fresh)
        self.outcome.code = self.classes.code(fresh)
        self.asm = self.assembler(self.new, factories, monitors)
        self.asm_old = self.assembler(self.old, {}, {})
        for name, changes in self.elements("policy set", "remove").items():
            self.step(changes)
            self.remove_policy_set(name)
        for name, changes in self.elements("connection", "remove", "reconnect").items():
            self.step(changes)
            self.disconnect(name)
        for name, changes in self.elements("monitor", "remove", "feeds", "replace").items():
            self.step(changes)
            self.unfeed(name)
            if changes[0].action == "remove" and self.here(self.old, name):
                self.remove_monitor(name)
        for name, changes in self.elements("component", "remove").items():
            self.step(changes)
            self.remove_component(name)
        for name, changes in comps.items():
            self.step(changes)
            self.component(name, changes[0].action)
        for name, changes in self.elements("connection", "add", "reconnect").items():
            self.step(changes)
            self.connect(name)
        for name, changes in self.merged("monitor", "add", "replace", "feeds").items():
            self.step(changes)
            if changes[0].action == "add" and self.here(self.new, name):
                self.add_monitor(name)
            elif any(c.action in ("replace", "code") for c in changes):
                self.replace_monitor(name)
            self.feed(name)
        for change in self.of("container", "property"):
            self.step([change])
            self.container_property(change)
        for change in [c for c in self.changes if c.action == "default"]:
            self.step([change])
            self.default(change)
        for name, changes in self.elements("policy set", "add", "replan").items():
            self.step(changes)
            if changes[0].action == "add":
                self.add_policy_set(name)
            else:
                self.replan(name)
        self.current = None
        for change in self.changes:
            if change.line in self.outcome.applied:
                self.container.emit(ev.MODEL_UPDATED, change.element, value=change.line)

    # ------------------------------------------------------------------------- components
    def component(self, name: str, action: str) -> None:
        desc = next(c for c in self.new.components if c.name == name)
        factory = self.asm.factory(desc)
        c = self.container
        if action == "add":
            c.install_factory(factory)
            self.did(lambda: c.remove_factory(factory.type_name))
            self.asm.component(desc, c, factory.type_name)

            def created() -> None:
                self.drop_checks(name)
                c.destroy(name)

            self.did(created)
            return
        old_factory = c.instance(name).factory
        checks = self.drop_checks(name)

        def back() -> None:
            c.remove_factory(factory.type_name)
            c.install_factory(old_factory)
            c.replace(name, old_factory.type_name)
            self.drop_checks(name)
            for check in checks:
                c.add_interceptor(check, component=name)

        c.remove_factory(old_factory.type_name)
        c.install_factory(factory)
        try:
            c.replace(name, factory.type_name)
        except BaseException:
            c.remove_factory(factory.type_name)
            c.install_factory(old_factory)
            for check in checks:
                c.add_interceptor(check, component=name)
            raise
        self.did(back)
        self.asm.port_properties(desc, c.instance(name))
        check = OutParameters(name, desc.operations)
        if check.lengths:
            c.add_interceptor(check, component=name)

    def drop_checks(self, name: str) -> list[OutParameters]:
        """Remove the out-parameter checks of component ``name``; the ones removed."""
        checks = [i for i in self.container.interceptors(name) if isinstance(i, OutParameters)]
        for check in checks:
            self.container.remove_interceptor(check)
        return checks

    def remove_component(self, name: str) -> None:
        c = self.container
        instance = c.instance(name)
        factory, state = instance.factory, instance.save_state()
        desc = next(x for x in self.old.components if x.name == name)
        checks = self.drop_checks(name)
        c.destroy(name)
        c.remove_factory(factory.type_name)

        def back() -> None:
            c.install_factory(factory)
            self.asm_old.port_properties(desc, c.create(factory.type_name, name).instance)
            c.instance(name).restore_state(state)
            for check in checks:
                c.add_interceptor(check, component=name)

        self.did(back)

    # ------------------------------------------------------------------------ connections
    def disconnect(self, name: str) -> None:
        c = self.container
        found = next((x for x in c.connections() if x.name == name), None)
        if found is None:  # the provider side of a request-reply connection declares nothing
            return
        # Local ends by name: the component may be replaced (and back) before this is undone.
        ends = [
            end if isinstance(end, RemotePort) else f"{end.component.name}.{end.name}"  # type: ignore[attr-defined]
            for end in found.ends()
        ]
        connector, qos = found.connector, dict(found.qos)
        c.disconnect(name)

        def back() -> None:
            c.connect(ends[0], ends[1], connector=connector, name=name, qos=qos)

        self.did(back)

    def connect(self, name: str) -> None:
        conn = next(x for x in self.new.connections if x.name == name)
        if self.asm.host_of(conn) != self.name:
            return
        self.asm.connect(conn)
        c = self.container
        if any(x.name == name for x in c.connections()):
            self.did(lambda: c.disconnect(name))

    # --------------------------------------------------------------------------- monitors
    def add_monitor(self, name: str) -> None:
        desc = next(m for m in self.new.monitors if m.name == name)
        c = self.container
        c.add_monitor(self.asm.monitor(desc))
        self.did(lambda: c.remove_monitor(name))

    def remove_monitor(self, name: str) -> None:
        c = self.container
        monitor = c.monitor(name)
        c.remove_monitor(name)
        self.did(lambda: c.add_monitor(monitor))

    def replace_monitor(self, name: str) -> None:
        if not self.here(self.new, name):
            return
        desc = next(m for m in self.new.monitors if m.name == name)
        c = self.container
        old: Monitor = c.monitor(name)
        new = self.asm.monitor(desc)
        for key in new.attributes.keys() & old.attributes.keys():
            new.attributes[key] = old.attributes[key]
        c.remove_monitor(name)
        self.did(lambda: c.add_monitor(old))
        c.add_monitor(new)
        self.did(lambda: c.remove_monitor(name))

    def feeds(self, app: Application, asm: Assembler, name: str) -> list[Feed]:
        """The feeds of monitor ``name`` in ``app`` that involve this container."""
        mon = next((m for m in app.monitors if m.name == name), None)
        if mon is None:
            return []
        out = []
        source = asm.where(name)
        for fed in mon.feeds:
            target = asm.where(fed.name)
            delivery = asm.delivery(source, target)
            if delivery not in (None, "local") and self.name in (source, target):
                out.append(Feed(name, source, fed.name, target, delivery))
        return list({(f.source, f.target): f for f in out}.values())

    def unfeed(self, name: str) -> None:
        """Take down the replicas and relays of monitor ``name`` that the new model does not
        have (its feeds to other containers)."""
        c = self.container
        kept = {(f.source, f.target) for f in self.feeds(self.new, self.asm, name)}
        for feed in self.feeds(self.old, self.asm_old, name):
            if (feed.source, feed.target) in kept:
                continue
            if feed.source == self.name:
                c.unsubscribe(f"feed:{name}->{feed.target}")
                self.did(partial(self.relay_again, feed))
            if feed.target == self.name and feed.source != self.name:
                self.remove_monitor(name)  # the replica here

    def feed(self, name: str) -> None:
        """Set up the replicas and relays of monitor ``name`` that the new model adds."""
        c = self.container
        had = {(f.source, f.target) for f in self.feeds(self.old, self.asm_old, name)}
        for feed in self.feeds(self.new, self.asm, name):
            if (feed.source, feed.target) in had:
                continue
            if feed.target == self.name and feed.source != self.name:
                desc = next(m for m in self.new.monitors if m.name == name)
                self.asm.replica(name, {p.name: p.default for p in desc.properties}, feed)
                self.did(lambda: c.remove_monitor(name))
            if feed.source == self.name:
                self.asm.relay_to(feed, self.replica_of(feed))
                self.did(partial(c.unsubscribe, f"feed:{name}->{feed.target}"))

    def relay_again(self, feed: Feed) -> None:
        self.asm_old.relay_to(feed, self.replica_of(feed))

    def replica_of(self, feed: Feed) -> Monitor | None:
        target = self.running.containers.get(feed.target)
        return target.monitor(feed.monitor) if target is not None else None

    # ------------------------------------------------------------------------- properties
    def container_property(self, change: Change) -> None:
        props = self.container.properties
        attribute = change.attribute
        had, before = attribute in props, props.get(attribute)
        if change.value is None:  # removed
            props.pop(attribute, None)
        else:
            props[attribute] = change.value

        def back() -> None:
            if had:
                props[attribute] = before
            else:
                props.pop(attribute, None)

        self.did(back)

    def default(self, change: Change) -> None:
        c, element, attribute = self.container, change.target, change.attribute
        if not c.has_property(element, attribute):
            return  # a replica's attribute: the readings it gets set it
        current = c.get_property(element, attribute)
        changed = self.touched(element, attribute) or current != change.old
        if changed and not self.reset:
            self.outcome.applied.remove(change.line)
            self.outcome.kept.append(
                f"{change.line}: kept at {shown(current)}, changed at run time "
                "(--reset sets the new default)"
            )
            return
        c.set_property(element, attribute, change.value)
        self.did(lambda: c.set_property(element, attribute, current))

    # ------------------------------------------------------------------------ policy sets
    def remove_policy_set(self, name: str) -> None:
        c = self.container
        policy_set = c.policy_set(name)
        c.remove_policy_set(name)
        self.did(lambda: c.add_policy_set(policy_set))

    def add_policy_set(self, name: str) -> None:
        desc = next(p for p in self.new.policy_sets if p.name == name)
        c = self.container
        c.add_policy_set(self.asm.policy_set(desc, c))
        self.did(lambda: c.remove_policy_set(name))

    def replan(self, name: str) -> None:
        desc = next(p for p in self.new.policy_sets if p.name == name)
        undo = self.container.policy_set(name).replan(
            plan_from_descriptor(desc),
            trigger=desc.trigger,
            frequency=desc.frequency,
            adapts=[a.name for a in desc.adapts],
            fed_by=self.new.fed_by(name),
        )
        self.did(undo)
