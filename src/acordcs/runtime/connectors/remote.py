"""The remote connector over Pyro5: components in containers of different processes talk (the paper's
RMI connector).

Transport choices, after the Pyro5 5.17 pitfalls (../shared/reference/context-and-transport.md):

- serpent serializer, set on every proxy (arguments must be serpent-serialisable: numbers, strings,
  lists, dicts, ...; tuples and sets arrive as tuples); serpent sends ``bytes`` as a base64 dict,
  turned back into ``bytes`` here for an argument, a message and a result (a camera frame arrives
  as the bytes it left as), by :func:`bytes_back`;
- an explicit timeout on every proxy (Pyro's default, 0, waits forever); it bounds connecting too;
- no automatic retries (``MAX_RETRIES`` would re-execute non-idempotent operations): a call whose reply
  is missing raises :class:`RemoteTimeoutError`, its outcome unknown;
- one proxy per thread (a Pyro proxy belongs to the thread that made it): proxies live in a
  ``threading.local``; a dropped connection is re-established on the next call, so calls succeed
  again once the remote container is back at the same URI (a fixed port and object id);
- notifications and stream items (one way, no reply awaited) go through an :class:`.Outbox` per
  connection, delivered in order by a thread of its own: the sender (often the clock's thread)
  never waits for a slow or unreachable peer, and what is not delivered is counted and reported.

The server side, :class:`ContainerServer`, exposes one endpoint per container; calls arriving there go
through the container like local ones (interceptors, events). Only the operations behind its provided
synchronous ports are callable (:func:`remote_operations`), and deliveries reach only its provided
asynchronous and stream ports. Who may connect (a token, a handshake deadline, serpent only, TLS) is
:mod:`.pyrogate`'s. A remote failure comes back as a
:class:`RemoteFault` and is raised as :class:`RemoteCallError` naming the remote component and operation.
"""

from __future__ import annotations

import errno
import logging
import socket
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

import Pyro5.api
import Pyro5.errors
import serpent
from Pyro5.callcontext import current_context

from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.connectors.outbox import Outbox
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
from acordcs.runtime.errors import (
    ConfigurationError,
    PortError,
    RemoteCallError,
    RemoteTimeoutError,
    RemoteUnreachableError,
    RuntimeFailure,
)

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


@dataclass(frozen=True)
class RemotePort:
    """A port of a component in another container process, reached at ``uri`` (its container's)."""

    uri: str
    component: str
    port: str

    @property
    def qualified_name(self) -> str:
        return f"{self.component}.{self.port}@{self.uri}"


CONTAINER_OBJECT = "acordcs.container.{}"
"""The Pyro5 object name of a container's endpoint (the application descriptor's ``Endpoint``)."""


def container_uri(container: str, host: str, port: int) -> str:
    """The URI of the remote endpoint of ``container``, served by a :class:`ContainerServer` on
    ``host:port``: what ``remote={container: uri}`` gives another process (the descriptor's
    ``Endpoint.uri(port)``). Stable for a given name, host and port."""
    return f"PYRO:{CONTAINER_OBJECT.format(container)}@{host}:{port}"


class RemoteConnector(Connector):
    """Calls, notifications and stream items to a :class:`RemotePort` over Pyro5.

    ``token``: the application's token, sent in every connection's handshake (default:
    ``$ACORDCS_TOKEN``); ``tls``: verify the server (and present a client certificate) over TLS.
    """

    kind = "remote"

    def __init__(
        self, *, timeout: float = 5.0, token: str | None = None, tls: TLSFiles | None = None
    ) -> None:
        if not timeout > 0:
            raise ConfigurationError(f"RemoteConnector timeout must be > 0 seconds, not {timeout}")
        self.timeout = float(timeout)
        self.token = resolve_token(token)
        if tls is not None:
            tls.configure(server=False)
        self._local = threading.local()
        self._all: list[tuple[threading.Thread, Pyro5.api.Proxy]] = []
        self._lock = threading.Lock()
        self._outboxes: dict[object, Outbox] = {}

    def default_qos(self) -> dict[str, object]:
        return {"timeout": self.timeout}

    def _proxy(self, uri: str) -> Pyro5.api.Proxy:
        proxies = getattr(self._local, "proxies", None)
        if proxies is None:
            proxies = self._local.proxies = {}
            self._local.bound = set()  # URIs this thread's proxies were bound to since a failure
        proxy = proxies.get(uri)
        if proxy is None:
            # The _pyro* attributes and methods of a proxy are Pyro5's documented public API
            # (underscored so they cannot clash with remote method names), not its internals.
            proxy = Pyro5.api.Proxy(uri)
            proxy._pyroSerializer = "serpent"
            proxy._pyroMaxRetries = 0
            proxy._pyroTimeout = self.timeout
            if self.token is not None:
                proxy._pyroHandshake = self.token
            proxies[uri] = proxy
            with self._lock:
                self._all.append((threading.current_thread(), proxy))
        return proxy

    def _invoke(self, conn: Connection, target: object, method: str, *args: Any) -> Any:
        target = self._remote(conn, target)
        reply = self.request(
            target.uri,
            method,
            target.component,
            target.port,
            *args,
            timeout=self._timeout_of(conn),
            where=_place(conn, target),
            what=f"{args[0]}()" if method == "call" else "a delivery",
        )
        conn.stats["sent"] += 1
        return bytes_back(reply)

    @staticmethod
    def _remote(conn: Connection, target: object) -> RemotePort:
        if not isinstance(target, RemotePort):
            raise RemoteCallError(
                f"connection {conn.name!r}: the remote connector needs a RemotePort, not {target!r}",
                hint="use the in-process connector between ports of one container",
            )
        return target

    def _timeout_of(self, conn: Connection) -> float:
        return float(conn.qos.get("timeout", self.timeout) or self.timeout)

    def _ready(self, uri: str, timeout: float, where: Callable[[], str]) -> Pyro5.api.Proxy:
        """This thread's proxy to ``uri``, with ``timeout``, connected (``where()`` names the
        caller in the error, made only if connecting fails)."""
        proxy = self._proxy(uri)
        if proxy._pyroTimeout != timeout:
            proxy._pyroTimeout = timeout
        try:
            proxy._pyroBind()  # Pyro5's documented bind: connects only a proxy not connected
            self._local.bound.add(uri)
        except Pyro5.errors.CommunicationError as exc:
            raise RemoteUnreachableError(
                f"cannot reach the remote container at {uri}: {exc}",
                where=where(),
                hint="start the remote container (or check its address); the call was not sent",
            ) from None
        return proxy

    def request(
        self,
        uri: str,
        method: str,
        *args: Any,
        timeout: float | None = None,
        where: str,
        what: str = "a request",
    ) -> Any:
        """Call ``method`` of the container endpoint at ``uri`` (:class:`ContainerEndpoint`) with
        ``args``; failures raise as for a port call (``where`` and ``what`` name it in them)."""
        timeout = timeout or self.timeout
        proxy = self._ready(uri, timeout, lambda: where)
        try:
            return getattr(proxy, method)(*args)
        except (RemoteFault, Pyro5.errors.PyroError) as exc:
            raise _translated(exc, method, timeout, where, what) from None

    def call(
        self,
        conn: Connection,
        target: object,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
    ) -> Any:
        target = self._remote(conn, target)
        if "." in target.port or "." in operation:
            # names that "component.port.operation" could not carry apart: the long form
            if kwargs:
                return self._invoke(conn, target, "call", operation, list(args), kwargs)
            return self._invoke(conn, target, "call", operation, list(args))
        # The short form (ContainerEndpoint.invoke): one target string, then the operation's own
        # arguments, as a bare Pyro5 call sends them; the names of the failure's place are made
        # only when there is a failure.
        timeout = self._timeout_of(conn)
        proxy = self._proxy(target.uri)
        # Bound once, then again only after a failure (Pyro5 drops the connection on one): its
        # _pyroBind costs a lock and a closure a call even when it has nothing to do.
        if proxy._pyroTimeout != timeout or target.uri not in self._local.bound:
            proxy = self._ready(target.uri, timeout, lambda: _place(conn, target))
        try:
            reply = proxy.invoke(f"{target.component}.{target.port}.{operation}", *args, **kwargs)
        except (RemoteFault, Pyro5.errors.PyroError) as exc:
            self._local.bound.discard(target.uri)
            raise _translated(
                exc, "invoke", timeout, _place(conn, target), f"{operation}()"
            ) from None
        conn.stats["sent"] += 1
        return bytes_back(reply)

    def notify(self, conn: Connection, target: object, message: Any, size: int | None) -> None:
        self._outbox(conn, target).put(message)

    def stream(self, conn: Connection, target: object, item: Any, size: int | None) -> None:
        self._outbox(conn, target).put(item)

    def _outbox(self, conn: Connection, target: object) -> Outbox:
        outbox = self._outboxes.get(conn)
        if outbox is None:
            remote = self._remote(conn, target)  # a wrong end is the sender's error, at once
            outbox = self.one_way(
                conn,
                lambda item: self._invoke(conn, remote, "deliver", item),
                conn.report_fault,
                conn.stats,
            )
        return outbox

    def one_way(
        self,
        key: object,
        send: Callable[[Any], None],
        report: Callable[[BaseException | str], None],
        stats: dict[str, int],
    ) -> Outbox:
        """The outbox of ``key`` (a connection, a monitor's feed), made on first use: items put
        there are sent by ``send`` in a thread of their own, failures go to ``report``, and
        :meth:`close` delivers what waits."""
        with self._lock:
            outbox = self._outboxes.get(key)
            if outbox is None:
                outbox = self._outboxes[key] = Outbox(str(key), send, report, stats)
        return outbox

    def pending(self) -> int:
        """One-way items taken and not yet delivered, over all outboxes."""
        with self._lock:
            outboxes = list(self._outboxes.values())
        return sum(outbox.pending() for outbox in outboxes)

    def close(self) -> None:
        """Deliver the waiting one-way items (for at most the timeout in all; each outbox then
        reports by count what it could not), and close every proxy."""
        with self._lock:
            outboxes, self._outboxes = list(self._outboxes.values()), {}
        deadline = time.monotonic() + self.timeout
        for outbox in outboxes:
            undelivered = outbox.close(deadline)
            if undelivered:
                outbox.report(
                    f"Undelivered: {undelivered} one-way item(s) waiting at close were not "
                    f"delivered within {self.timeout:g} s (the peer is unreachable or slow); "
                    "counted in stats['lost']"
                )
        with self._lock:
            proxies, self._all = self._all, []
        for _thread, proxy in proxies:
            # Closing another thread's proxy is safe here: that thread no longer uses the connector.
            proxy._pyroClaimOwnership()
            proxy._pyroRelease()


class RemoteFault(Exception):
    """A failure on the remote side, carried back over Pyro5: ``args = (type, message, hint)``.

    Results travel bare and failures as this exception (registered with Pyro5's serializer below),
    because wrapping every reply in an envelope costs a serpent round of its own.
    """


_FAULT_CLASS = f"{RemoteFault.__module__}.{RemoteFault.__qualname__}"
Pyro5.api.register_dict_to_class(
    _FAULT_CLASS, lambda _name, data: RemoteFault(*(list(data.get("args", ())) + [None] * 3)[:3])
)


def _fault(exc: BaseException) -> RemoteFault:
    hint = exc.hint if isinstance(exc, RuntimeFailure) else None
    return RemoteFault(type(exc).__name__, str(exc), hint)


def _place(conn: Connection, target: RemotePort) -> str:
    return f"connection {conn.name!r} to {target.qualified_name}"


def _translated(
    exc: RemoteFault | Pyro5.errors.PyroError, method: str, timeout: float, where: str, what: str
) -> RuntimeFailure:
    """What a failed request to an endpoint raises: the remote failure, a missing reply (outcome
    unknown) or Pyro5's refusal, saying where."""
    if isinstance(exc, RemoteFault):
        kind, message, hint = exc.args
        return RemoteCallError(
            f"remote {kind}: {message}", where=where, hint=hint or "see the remote container's log"
        )
    if isinstance(exc, Pyro5.errors.CommunicationError):
        # Pyro already closed the connection (a late reply must not answer the next call); the
        # next call reconnects.
        return RemoteTimeoutError(
            f"no reply to {what} within {timeout:g} s "
            f"({type(exc).__name__}: {exc}); it may or may not have run remotely",
            where=where,
            hint="retry only if the operation is idempotent; check the remote container",
        )
    return RemoteCallError(
        f"Pyro5 refused {method}: {exc}",
        where=where,
        hint="arguments and results must be serpent-serialisable (numbers, str, lists, dicts)",
    )


def bytes_back(value: Any) -> Any:
    """``value``, unless it is how serpent sends ``bytes`` (a dict of exactly ``data`` and
    ``encoding: "base64"``): then the bytes. Only the value itself, not what it contains: a frame
    is one argument or result; a dict of that very shape sent on purpose is taken for bytes."""
    # (len, then the two keys: no set made for every dict result)
    if (
        isinstance(value, dict)
        and len(value) == 2
        and value.get("encoding") == "base64"
        and "data" in value
    ):
        try:
            return serpent.tobytes(value)
        except (TypeError, ValueError):  # not base64 after all: a dict of that shape
            return value
    return value


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
                raise _fault(exc) from None
        try:
            component, port, operation = target.rsplit(".", 2)
        except (AttributeError, ValueError):
            raise _fault(
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
            raise _fault(exc) from None

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
            raise _fault(exc) from None

    @serpent_only
    def update_monitor(self, monitor: str, values: dict[str, Any]) -> None:
        """A reading of a monitor of another process, for the replica of it here (which feeds
        the policy sets of this container)."""
        try:
            self._container.monitor(monitor).update(**values)
        except Exception as exc:
            raise _fault(exc) from None


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
