"""The in-process connector: direct calls into the peer's container, no copies, no delay."""

from __future__ import annotations

from typing import Any

from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.errors import PortError
from acordcs.runtime.ports import Port


def _local(conn: Connection, target: object) -> Port:
    if not isinstance(target, Port):
        raise PortError(
            f"connection {conn.name!r}: the in-process connector cannot reach {target!r}",
            hint="use a RemoteConnector for a port in another container process",
        )
    return target


class InProcessConnector(Connector):
    kind = "inprocess"

    def call(
        self,
        conn: Connection,
        target: object,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
    ) -> Any:
        port = _local(conn, target)
        # Through the provider's container: its interceptors and events see the call.
        return port.component.container.invoke_port(port, operation, args, kwargs)

    def notify(self, conn: Connection, target: object, message: Any, size: int | None) -> None:
        conn.stats["sent"] += 1
        _local(conn, target).deliver(message)

    def stream(self, conn: Connection, target: object, item: Any, size: int | None) -> None:
        conn.stats["sent"] += 1
        _local(conn, target).deliver(item)
