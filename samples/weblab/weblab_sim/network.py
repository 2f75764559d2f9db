"""The user's access networks (residential, campus, LAN) and the access link they share.

A :class:`Profile` gives the link's connector QoS (``latency`` one way and ``jitter`` in seconds,
``bandwidth`` in bit/s: the names :mod:`acordcs.runtime.connectors.shaping` reads), the WebLab
server's time to grab an on-board frame, and the user's CPU time per control cycle.

All the connections between the user's computer and the WebLab go through one :class:`AccessLink`
(a connector): one uplink (requests) and one downlink (replies, telemetry, the panoramic stream),
each a FIFO that sends a message in ``size * 8 / bandwidth`` seconds and delivers it ``latency``
plus up to ``jitter`` later. The downlink has a drop-tail buffer (:data:`BUFFER_BYTES`): a stream
frame that does not fit is dropped, as a camera server skips frames a slow client cannot take;
replies and notifications always queue. A frame rate the link cannot carry keeps the buffer full,
so every reply waits behind it: this is why the panoramic camera's frame rate matters on the
residential line.

Tuned to the paper's Table 1 (cycle rates 0.90, 1.46, 1.72 per second): the latencies, the server
grab time and the user's CPU time. From the paper: the residential line's 2 Mbit/s. Chosen
beforehand: campus 10 Mbit/s, LAN 100 Mbit/s, the 48 KB buffer.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from acordcs.runtime.api import Clock, Connector, InProcessConnector
from acordcs.runtime.connectors.base import Connection
from acordcs.runtime.connectors.shaping import size_of

BUFFER_BYTES = 48_000


@dataclass(frozen=True)
class Profile:
    """An access network: the link's QoS, the server's grab time and the user's CPU time (s)."""

    name: str
    latency: float
    jitter: float
    bandwidth: float
    grab_time: float = 0.33
    cpu_time: float = 0.25

    def qos(self) -> dict[str, object]:
        """The connector QoS of every connection over this link."""
        return {"latency": self.latency, "jitter": self.jitter, "bandwidth": self.bandwidth}


PROFILES: dict[str, Profile] = {
    "residential": Profile("residential", latency=0.115, jitter=0.02, bandwidth=2e6),
    "campus": Profile("campus", latency=0.025, jitter=0.005, bandwidth=10e6),
    "LAN": Profile("LAN", latency=0.0005, jitter=0.0002, bandwidth=100e6),
}


def profile(name: str) -> Profile:
    try:
        return PROFILES[name]
    except KeyError:
        raise ValueError(f"no network profile {name!r} (profiles: {', '.join(PROFILES)})") from None


class AccessLink(Connector):
    """One user's access link, shared by the connections given to it (see the module docstring).

    The user's side calls and subscribes; the WebLab's side replies and publishes: requests go
    up, everything else comes down. QoS is read from each connection at each send, so a policy
    changing a connection's QoS applies to its next message.
    """

    kind = "access-link"

    def __init__(self, clock: Clock, inner: Connector | None = None) -> None:
        self.clock = clock
        self.inner = inner or InProcessConnector()
        self._free = {"up": 0.0, "down": 0.0}  # when each direction's link is free
        self._last = {"up": 0.0, "down": 0.0}  # the last arrival (FIFO: no overtaking)
        self.dropped_frames = 0
        self.bytes = {"up": 0, "down": 0}

    def _arrival(
        self, conn: Connection, direction: str, size: int, droppable: bool
    ) -> float | None:
        q = conn.qos
        now = self.clock.now()
        bandwidth = float(q.get("bandwidth", 0.0) or 0.0)
        start = max(now, self._free[direction])
        if droppable and bandwidth > 0:
            backlog = (start - now) * bandwidth / 8.0
            if backlog + size > BUFFER_BYTES:
                self.dropped_frames += 1
                return None
        # One draw per message and direction, whatever the message: a deterministic stream.
        u = self.clock.rng("access-link", direction).random()
        tx = size * 8.0 / bandwidth if bandwidth > 0 else 0.0
        self._free[direction] = start + tx
        self.bytes[direction] += size
        latency = float(q.get("latency", 0.0) or 0.0) + float(q.get("jitter", 0.0) or 0.0) * u
        arrival = max(start + tx + latency, self._last[direction])
        self._last[direction] = arrival
        return arrival

    def _wait_until(self, t: float) -> None:
        delay = t - self.clock.now()
        if delay > 0:
            self.clock.sleep(delay)

    def call(
        self,
        conn: Connection,
        target: object,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
    ) -> Any:
        request = size_of([operation, list(args), kwargs])
        conn.stats["sent"] += 1  # (the inner connector counts notifications and stream items)
        self._wait_until(self._arrival(conn, "up", request, False) or 0.0)
        result = self.inner.call(conn, target, operation, args, kwargs)
        self._wait_until(self._arrival(conn, "down", size_of(result), False) or 0.0)
        return result

    def _later(
        self, conn: Connection, target: object, payload: Any, size: int | None, how: str
    ) -> None:
        size = size if size is not None else size_of(payload)
        arrival = self._arrival(conn, "down", size, how == "stream")
        if arrival is None:
            conn.stats["lost"] += 1
            return
        send = getattr(self.inner, how)
        self.clock.call_at(arrival, lambda: send(conn, target, payload, size))

    def notify(self, conn: Connection, target: object, message: Any, size: int | None) -> None:
        self._later(conn, target, message, size, "notify")

    def stream(self, conn: Connection, target: object, item: Any, size: int | None) -> None:
        self._later(conn, target, item, size, "stream")
