"""A shaping connector: emulates a network link (latency, jitter, bandwidth, loss) through the clock.

Each direction of a connection is a FIFO link: a message waits for the link to be free, takes
``size * 8 / bandwidth`` seconds to transmit, then ``latency`` plus a jitter drawn uniformly in
``[0, jitter]``; arrivals never overtake each other. A message is lost with probability ``loss``.
All four are QoS properties of the connection, read at each send (policies may change them).
Randomness comes from ``clock.rng("shaping", connection name)``: deterministic for the clock's seed.

Notifications and stream items are delivered at their arrival time by a clock timer; a lost one is
counted in ``connection.stats["lost"]``. A synchronous call sleeps (in clock time) for the request and
the reply; if either is lost the caller waits ``timeout`` and gets :class:`ConnectorError`.
"""

from __future__ import annotations

from typing import Any

import serpent

from acordcs.runtime.clock import Clock
from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.connectors.inprocess import InProcessConnector
from acordcs.runtime.errors import ConnectorError


def size_of(obj: Any) -> int:
    """Bytes a message takes on the wire (its serpent encoding unless it is bytes or text)."""
    if isinstance(obj, bytes | bytearray | memoryview):
        return len(obj)
    if isinstance(obj, str):
        return len(obj.encode("utf-8"))
    return len(serpent.dumps(obj))


class ShapedConnector(Connector):
    """Wraps another connector (in-process by default) and shapes what goes through it."""

    kind = "shaped"

    def __init__(
        self,
        clock: Clock,
        inner: Connector | None = None,
        *,
        latency: float = 0.0,
        jitter: float = 0.0,
        bandwidth: float = 0.0,
        loss: float = 0.0,
        timeout: float = 1.0,
    ) -> None:
        self.clock = clock
        self.inner = inner or InProcessConnector()
        self._defaults: dict[str, object] = {
            "latency": latency,
            "jitter": jitter,
            "bandwidth": bandwidth,
            "loss": loss,
            "timeout": timeout,
        }
        _check_qos(self._defaults, "ShapedConnector")
        # Per (connection, direction): when the link is free, and the last arrival (FIFO order).
        self._free: dict[tuple[str, str], float] = {}
        self._last: dict[tuple[str, str], float] = {}

    def default_qos(self) -> dict[str, object]:
        return dict(self._defaults)

    def _arrival(self, conn: Connection, direction: str, size: int) -> float | None:
        """Arrival time of a message sent now, or None if it is lost."""
        q = conn.qos
        _check_qos(q, f"connection {conn.name!r}")
        rng = self.clock.rng("shaping", conn.name)
        # Draw both numbers for every message, so a change of loss or jitter does not shift later draws.
        u_loss, u_jitter = rng.random(), rng.random()
        now = self.clock.now()
        key = (conn.name, direction)
        bandwidth = float(q.get("bandwidth", 0.0) or 0.0)
        tx = size * 8.0 / bandwidth if bandwidth > 0 else 0.0
        start = max(now, self._free.get(key, now))
        self._free[key] = start + tx
        conn.stats["sent"] += 1
        if u_loss < float(q.get("loss", 0.0) or 0.0):
            conn.stats["lost"] += 1
            return None
        latency = float(q.get("latency", 0.0) or 0.0)
        jitter = float(q.get("jitter", 0.0) or 0.0)
        arrival = max(start + tx + latency + jitter * u_jitter, self._last.get(key, now))
        self._last[key] = arrival
        return arrival

    def _send_later(
        self, conn: Connection, target: object, payload: Any, size: int | None, how: str
    ) -> None:
        arrival = self._arrival(conn, "forward", size if size is not None else size_of(payload))
        if arrival is None:
            return
        send = getattr(self.inner, how)
        self.clock.call_at(arrival, lambda: send(conn, target, payload, size))

    def notify(self, conn: Connection, target: object, message: Any, size: int | None) -> None:
        self._send_later(conn, target, message, size, "notify")

    def stream(self, conn: Connection, target: object, item: Any, size: int | None) -> None:
        self._send_later(conn, target, item, size, "stream")

    def call(
        self,
        conn: Connection,
        target: object,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
    ) -> Any:
        timeout = float(conn.qos.get("timeout", 1.0) or 1.0)
        start = self.clock.now()
        arrival = self._arrival(conn, "forward", size_of([operation, list(args), kwargs]))
        if arrival is None:
            self._wait_until(start + timeout)
            raise self._lost(conn, operation, timeout, "request")
        self._wait_until(arrival)
        result = self.inner.call(conn, target, operation, args, kwargs)
        back = self._arrival(conn, "back", size_of(result))
        if back is None:
            self._wait_until(start + timeout)
            raise self._lost(conn, operation, timeout, "reply")
        self._wait_until(back)
        return result

    def _wait_until(self, t: float) -> None:
        delay = t - self.clock.now()
        if delay > 0:
            self.clock.sleep(delay)

    @staticmethod
    def _lost(conn: Connection, operation: str, timeout: float, which: str) -> ConnectorError:
        return ConnectorError(
            f"call {operation}() over connection {conn.name!r} timed out after {timeout:g} s: "
            f"the {which} was lost (shaped link, loss={conn.qos.get('loss')})",
            where=f"connection {conn.name!r}",
            hint="lower the connection's loss or handle ConnectorError in the caller",
        )


def _check_qos(q: dict[str, object], where: str) -> None:
    for key in ("latency", "jitter", "bandwidth", "timeout"):
        value = q.get(key, 0.0)
        if not isinstance(value, int | float) or value < 0:
            raise ConnectorError(f"{where}: QoS {key!r} must be a number >= 0, not {value!r}")
    loss = q.get("loss", 0.0)
    if not isinstance(loss, int | float) or not 0.0 <= loss <= 1.0:
        raise ConnectorError(f"{where}: QoS 'loss' must be a probability in [0, 1], not {loss!r}")
