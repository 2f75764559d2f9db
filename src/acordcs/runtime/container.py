"""The context-aware container (paper, Figure 2): hosts component factories, components, monitors and
policy sets; intercepts operation calls; turns every state change into an event.

Everything that changes state goes through this API (user code, policy actions, monitors, remote
calls), so interceptors and monitors see it all. Faults of hosted code (a raising action, monitor,
interceptor, listener or component) are isolated: recorded in :attr:`Container.faults` with context,
counted, and the container goes on. Bad calls by the user (unknown names, wrong kinds) raise a
:class:`~acordcs.runtime.errors.RuntimeFailure` that says what to do.

The parts: operation calls and interceptors (:mod:`.calls`) and the element namespace and
connections (:mod:`.wiring`) are mixed in; events go through an :class:`~.dispatch.EventDispatcher`.
Components, ports, monitors, policy sets and the remote endpoint know their container only through
the Protocol each declares (``ComponentHost``, ``PortHost``, ``MonitorHost``, ``PolicyHost``,
``ServedContainer``), so none of them imports this module.

Removing a factory while instances of its type live (stated behaviour): no new instance of that type
can be created; the live ones keep running, stay findable and callable, can be replaced, and when
destroyed their (removed) factory's destroy hook still runs. ``remove_factory(t,
destroy_instances=True)`` destroys them at once instead.
"""

from __future__ import annotations

import itertools
import logging
import threading
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING, Any

from acordcs.diagnostics import article
from acordcs.runtime import events as ev
from acordcs.runtime.calls import OperationCalls
from acordcs.runtime.clock import Clock, RealClock, Timer, VirtualClock
from acordcs.runtime.component import (
    ComponentFactory,
    ComponentRef,
    CtxComponent,
    Hosted,
    attach_component,
)
from acordcs.runtime.dispatch import EventDispatcher, Handler
from acordcs.runtime.errors import (
    ComponentDestroyedError,
    ComponentError,
    ComponentNotFoundError,
    ConfigurationError,
    FactoryError,
    PortError,
)
from acordcs.runtime.events import Event, FaultLog
from acordcs.runtime.monitor import PortTap
from acordcs.runtime.wiring import Wiring

if TYPE_CHECKING:
    from acordcs.runtime.context.core import ProviderCore
    from acordcs.runtime.monitor import Monitor
    from acordcs.runtime.policy import PolicySet


class Container(OperationCalls, Wiring):
    """A container. ``clock`` defaults to a :class:`RealClock` the container owns (and closes)."""

    def __init__(
        self,
        name: str,
        *,
        clock: Clock | None = None,
        max_cascade_depth: int = 32,
        max_cascade_events: int = 10_000,
        properties: dict[str, object] | None = None,
        logger: logging.Logger | None = None,
        context: ProviderCore | None = None,
    ) -> None:
        self.name = name
        self._owns_clock = clock is None
        self.clock: Clock = clock if clock is not None else RealClock()
        # The context provider its components publish to and its monitors subscribe to: given
        # (shared by the containers of one application), else its own, made on first use.
        self._context = context
        self._owns_context = context is None
        self.log = logger or logging.getLogger(f"acordcs.runtime.{name}")
        self.faults = FaultLog(name, self.log)
        self.stats: Counter[str] = Counter()
        self.properties: dict[str, object] = dict(properties or {})
        self.clock.on_error = self._timer_fault
        self._events = EventDispatcher(
            self.stats,
            self.faults,
            self.clock,
            max_depth=max_cascade_depth,
            max_events=max_cascade_events,
        )
        self._lock = threading.RLock()
        self._lineages = itertools.count(1)
        self._factories: dict[str, ComponentFactory] = {}
        self._components: dict[str, Hosted] = {}
        self._destroyed: dict[int, float] = {}
        self._monitors: dict[str, Monitor] = {}
        self._taps: dict[str, list[PortTap]] = {}  # monitor name -> interceptors on its ports
        self._policy_sets: dict[str, PolicySet] = {}
        self._where = f"container {name!r}"
        OperationCalls.__init__(self)
        Wiring.__init__(self)

    def __repr__(self) -> str:
        return f"<Container {self.name}: {len(self._components)} components>"

    # -------------------------------------------------------------------------------- faults
    @contextmanager
    def guard(self, kind: str, where: str, **context: object) -> Iterator[None]:
        """Run hosted code; an exception becomes a recorded fault and the caller goes on."""
        try:
            yield
        except Exception as exc:
            self.faults.record(kind, where, exc, self.clock.now(), **context)

    def _timer_fault(self, timer: Timer, exc: BaseException) -> None:
        self.faults.record("timer", repr(timer.fn), exc, self.clock.now())

    # ------------------------------------------------------------------------------ context
    @property
    def context(self) -> ProviderCore:
        """The context provider (its own embedded one unless one was given; inline, hence
        deterministic, on a virtual clock)."""
        with self._lock:
            if self._context is None:
                from acordcs.runtime.context.embedded import ContextProvider  # needs lxml

                self._context = ContextProvider(inline=isinstance(self.clock, VirtualClock))
            return self._context

    def publish_context(self, publisher: str, document: object) -> int:
        """Publish ``document`` as ``publisher``'s latest context (see ``ContextProvider.publish``)."""
        return self.context.publish(publisher, document)  # type: ignore[attr-defined]

    # ------------------------------------------------------------------------------- events
    def subscribe(
        self,
        kind: str,
        handler: Handler,
        *,
        name: str,
        element: str | None = None,
        attribute: str | None = None,
    ) -> None:
        """Listen to events of ``kind`` (one of ``events.EVENT_KINDS``, or ``*``)."""
        if kind != "*" and kind not in ev.EVENT_KINDS:
            raise ConfigurationError(
                f"unknown event kind {kind!r}; one of {sorted(ev.EVENT_KINDS)} or '*'"
            )
        self._events.subscribe(kind, handler, name=name, element=element, attribute=attribute)

    def unsubscribe(self, name: str) -> None:
        self._events.unsubscribe(name)

    def emit(self, kind: str, element: str, attribute: str | None = None, **fields: Any) -> None:
        if not self._events.wants(kind):
            # Nobody could observe it: count it, skip building and queueing it.
            self.stats["events"] += 1
            return
        data = fields.pop("data", None) or {}
        event = Event(kind, element, attribute, time=self.clock.now(), data=data, **fields)
        self._events.emit(event)

    @property
    def origin(self) -> str | None:
        """What events emitted now are attributed to; a policy set's firing sets and restores it
        itself (the adaptation hot path)."""
        return self._events.origin

    @origin.setter
    def origin(self, origin: str | None) -> None:
        self._events.origin = origin

    # ---------------------------------------------------------------------------- factories
    def install_factory(self, factory: ComponentFactory) -> None:
        with self._lock:
            if factory.type_name in self._factories:
                raise FactoryError(
                    f"a factory for type {factory.type_name!r} is already installed",
                    where=self._where,
                    hint="remove_factory() it first to install a new version",
                )
            self._factories[factory.type_name] = factory
        self.emit(ev.FACTORY_CHANGED, factory.type_name, value="installed")

    def remove_factory(self, type_name: str, *, destroy_instances: bool = False) -> None:
        """Remove a factory; see the module docstring for what happens to live instances."""
        with self._lock:
            factory = self._factory(type_name)
            if destroy_instances:
                for name in list(factory.instances):
                    self.destroy(name)
            del self._factories[type_name]
        self.emit(ev.FACTORY_CHANGED, type_name, value="removed")

    def factories(self) -> list[str]:
        return sorted(self._factories)

    def _factory(self, type_name: str) -> ComponentFactory:
        try:
            return self._factories[type_name]
        except KeyError:
            raise FactoryError(
                f"no factory for component type {type_name!r} "
                f"(installed: {', '.join(sorted(self._factories)) or 'none'})",
                where=self._where,
                hint="install_factory(ComponentFactory(type_name, cls)) first",
            ) from None

    # --------------------------------------------------------------------------- components
    def create(
        self,
        type_name: str,
        name: str,
        *,
        properties: dict[str, object] | None = None,
        state: dict[str, Any] | None = None,
        **config: Any,
    ) -> ComponentRef:
        """Create a component of an installed type; ``config`` goes to the factory. ``state``: a
        state it takes (:meth:`CtxComponent.restore_state`) before its ``on_start``, as one kept
        across a restart (:mod:`.persistence`)."""
        with self._lock:
            factory = self._factory(type_name)
            if name in self._components:
                raise FactoryError(
                    f"a component named {name!r} already exists",
                    where=self._where,
                    hint="destroy it, replace it, or pick another name",
                )
            instance = self._build(factory, name, properties, config)
            if state is not None:
                with self.guard("component", name, phase="restore_state"):
                    instance.restore_state(state)
            hosted = Hosted(instance, next(self._lineages), instance.operation_names())
            self._components[name] = hosted
            factory.adopt(instance)
            self._start(instance)
        self.emit(ev.COMPONENT_CREATED, name, value=type_name)
        return ComponentRef(self, name, hosted.lineage)

    def _build(
        self,
        factory: ComponentFactory,
        name: str,
        properties: dict[str, object] | None,
        config: dict[str, Any],
    ) -> CtxComponent:
        try:
            instance = factory.create(**config)
        except FactoryError:
            raise
        except Exception as exc:
            self.faults.record("component", name, exc, self.clock.now(), phase="create")
            raise ComponentError(
                f"factory {factory.type_name!r} failed to create {name!r}: {type(exc).__name__}: {exc}",
                where=self._where,
                hint="check the configuration passed to create()",
            ) from exc
        attach_component(instance, name, self, factory)
        for key, value in (properties or {}).items():
            if key not in instance.props:
                raise self._no_attribute(name, key, instance.props)
            instance.props[key] = value
        return instance

    def _start(self, instance: CtxComponent) -> None:
        with self.guard("component", instance.name, phase="on_start"):
            instance.on_start()
        for port in instance.port_map.values():
            port.restart_stream()

    def _stop(self, instance: CtxComponent) -> None:
        for port in instance.port_map.values():
            port.stop()
        with self.guard("component", instance.name, phase="on_stop"):
            instance.on_stop()

    def destroy(self, name: str) -> None:
        with self._lock:
            hosted = self._hosted(name)
            instance = hosted.instance
            self._stop(instance)
            self._drop_connections_of(instance)
            instance.alive = False
            del self._components[name]
            self._destroyed[hosted.lineage] = self.clock.now()
            with self.guard("component", name, phase="factory destroy"):
                instance.factory.destroy(instance)
        self.emit(ev.COMPONENT_DESTROYED, name, value=instance.factory.type_name)

    def replace(
        self, name: str, type_name: str, *, drain_timeout: float = 5.0, **config: Any
    ) -> ComponentRef:
        """Replace a component by a new one of ``type_name``, keeping its name, state and connections.

        The new type must have every port the old one has connected (same name and kind). Handles on
        the old component follow the new one. Calls running in the component are waited for (up
        to ``drain_timeout`` seconds; still running then: ComponentError, nothing replaced), so
        their writes reach the new instance; calls arriving meanwhile wait and run on the new one.
        """
        hosted = self._hosted(name)
        running = hosted.gate.hold(drain_timeout)
        try:
            if running:
                raise ComponentError(
                    f"cannot replace {name!r}: {running} call(s) still running in it after "
                    f"{drain_timeout:g} s",
                    where=self._where,
                    hint="replace it when its operations have returned, or raise drain_timeout",
                )
            return self._replace_drained(name, type_name, config)
        finally:
            hosted.gate.release()

    def _replace_drained(self, name: str, type_name: str, config: dict[str, Any]) -> ComponentRef:
        with self._lock:
            hosted = self._hosted(name)
            old = hosted.instance
            factory = self._factory(type_name)
            specs = {s.name: s for s in factory.cls.ports}
            for port in old.port_map.values():
                if port.connections and (
                    port.name not in specs or specs[port.name].kind != port.kind
                ):
                    raise PortError(
                        f"cannot replace {name!r} by a {type_name!r}: connected port "
                        f"{port.name!r} ({port.kind}) has no counterpart",
                        where=self._where,
                        hint=f"give {factory.cls.__name__} {article(port.kind)} {port.kind} port named {port.name!r}",
                    )
            state = old.save_state()
            new = self._build(factory, name, None, config)
            new.restore_state(state)
            self._stop(old)
            for port in old.port_map.values():
                successor = new.port_map.get(port.name)
                if successor is None:  # unconnected (checked above): it goes with the old type
                    continue
                for conn in port.connections:
                    conn.replace_end(port, successor)
                successor.connections = port.connections
                successor.properties.update(port.properties)
                port.connections = []
            old.alive = False
            with self.guard("component", name, phase="factory destroy"):
                old.factory.destroy(old)
            hosted.instance = new
            hosted.operations = new.operation_names()
            factory.adopt(new)
            self._start(new)
        self.emit(ev.COMPONENT_REPLACED, name, value=type_name, old=old.factory.type_name)
        return ComponentRef(self, name, hosted.lineage)

    def find(self, name: str) -> ComponentRef:
        hosted = self._hosted(name)
        return ComponentRef(self, name, hosted.lineage)

    def instance(self, name: str, lineage: int | None = None) -> CtxComponent:
        """The live instance named ``name`` (of ``lineage``, a handle's: raises
        ComponentDestroyedError once that one is gone); calls on it bypass interceptors."""
        return self._hosted(name, lineage).instance

    def operations_of(self, name: str) -> frozenset[str]:
        """The operations of component ``name`` (none when there is no such component)."""
        hosted = self._components.get(name)
        return hosted.operations if hosted is not None else frozenset()

    def find_by_type(self, type_name: str) -> list[ComponentRef]:
        return [
            ComponentRef(self, n, h.lineage)
            for n, h in sorted(self._components.items())
            if h.instance.factory.type_name == type_name
        ]

    def components(self) -> list[ComponentRef]:
        return [ComponentRef(self, n, h.lineage) for n, h in sorted(self._components.items())]

    def _hosted(self, name: str, lineage: int | None = None) -> Hosted:
        hosted = self._components.get(name)
        if lineage is not None and (hosted is None or hosted.lineage != lineage):
            when = self._destroyed.get(lineage)
            raise ComponentDestroyedError(
                f"component {name!r} was destroyed"
                + (f" at t={when:.6f}" if when is not None else ""),
                where=self._where,
                hint="drop this handle; find() or create() a component again",
            )
        if hosted is None:
            raise ComponentNotFoundError(
                f"no component named {name!r} (components: {', '.join(sorted(self._components)) or 'none'})",
                where=self._where,
                hint="create() it first, or check the name",
            )
        return hosted

    # ------------------------------------------------------------------------------ monitors
    def add_monitor(self, monitor: Monitor) -> None:
        with self._lock:
            if monitor.name in self._monitors or monitor.name in self._components:
                raise FactoryError(
                    f"an element named {monitor.name!r} already exists", where=self._where
                )
            self._monitors[monitor.name] = monitor

            def feed(event: Event, m: Monitor = monitor) -> None:
                with self.guard("monitor", m.name, event=f"{event.kind} {event.element}"):
                    m.on_event(event)

            for source in monitor.event_sources:
                for kind in (ev.OPERATION_CALLED, ev.PROPERTY_CHANGED):
                    self._events.subscribe(
                        kind, feed, name=f"monitor:{monitor.name}", element=source
                    )
                component, dot, port = source.rpartition(".")
                if dot:
                    # Calls through a port are not events of the port: an interceptor on the port's
                    # calls hands them to the monitor (by name, so it survives a replacement).
                    tap = PortTap(monitor.name, component, port, feed)
                    self.add_interceptor(tap, component=component, port=port)
                    self._taps.setdefault(monitor.name, []).append(tap)
            monitor.attach(self)

    def remove_monitor(self, name: str) -> None:
        monitor = self._monitors.pop(name, None)
        if monitor is None:
            raise ComponentNotFoundError(f"no monitor named {name!r}", where=self._where)
        self._events.unsubscribe(f"monitor:{name}")
        for tap in self._taps.pop(name, ()):
            self.remove_interceptor(tap)
        monitor.detach()

    def monitors(self) -> list[str]:
        return sorted(self._monitors)

    def monitor(self, name: str) -> Monitor:
        """The monitor ``name`` (to feed it with ``update``)."""
        try:
            return self._monitors[name]
        except KeyError:
            raise ComponentNotFoundError(
                f"no monitor named {name!r} (monitors: {', '.join(sorted(self._monitors)) or 'none'})",
                where=self._where,
            ) from None

    def monitor_update(self, monitor: Monitor, values: dict[str, object]) -> None:
        monitor.attributes.update(values)
        self.emit(ev.MONITOR_UPDATED, monitor.name, data=dict(values))

    def monitor_stale(self, monitor: Monitor, stale: bool, data: dict[str, object]) -> None:
        self.emit(ev.MONITOR_STALE, monitor.name, value=stale, data=data)

    # --------------------------------------------------------------------------- policy sets
    def add_policy_set(self, policy_set: PolicySet) -> None:
        """Bind a policy set to this container (rules to an engine, variables to attributes)."""
        with self._lock:
            if policy_set.name in self._policy_sets:
                raise FactoryError(
                    f"a policy set named {policy_set.name!r} already exists", where=self._where
                )
            policy_set.attach(self)
            self._policy_sets[policy_set.name] = policy_set

    def remove_policy_set(self, name: str) -> None:
        policy_set = self._policy_sets.pop(name, None)
        if policy_set is None:
            raise ComponentNotFoundError(f"no policy set named {name!r}", where=self._where)
        policy_set.detach()

    def policy_set(self, name: str) -> PolicySet:
        try:
            return self._policy_sets[name]
        except KeyError:
            raise ComponentNotFoundError(
                f"no policy set named {name!r}", where=self._where
            ) from None

    # ----------------------------------------------------------------------------- lifecycle
    def describe(self) -> dict[str, Any]:
        """Components, their types and ports, as plain data (also served to remote containers)."""
        return {
            "container": self.name,
            "factories": self.factories(),
            "components": {
                n: {
                    "type": h.instance.factory.type_name,
                    "ports": {p.name: [p.kind, p.role] for p in h.instance.port_map.values()},
                }
                for n, h in sorted(self._components.items())
            },
        }

    def close(self) -> None:
        """Stop monitors and policy sets, destroy components, close connectors (and an owned clock)."""
        for name in list(self._policy_sets):
            self.remove_policy_set(name)
        for name in list(self._monitors):
            self.remove_monitor(name)
        for name in list(self._components):
            self.destroy(name)
        self.close_connectors()
        if self._owns_context and self._context is not None:
            self._context.close()
        if self._owns_clock:
            self.clock.close()

    def __enter__(self) -> Container:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
