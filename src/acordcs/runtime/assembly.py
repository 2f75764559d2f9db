"""``assemble(descriptor) -> RunningApplication``: running containers built from an application
descriptor (:mod:`acordcs.descriptor`), the one source of truth between a model and what runs.

Each container of the descriptor becomes a :class:`Container` (all sharing one clock); a descriptor
with no container gets one named after the application. Components are created from the factories
given by component name; a component without one gets a generic class made from the model (its
properties, ports and operations: :mod:`.operations`). Monitors are made by the makers given by name
(default: a plain :class:`Monitor`, fed from outside with ``update``). Connections get their QoS
properties and a connector by where their ends run: in-process between containers built here (also
for a ``remote`` connection: co-located containers need no network), Pyro5 to an end in a container
not built here (given as ``remote={container name: uri}``); ``shaped`` adds an emulated link.
Policy sets get their plan (:func:`acordcs.engines.plan.plan_from_descriptor`: the rules as
the descriptor resolved them), trigger and frequency. A monitor feeding a policy set of another container has a replica there, updated with its
readings (in-process, or over Pyro5 to another process: see :class:`Feed`).

The descriptor is read as plain data: this module imports neither the descriptor package nor the
model (the caller that made or read the descriptor has them), so a deployed application does not
load the toolchain.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from acordcs.engines.plan import plan_from_descriptor
from acordcs.runtime import events as ev
from acordcs.runtime.acquisition import MONITOR_KINDS
from acordcs.runtime.clock import Clock, VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors import (
    ContainerServer,
    InProcessConnector,
    RemoteConnector,
    RemotePort,
    ShapedConnector,
)
from acordcs.runtime.connectors.base import Connector
from acordcs.runtime.connectors.pyrogate import TLSFiles, resolve_token
from acordcs.runtime.container import Container
from acordcs.runtime.errors import BindingError, RemoteNotGivenError
from acordcs.runtime.events import Event
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.operations import OutParameters, generic_component
from acordcs.runtime.persistence import Persistence, StateStore
from acordcs.runtime.policy import PolicySet
from acordcs.runtime.ports import Port

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application, Connection
    from acordcs.descriptor.application import Component as ComponentDescription
    from acordcs.descriptor.application import Monitor as MonitorDescription
    from acordcs.descriptor.application import PolicySet as PolicySetDescription
    from acordcs.runtime.context.core import ProviderCore

MonitorMaker = Callable[..., Monitor]
log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Feed:
    """A monitor feeding a policy set, as assembled here: the monitor and the container it runs in
    (``source``), the policy set and its container (``target``), and ``delivery``:

    - ``local``: the same container;
    - ``in-process``: another container of this process: a replica of the monitor there is updated
      with each reading;
    - ``remote``: the monitor runs here, the policy set's container in the process given by
      ``remote=``: each reading is sent to that container's endpoint, which updates its replica;
    - ``replica``: the policy set runs here, the monitor in another process: a replica here, fed
      by that process (``remote``) or by ``container.monitor(name).update``;
    - ``undelivered``: the monitor runs here, and the policy set's container is neither here nor
      given by ``remote=``: its readings do not reach it (a warning says so at assembly).
    """

    monitor: str
    source: str
    policy_set: str
    target: str
    delivery: str


class RunningApplication:
    """The containers assembled from one descriptor (``descriptor``); ``close()`` stops them all,
    and the servers :meth:`serve` started."""

    def __init__(
        self,
        descriptor: Application,
        clock: Clock,
        containers: dict[str, Container],
        *,
        feeds: tuple[Feed, ...] = (),
        release: Iterable[Callable[[], None]] = (),
        token: str | None = None,
        java_sources: Path | None = None,
        restored: Mapping[str, Iterable[tuple[str, str]]] | None = None,
    ) -> None:
        self.descriptor = descriptor
        # By container: the (component, property) a kept state gave another value than the
        # model's, as changes at run time are (an update of the default leaves them be).
        self.restored = {k: frozenset(v) for k, v in (restored or {}).items()}
        self.java_sources = java_sources  # where its Java components' classes are (or None)
        self.name = descriptor.name
        self.clock = clock
        self.containers = containers
        self.feeds = feeds
        self.servers: dict[str, ContainerServer] = {}
        self._release = list(release)  # what else close() releases (the feeds' connector)
        self._token = token  # the application's token, for serve() (None: $ACORDCS_TOKEN)

    @property
    def context(self) -> ProviderCore:
        """The context provider its containers share."""
        return self.container().context

    def release(self, fn: Callable[[], None]) -> None:
        """Call ``fn`` when the application closes (after its containers)."""
        self._release.append(fn)

    def container(self, name: str | None = None) -> Container:
        """The container ``name`` (default: the first one built)."""
        if name is None:
            return next(iter(self.containers.values()))
        try:
            return self.containers[name]
        except KeyError:
            raise BindingError(
                f"application {self.name!r} has no container {name!r} here "
                f"(built: {', '.join(self.containers)})"
            ) from None

    def serve(
        self, name: str, *, host: str | None = None, port: int = 0, tls: TLSFiles | None = None
    ) -> ContainerServer:
        """Serve the container ``name`` to other processes at its endpoint,
        ``container_uri(name, host, port)`` (``server.uri``; port 0: any free one). ``host``
        defaults to the container's host in the descriptor. Callers must present the
        application's token (``assemble(token=...)``, else ``$ACORDCS_TOKEN``); ``tls``: see
        :class:`~acordcs.runtime.connectors.pyrogate.TLSFiles`."""
        container = self.container(name)
        if name in self.servers:
            raise BindingError(f"container {name!r} is already served at {self.servers[name].uri}")
        if host is None:
            found = next((c for c in self.descriptor.containers if c.name == name), None)
            host = (found.endpoint.host if found.endpoint else found.host) if found else "localhost"
        self.servers[name] = server = ContainerServer(
            container, host=host, port=port, token=self._token, tls=tls
        )
        return server

    def close(self) -> None:
        for server in self.servers.values():
            server.close()
        self.servers.clear()
        for container in self.containers.values():
            container.close()
        for release in self._release:
            release()
        self._release.clear()
        self.clock.close()

    def __enter__(self) -> RunningApplication:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def assemble(
    descriptor: Application,
    *,
    factories: Mapping[str, type[CtxComponent] | ComponentFactory] | None = None,
    monitors: Mapping[str, MonitorMaker] | None = None,
    clock: Clock | None = None,
    only: Iterable[str] | None = None,
    remote: Mapping[str, str] | None = None,
    remote_timeout: float = 5.0,
    context: ProviderCore | None = None,
    token: str | None = None,
    java_sources: Path | None = None,
    state_dir: Path | None = None,
) -> RunningApplication:
    """Build the containers of ``descriptor`` (all, or those named in ``only``) on one clock
    (default: a :class:`VirtualClock` with seed 0) and one context provider (default: an embedded
    one, inline on a virtual clock; give an MQTT one to share context between processes); see the
    module's docstring. ``token``: the application's token, presented to the containers given by
    ``remote`` and required by the ones this process serves (default: ``$ACORDCS_TOKEN``).
    ``java_sources``: the ``java`` target's output, where the classes of the components tagged
    ``language=java`` are (:mod:`acordcs.runtime.jvm` hosts them; none: such a component is
    refused). ``state_dir``: where the state of the components tagged ``persistent`` is kept
    (the run directory; :mod:`.persistence`): restored from there before they start, written
    there as it changes (None: not kept)."""
    clock = clock or VirtualClock()
    owned = context is None
    if context is None:
        # imported here: the provider needs lxml, which an application without context documents
        # (and a process only reading the descriptor) does not load
        from acordcs.runtime.context.embedded import ContextProvider

        context = ContextProvider(inline=isinstance(clock, VirtualClock))
    provider = context
    try:
        running = Assembler(
            descriptor,
            factories=dict(factories or {}),
            monitors=dict(monitors or {}),
            clock=clock,
            only=only,
            remote=dict(remote or {}),
            remote_timeout=remote_timeout,
            context=provider,
            token=token,
            java_sources=java_sources,
            state_dir=state_dir,
        ).run()
    except BaseException:
        if owned:
            provider.close()
        raise
    if owned:
        running.release(provider.close)
    return running


class Assembler:
    """Builds the elements of ``app`` into containers: :func:`assemble` builds them all into new
    containers; a live update (:mod:`acordcs.runtime.live.apply_update`) builds the elements a change adds
    into the running ones (``containers``, by name)."""

    def __init__(
        self,
        app: Application,
        *,
        factories: dict[str, type[CtxComponent] | ComponentFactory],
        monitors: dict[str, MonitorMaker],
        clock: Clock,
        only: Iterable[str] | None,
        remote: dict[str, str],
        remote_timeout: float,
        context: ProviderCore,
        token: str | None = None,
        containers: dict[str, Container] | None = None,
        java_sources: Path | None = None,
        state_dir: Path | None = None,
    ) -> None:
        self.app = app
        self.java_sources = java_sources
        self.state_dir = state_dir
        # The state files of the persistent components built here, by container and component,
        # and the properties their kept state changed.
        self.stores: dict[str, dict[str, StateStore]] = {}
        self.restored: dict[str, set[tuple[str, str]]] = {}
        self.token = token
        self.context = context
        self.factories = factories
        self.monitors = monitors
        self.clock = clock
        self.remote = remote
        self.remote_timeout = remote_timeout
        wanted = set(only) if only is not None else None
        unknown = sorted((wanted or set()) - {c.name for c in app.containers})
        if unknown:
            raise BindingError(
                f"application {app.name!r} has no container {', '.join(map(repr, unknown))} "
                f"(containers: {', '.join(c.name for c in app.containers) or 'none'})",
                hint="name containers of the descriptor in only=[...]",
            )
        self.containers: dict[str, Container] = {}
        # Where each component, monitor and policy set runs (by name; names are unique in a model).
        self.placed: dict[str, str] = {}
        for c in app.containers:
            for ref in c.hosts:
                self.placed[ref.name] = c.name
            if containers is not None:
                if c.name in containers and (wanted is None or c.name in wanted):
                    self.containers[c.name] = containers[c.name]
            elif wanted is None or c.name in wanted:
                props = {p.name: p.default for p in c.properties}
                self.containers[c.name] = Container(
                    c.name, clock=clock, properties=props, context=context
                )
        if not app.containers:
            if containers is not None:
                self.containers.update(containers)
            else:
                self.containers[app.name] = Container(app.name, clock=clock, context=context)
        self.default = app.containers[0].name if app.containers else app.name
        self.relay: RemoteConnector | None = None  # sends readings to other processes

    def where(self, name: str) -> str:
        """The container the element ``name`` runs in."""
        return self.placed.get(name, self.default)

    def home(self, name: str) -> Container | None:
        """The container of ``name`` if it is built here."""
        return self.containers.get(self.where(name))

    def run(self) -> RunningApplication:
        for comp in self.app.components:
            target = self.home(comp.name)
            if target is not None:
                factory = self.factory(comp)
                target.install_factory(factory)
                self.component(comp, target, factory.type_name)
        for mon in self.app.monitors:
            target = self.home(mon.name)
            if target is not None:
                target.add_monitor(self.monitor(mon))
        for conn in self.app.connections:
            self.connect(conn)
        feeds = self.feeds()
        for ps in self.app.policy_sets:
            target = self.home(ps.name)
            if target is not None:
                target.add_policy_set(self.policy_set(ps, target))
        release = [self.relay.close] if self.relay is not None else []
        for name, stores in self.stores.items():  # closed after the components stopped
            release.append(Persistence(self.containers[name], stores).close)
        return RunningApplication(
            self.app,
            self.clock,
            self.containers,
            feeds=feeds,
            release=release,
            token=self.token,
            java_sources=self.java_sources,
            restored=self.restored,
        )

    def factory(self, comp: ComponentDescription) -> ComponentFactory:
        """The factory of component ``comp``: a :class:`ComponentFactory` given for it, as given
        (a run that stands in for the component whatever its language, as ``acordcs-gen test``
        does); else a Java host for one tagged ``language=java`` (the python target's class of such
        a component is a stub the tag overrides); else its class given, else one made from the
        model."""
        given = self.factories.get(comp.name)
        if isinstance(given, ComponentFactory):
            return given
        if comp.language == "java":
            from acordcs.runtime.jvm import java_factory  # here: only a Java component loads JPype

            # the call's timeout: what a caller in another process waits for the reply
            return java_factory(comp, self.app.name, self.java_sources, timeout=self.remote_timeout)
        return ComponentFactory(comp.name, given or generic_component(comp))

    def component(
        self, comp: ComponentDescription, target: Container, type_name: str
    ) -> CtxComponent:
        """Create component ``comp`` in ``target`` from its factory there (of ``type_name``); one
        tagged ``persistent`` takes the state its file keeps, if any, before it starts."""
        state = None
        if comp.persistent and self.state_dir is not None:
            store = StateStore(Path(self.state_dir), self.app.name, comp,
                               token=resolve_token(self.token))  # fmt: skip
            self.stores.setdefault(target.name, {})[comp.name] = store
            state = store.load()
            defaults = {p.name: p.default for p in comp.properties}
            for name, value in (state or {}).get("properties", {}).items():
                if value != defaults.get(name):
                    self.restored.setdefault(target.name, set()).add((comp.name, name))
        instance = target.create(type_name, comp.name, state=state).instance
        self.port_properties(comp, instance)
        check = OutParameters(comp.name, comp.operations)
        if check.lengths:
            target.add_interceptor(check, component=comp.name)
        return instance

    @staticmethod
    def port_properties(comp: ComponentDescription, instance: CtxComponent) -> None:
        """The model's port properties are the port's (rule variables), besides those the class
        sets (rate, capacity, overflow: its own values win). A port the class lacks fails where
        it is connected, with the port's name."""
        for port in comp.ports:
            found = instance.port_map.get(port.name)
            for p in port.properties if found is not None else ():
                found.properties.setdefault(p.name, p.default)

    def monitor(self, mon: MonitorDescription) -> Monitor:
        """The monitor ``mon``, made by its maker (its class given, else its acquisition kind's)."""
        maker = self.monitors.get(mon.name, MONITOR_KINDS[mon.acquisition])
        how: dict[str, str] = {}  # what its kind needs besides what every monitor has
        if mon.acquisition == "subscribe":
            how["xpath"] = mon.xpath or ""
        elif mon.acquisition == "poll":
            how["operation"] = mon.operation or ""
        return maker(
            mon.name,
            frequency=mon.frequency,
            sources=[s.name for s in mon.sources],
            attributes={p.name: p.default for p in mon.properties},
            **how,
        )

    def host_of(self, conn: Connection) -> str | None:
        """The container built here that declares ``conn`` (the first of its ends built here)."""
        ends = (self.where(e.component) for e in (conn.required, conn.provided))
        return next((where for where in ends if where in self.containers), None)

    def connect(self, conn: Connection) -> None:
        ends = [
            (self.where(e.component), e.component, e.port) for e in (conn.required, conn.provided)
        ]
        where = self.host_of(conn)
        if where is None:
            return
        host = self.containers[where]
        caller = ends[0]
        if caller[0] not in self.containers and caller[0] not in self.remote:
            provided = host.port_of(conn.provided.component, conn.provided.port)
            if provided.kind == "synchronous":
                # Request-reply from another process: the calls arrive through this container's
                # endpoint (serve it); nothing goes back on this connection, so nothing to declare.
                return
        resolved: list[Port | RemotePort] = []
        for where, comp, port in ends:
            if where in self.containers:
                resolved.append(self.containers[where].port_of(comp, port))
            elif where in self.remote:
                resolved.append(RemotePort(self.remote[where], comp, port))
            else:
                raise RemoteNotGivenError(
                    f"connection {conn.name!r}: {comp}.{port} is in container {where!r}, not built here",
                    hint=f"pass remote={{{where!r}: uri}} to assemble",
                )
        connector = self.connector(conn, crosses=any(isinstance(e, RemotePort) for e in resolved))
        qos = {q.name: q.default for q in conn.qos}
        host.connect(resolved[0], resolved[1], connector=connector, name=conn.name, qos=qos)

    def connector(self, conn: Connection, *, crosses: bool) -> Connector:
        """The connector of ``conn``: the transport follows where the ends run (Pyro5 to another
        process, direct calls within this one, whatever the model's ``remote`` says: co-located
        containers need no network), and ``shaped`` puts an emulated link over it."""
        if conn.connector == "inprocess" and crosses:
            raise BindingError(
                f"connection {conn.name!r} is in-process but joins {conn.required.component} and "
                f"{conn.provided.component}, which run in different processes (containers "
                f"{self.where(conn.required.component)!r} and {self.where(conn.provided.component)!r})",
                hint="set the connection's connector to remote (or shaped) in the model, or "
                "assemble both containers in one process",
            )
        transport: Connector
        if crosses:
            transport = RemoteConnector(timeout=self.remote_timeout, token=self.token)
        else:
            transport = InProcessConnector()
        if conn.connector == "shaped":
            # A lost message waits as long as a remote reply would.
            timeout = {"timeout": self.remote_timeout} if crosses else {}
            return ShapedConnector(self.clock, transport, **timeout)
        return transport

    def feeds(self) -> tuple[Feed, ...]:
        """Deliver the readings of monitors to the policy sets they feed in other containers
        (see :class:`Feed`); the feeds that involve a container built here."""
        return tuple(f for mon in self.app.monitors for f in self.feeds_of(mon))

    def feeds_of(self, mon: MonitorDescription) -> list[Feed]:
        """Deliver the readings of ``mon`` to the policy sets it feeds (see :meth:`feeds`)."""
        out: list[Feed] = []
        done: set[str] = set()  # target containers already wired
        source = self.where(mon.name)
        for fed in mon.feeds:
            target = self.where(fed.name)
            delivery = self.delivery(source, target)
            if delivery is None:
                continue
            out.append(Feed(mon.name, source, fed.name, target, delivery))
            if delivery == "local" or target in done:
                continue
            done.add(target)
            self.wire(mon.name, {p.name: p.default for p in mon.properties}, out[-1])
        return out

    def delivery(self, source: str, target: str) -> str | None:
        here = self.containers
        if source == target:
            return "local" if source in here else None
        if target in here:
            return "in-process" if source in here else "replica"
        if source in here:
            return "remote" if target in self.remote else "undelivered"
        return None

    def wire(self, monitor: str, attributes: dict[str, object], feed: Feed) -> None:
        """A replica of ``monitor`` in the policy set's container, and the relay of readings to it."""
        self.relay_to(feed, self.replica(monitor, attributes, feed))

    def replica(self, monitor: str, attributes: dict[str, object], feed: Feed) -> Monitor | None:
        """The replica of ``monitor`` that ``feed`` needs in its policy set's container (None
        when that container is not built here)."""
        if feed.delivery not in ("in-process", "replica"):
            return None
        replica = Monitor(monitor, attributes=attributes)
        self.containers[feed.target].add_monitor(replica)
        return replica

    def relay_to(self, feed: Feed, replica: Monitor | None) -> None:
        """Send the readings of ``feed``'s monitor to the replica in its policy set's container:
        ``replica`` when built here, else over Pyro5 (see :class:`Feed`)."""
        source, target, monitor = feed.source, feed.target, feed.monitor
        if feed.delivery == "replica":
            log.info(
                "policy set %r of container %r reads monitor %r of container %r (another process) "
                "through a replica here: it gets the readings that process sends to this "
                "container's endpoint (serve it, and assemble that process with "
                "remote={%r: uri}); until then the monitor's attributes keep their defaults",
                feed.policy_set,
                target,
                monitor,
                source,
                target,
            )
            return
        if feed.delivery == "undelivered":
            log.warning(
                "monitor %r feeds policy set %r of container %r, which is neither assembled in "
                "this process nor given as remote={%r: uri}: its readings are not delivered there",
                monitor,
                feed.policy_set,
                target,
                target,
            )
            return
        # the feed's name: its two subscriptions' (a live update takes both down with one
        # unsubscribe) and its faults' place, as a listener's would be
        name = f"feed:{monitor}->{target}"
        relay: Callable[[Event], None]
        stale: Callable[[Event], None]
        if replica is not None:

            def relay(event: Event, replica: Monitor = replica) -> None:
                replica.update(**event.data)

            def stale(event: Event, replica: Monitor = replica) -> None:
                if event.value:  # fresh again comes with the monitor's next reading
                    replica.mark_stale(stale_cause(monitor, source, event))

        else:
            if self.relay is None:
                self.relay = RemoteConnector(timeout=self.remote_timeout, token=self.token)
            uri, connector, home = self.remote[target], self.relay, self.containers[source]
            where = f"feed of monitor {monitor!r} to container {target!r}"

            def send(item: tuple[str, object]) -> None:
                # ("update_monitor", a reading) or ("stale_monitor", why it went stale)
                method, value = item
                what = "a reading" if method == "update_monitor" else "a stale mark"
                connector.request(uri, method, monitor, value, where=where, what=what)

            def report(error: BaseException | str) -> None:
                home.faults.record("listener", name, error, home.clock.now())

            # In order, from a thread of the connector's, no retry: the monitor (often ticked by
            # the clock's thread) never waits for the other process; an unreachable container is
            # a fault of this feed (logged once, counted) and the reading is lost for it.
            outbox = connector.one_way(name, send, report, {"lost": 0})

            def relay(event: Event) -> None:
                outbox.put(("update_monitor", dict(event.data)))

            def stale(event: Event) -> None:
                if event.value:  # in order with the readings: the next one is fresh again
                    outbox.put(("stale_monitor", stale_cause(monitor, source, event)))

        self.containers[source].subscribe(ev.MONITOR_UPDATED, relay, name=name, element=monitor)
        self.containers[source].subscribe(ev.MONITOR_STALE, stale, name=name, element=monitor)

    def policy_set(self, ps: PolicySetDescription, target: Container) -> PolicySet:
        # Every monitor feeding the set is in its container, or has a replica there (see feeds).
        return PolicySet.from_plan(
            plan_from_descriptor(ps),
            trigger=ps.trigger,
            frequency=ps.frequency,
            adapts=[a.name for a in ps.adapts],
            fed_by=self.app.fed_by(ps.name),
        )


def stale_cause(monitor: str, source: str, event: Event) -> str:
    """Why a replica of ``monitor`` goes stale: its monitor in container ``source`` did (``event``,
    its ``monitor.stale``), and why that one did."""
    return f"monitor {monitor!r} of container {source!r} went stale: {event.data.get('cause')}"
