"""What every connector implements, and the connection object it serves.

A :class:`Connection` joins two endpoints (local :class:`~acordcs.runtime.ports.Port` s, or a local
port and a :class:`~acordcs.runtime.connectors.remote.RemotePort`) and carries QoS properties (``qos``) that policies may change through the
container (``container.set_property(connection_name, "bandwidth", 2e6)``); connectors read them at
each send, so a change applies to the next message.
"""

from __future__ import annotations

import logging
from abc import ABC, abstractmethod
from collections.abc import Callable
from typing import Any, Protocol

from acordcs.runtime.errors import PortError

log = logging.getLogger(__name__)


class Endpoint(Protocol):
    """An end of a connection: a local port or a remote one."""

    @property
    def qualified_name(self) -> str: ...


class Connector(ABC):
    """Carries calls, notifications and stream items from one endpoint to its peer."""

    kind = "abstract"

    def default_qos(self) -> dict[str, object]:
        """QoS properties a new connection starts with (overridden by ``connect(qos=...)``)."""
        return {}

    @abstractmethod
    def call(
        self,
        conn: Connection,
        target: object,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
    ) -> Any:
        """Run ``operation`` on the peer and return its result (request-reply)."""

    @abstractmethod
    def notify(self, conn: Connection, target: object, message: Any, size: int | None) -> None:
        """Deliver a notification to the peer's queue."""

    @abstractmethod
    def stream(self, conn: Connection, target: object, item: Any, size: int | None) -> None:
        """Deliver one stream item to the peer."""

    def close(self) -> None:  # noqa: B027 (a no-op unless the connector holds sockets)
        """Release what the connector holds (sockets, proxies)."""


class Connection:
    """A port connection (the metamodel's CtxPortConnection) at run time."""

    def __init__(
        self,
        name: str,
        required: Endpoint,
        provided: Endpoint,
        connector: Connector,
        qos: dict[str, object],
    ) -> None:
        self.name = name
        self.required = required
        self.provided = provided
        self.connector = connector
        self.qos = qos
        self.stats: dict[str, int] = {"sent": 0, "lost": 0}
        self.on_fault: Callable[[BaseException | str], None] | None = None
        """Where a failure off the sender's thread goes (a connector's own thread delivering a
        notification): the container that made the connection records it as its fault."""

    def report_fault(self, error: BaseException | str) -> None:
        if self.on_fault is not None:
            self.on_fault(error)
        else:
            log.error("connection %r: %s", self.name, error)

    def peer_of(self, port: Endpoint) -> Endpoint:
        if self.required is port:
            return self.provided
        if self.provided is port:
            return self.required
        raise PortError(f"port {port.qualified_name} is not an end of connection {self.name!r}")

    def ends(self) -> tuple[Endpoint, Endpoint]:
        return self.required, self.provided

    def replace_end(self, old: Endpoint, new: Endpoint) -> None:
        """Swap a port (component replacement keeps connections)."""
        if self.required is old:
            self.required = new
        if self.provided is old:
            self.provided = new

    def __repr__(self) -> str:
        return f"<Connection {self.name} via {self.connector.kind}>"
