"""The server side of the remote connector: a container served over Pyro5.

:class:`ContainerServer` runs a Pyro5 daemon (:mod:`.pyrogate`'s: token, handshake deadline,
TLS) with one :class:`ContainerEndpoint` for its container. Calls arriving there go through the
container like local ones (interceptors, events); only the operations behind its provided
synchronous ports are callable (:func:`remote_operations`), and deliveries reach only its
provided asynchronous and stream ports. Failures travel back as :class:`~.remote.RemoteFault`.
"""

from __future__ import annotations

import errno
import logging
import socket
import threading
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import Pyro5.api
import Pyro5.errors
from Pyro5.callcontext import current_context

from acordcs.runtime.connectors.pyrogate import (
    HANDSHAKE_TIMEOUT,
    MAX_CONNECTIONS,
    SERPENT_ID,
    GatedDaemon,
    TLSFiles,
    configure_server,
    is_loopback,
    not_serpent,
    resolve_token,
    serpent_only,
)
from acordcs.runtime.connectors.remote import CONTAINER_OBJECT, bytes_back, fault_of
from acordcs.runtime.errors import ConfigurationError, PortError

if TYPE_CHECKING:
    from acordcs.runtime.monitor import Monitor
    from acordcs.runtime.ports import Port

log = logging.getLogger(__name__)


class ServedContainer(Protocol):
    """What a :class:`ContainerServer` needs from the container it serves."""

    name: str

    def describe(self) -> dict[str, Any]: ...

    def port_of(self, component: str, port: str) -> Port: ...

    def invoke_port(
        self, port: Port, operation: str, args: tuple[Any, ...], kwargs: dict[str, Any]
    ) -> Any: ...

    def monitor(self, name: str) -> Monitor: ...

    def operations_of(self, name: str) -> frozenset[str]: ...


def remote_operations(port: Port, operations: frozenset[str]) -> frozenset[str]:
    """The operations another process may call through ``port``: those it declares
    (``PortSpec.operations``), else ``operations`` (its component's, as its container keeps them:
    ``operations_of``) less the methods its ports are fed through (handlers such as
    ``on_<port>``, stream sources) and any other ``on_*`` hook, which run from the port's queue,
    never from a caller."""
    if port.spec.operations is not None:
        return frozenset(port.spec.operations)
    fed_through = set()
    for p in getattr(port.component, "port_map", {}).values():
        fed_through.update(n for n in (p.handler, p.spec.source) if n)
    return frozenset(o for o in operations if o not in fed_through and not o.startswith("on_"))


def _has(port: Port, operation: str) -> bool:
    """Whether ``operation`` is a method of the port's component (one that is not exposed gets a
    refusal; one that does not exist gets the container's "no operation" error)."""
    return callable(getattr(port.component, operation, None))


MAX_ROUTES = 4096
"""Short-form targets a :class:`ContainerEndpoint` remembers (forgotten all at once beyond)."""


class ContainerEndpoint:
    """What a container exposes over Pyro5; failures come back as :class:`RemoteFault`. Every
    method refuses a call made with another serializer than serpent."""

    def __init__(self, container: ServedContainer) -> None:
        self._container = container
        # (component, port) -> (the port, its component's operations, what it exposes): computed
        # again when the container has another port or operations there (a replaced component)
        self._exposed: dict[tuple[str, str], tuple[Port, frozenset[str], frozenset[str]]] = {}
        # a short-form target -> (its port, its operation), once the call was found to reach an
        # exposed operation of a synchronous provided port: the next calls to it go straight to
        # invoke_port (which checks the port again), without splitting the name, finding the port
        # and what it exposes. Valid while the port's component is alive (a replaced or destroyed
        # component is not: its target is resolved again, with the errors of the first time).
        self._routes: dict[str, tuple[Port, str]] = {}

    def _exposed_by(self, component: str, target: Port) -> frozenset[str]:
        operations = self._container.operations_of(component)
        known = self._exposed.get((component, target.name))
        if known is not None and known[0] is target and known[1] is operations:
            return known[2]
        exposed = remote_operations(target, operations)
        self._exposed[(component, target.name)] = (target, operations, exposed)
        return exposed

    @serpent_only
    def ping(self) -> str:
        return self._container.name

    @serpent_only
    def describe(self) -> dict[str, Any]:
        return self._container.describe()

    @serpent_only
    def call(
        self,
        component: str,
        port: str,
        operation: str,
        args: list[Any],
        kwargs: dict[str, Any] | None = None,
    ) -> Any:
        """``operation`` of ``component`` through its provided synchronous ``port``, with ``args``
        (a list) and ``kwargs``: the long form, for any names (a tool's, the console's)."""
        return self._call(component, port, operation, args, kwargs or {})

    @Pyro5.api.expose
    def invoke(self, target: str, /, *args: Any, **kwargs: Any) -> Any:
        """The same call in the short form the connector sends: ``target`` is
        ``"component.port.operation"`` (a port and an operation whose names have no dot), then the
        operation's own arguments, as a bare Pyro5 call carries them (fewer values to serialise
        and to parse on both sides)."""
        # serpent only, as @serpent_only checks it, written out here: the busiest method of the
        # endpoint, without the decorator's extra frame and repacking of the arguments
        used = getattr(current_context, "serializer_id", SERPENT_ID)
        if used != SERPENT_ID:
            raise not_serpent(used)
        route = self._routes.get(target) if type(target) is str else None
        if route is not None and route[0].component.alive:
            try:
                args = tuple(map(bytes_back, args))
                if kwargs:
                    kwargs = {k: bytes_back(v) for k, v in kwargs.items()}
                return self._container.invoke_port(route[0], route[1], args, kwargs)
            except Exception as exc:  # as in _call
                raise fault_of(exc) from None
        try:
            component, port, operation = target.rsplit(".", 2)
        except (AttributeError, ValueError):
            raise fault_of(
                PortError(
                    f"a call names its target 'component.port.operation', not {target!r}",
                    where=f"container {self._container.name!r}",
                )
            ) from None
        return self._call(component, port, operation, args, kwargs, route=target)

    def _call(
        self,
        component: str,
        port: str,
        operation: str,
        args: Sequence[Any],
        kwargs: dict[str, Any],
        route: str | None = None,
    ) -> Any:
        """The call; ``route``: the short-form target naming it, remembered for the next calls
        when it reaches an exposed operation (:attr:`_routes`)."""
        c = self._container
        try:
            args = tuple(map(bytes_back, args))
            if kwargs:
                kwargs = {k: bytes_back(v) for k, v in kwargs.items()}
            target = c.port_of(component, port)
            # the operations the container recorded when it made (or replaced) the component,
            # and what the port exposes of them: not computed again at every call
            exposed = self._exposed_by(component, target)
            if (
                target.kind == "synchronous"
                and operation not in exposed
                and _has(target, operation)
            ):
                raise PortError(
                    f"port {target.qualified_name} does not expose {operation!r} to other "
                    f"processes (exposes: {', '.join(sorted(exposed)) or 'none'})",
                    where=f"container {c.name!r}",
                    hint="call an operation of the port's interface; handlers and hooks run "
                    "from the port's queue",
                )
            if (
                route is not None
                and operation in exposed
                and target.kind == "synchronous"
                and target.role == "provided"
            ):
                if len(self._routes) >= MAX_ROUTES:  # components made and destroyed all along
                    self._routes.clear()
                self._routes[route] = (target, operation)
            return c.invoke_port(target, operation, args, kwargs)
        except Exception as exc:  # including faults in our own code: the worker must survive
            raise fault_of(exc) from None

    @serpent_only
    def deliver(self, component: str, port: str, message: Any) -> None:
        try:
            target = self._container.port_of(component, port)
            # A delivery is a message or stream item for the receiving end of a connection: a
            # required port of a provider's notifications or stream (a camera's frames), or a
            # provided port that takes messages; never a synchronous port's operations.
            if target.kind == "synchronous":
                raise PortError(
                    f"deliveries arrive at asynchronous or stream ports; "
                    f"{target.qualified_name} is {target.kind}/{target.role}",
                    where=f"container {self._container.name!r}",
                )
            target.deliver(bytes_back(message))
        except Exception as exc:
            raise fault_of(exc) from None

    @serpent_only
    def update_monitor(self, monitor: str, values: dict[str, Any]) -> None:
        """A reading of a monitor of another process, for the replica of it here (which feeds
        the policy sets of this container)."""
        try:
            self._container.monitor(monitor).update(**values)
        except Exception as exc:
            raise fault_of(exc) from None

    @serpent_only
    def stale_monitor(self, monitor: str, cause: str) -> None:
        """A monitor of another process went stale (``cause``: why): its replica here goes stale
        too, keeping its last values, until the next reading (:meth:`update_monitor`)."""
        try:
            self._container.monitor(monitor).mark_stale(str(cause)[:500])
        except Exception as exc:
            raise fault_of(exc) from None


class ContainerServer:
    """Serves a container on ``host:port`` (port 0: any free one) with a Pyro5 daemon thread, at
    :func:`container_uri` (``uri``).

    ``token`` (default ``$ACORDCS_TOKEN``): connections must present it in the handshake; without
    one, only a loopback host may be served (with a warning). ``handshake_timeout``: seconds a new
    connection has to complete the handshake; ``max_connections``: connections served at once;
    ``tls``: serve over TLS (:class:`~.pyrogate.TLSFiles`; with ``cacerts``, clients need a
    certificate signed by it). The last three are Pyro5 settings of the whole process.
    Refused connections are counted (:meth:`refused`) and logged on the 1st, 2nd, 4th, 8th...
    of each kind only, with the peer's address.
    """

    def __init__(
        self,
        container: ServedContainer,
        *,
        host: str = "127.0.0.1",
        port: int = 0,
        token: str | None = None,
        handshake_timeout: float = HANDSHAKE_TIMEOUT,
        max_connections: int = MAX_CONNECTIONS,
        tls: TLSFiles | None = None,
    ) -> None:
        self.container = container
        token = resolve_token(token)
        self.token_required = token is not None
        if token is None:
            if not is_loopback(host):
                raise ConfigurationError(
                    f"container {container.name!r} would be served at {host}:{port} without a "
                    "token: any process reaching that address could call it",
                    hint="set ACORDCS_TOKEN (the same in every process of the application) or "
                    "pass token=",
                )
            log.warning(
                "container %r is served on %s without a token: any local process may call it "
                "(set ACORDCS_TOKEN)",
                container.name,
                host,
            )
        configure_server(handshake_timeout, max_connections)
        if tls is not None:
            tls.configure(server=True)
        try:
            self.daemon = GatedDaemon(
                host=host, port=port, token=token, name=f"container {container.name!r}"
            )
        except OSError as err:  # a host that does not resolve (gaierror), a port in use...
            raise ConfigurationError(
                f"container {container.name!r} cannot serve at {host}:{port}: "
                f"{err.strerror or err}",
                where=f"container {container.name!r}",
                hint=(
                    f"{host!r} is not a name or address of this machine: give the container's "
                    "address here (ACORDCS_<container>_HOST, or --host)"
                    if isinstance(err, socket.gaierror)
                    or err.errno in (errno.EADDRNOTAVAIL, errno.EAFNOSUPPORT)
                    else f"another process uses port {port} on {host}: stop it, or give the "
                    "container another port (ACORDCS_<container>_PORT, or --serve)"
                    if err.errno == errno.EADDRINUSE
                    else "check the host and port this container serves at"
                ),
            ) from None
        if tls is not None:
            # Pyro5 accepts in one thread; with the TLS handshake done at accept (ssl's default) a
            # client that connects and stays silent would hold every other connection up (the
            # accepted socket has no timeout yet). Deferred, the handshake runs in the
            # connection's worker, on its first read, within handshake_timeout.
            self.daemon.sock.do_handshake_on_connect = False
        self.host, self.port = host, int(self.daemon.locationStr.rsplit(":", 1)[1])
        self.uri = str(
            self.daemon.register(
                ContainerEndpoint(container), CONTAINER_OBJECT.format(container.name)
            )
        )
        self._thread = threading.Thread(
            target=self.daemon.requestLoop, name=f"acordcs-pyro-{container.name}", daemon=True
        )
        self._thread.start()

    def refused(self) -> dict[str, int]:
        """The connections refused so far, by why: ``wrong_token`` (a handshake without the
        application's token), each logged on its 1st, 2nd, 4th, 8th... refusal only."""
        return self.daemon.refusals.counts()

    def close(self) -> None:
        self.daemon.shutdown()
        self._thread.join(timeout=5)

    def __enter__(self) -> ContainerServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
