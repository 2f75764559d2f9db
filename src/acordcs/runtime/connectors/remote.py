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

The server side is :mod:`.endpoint` (:class:`~.endpoint.ContainerServer`); who may connect (a
token, a handshake deadline, serpent only, TLS) is :mod:`.pyrogate`'s. A remote failure comes back
as a :class:`RemoteFault` and is raised as :class:`RemoteCallError` naming the remote component
and operation.
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import Pyro5.api
import Pyro5.errors
import serpent

from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.connectors.outbox import Outbox
from acordcs.runtime.connectors.pyrogate import (
    TLSFiles,
    resolve_token,
)
from acordcs.runtime.errors import (
    ConfigurationError,
    RemoteCallError,
    RemoteTimeoutError,
    RemoteUnreachableError,
    RuntimeFailure,
)

if TYPE_CHECKING:
    pass

log = logging.getLogger(__name__)


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
    """The URI of the remote endpoint of ``container``, served by a :class:`~.endpoint.ContainerServer` on
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
        """Call ``method`` of the container endpoint at ``uri`` (:class:`~.endpoint.ContainerEndpoint`) with
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


def fault_of(exc: BaseException) -> RemoteFault:
    """What an endpoint raises for ``exc`` so that it travels back to the caller."""
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
