"""Ports: a component's endpoints, of the three RM-ODP interaction kinds (paper, section 2).

- ``synchronous`` (request-reply): a *required* port calls operations of the component owning the
  *provided* port it is connected to, and waits for the result.
- ``asynchronous`` (notification): ``notify(message)`` sends to every connected peer; a receiving port
  keeps messages in a bounded queue. Overflow policy (stated per port): ``drop_oldest`` (default: the
  newest context wins), ``drop_newest``, or ``reject`` (the sender gets :class:`QueueFullError`). Drops
  are counted in ``port.dropped``. A receiver with a handler method gets messages pumped through the
  container (intercepted like any call); without one, it polls with :meth:`Port.take`.
- ``stream`` (flow): the *provided* port produces, the *required* port consumes. A producer with a
  ``source`` method is ticked at its ``rate`` (Hz, a port property policies can change; 0 pauses).

A connection joins two ports through a connector; a port may have several connections (fan-out),
except a synchronous required port, which has exactly one provider.

A port knows its component and its container only through what it needs of them (:class:`PortOwner`,
:class:`PortHost`), so this module depends on neither.
"""

from __future__ import annotations

import contextlib
from collections import deque
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from acordcs.runtime.errors import ComponentError, PortError, QueueFullError
from acordcs.vocabularies import PORT_KINDS, PORT_ROLES

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock, Timer
    from acordcs.runtime.connectors.base import Connection

KINDS = PORT_KINDS  # the metamodel's PortKind and PortRole
ROLES = PORT_ROLES
OVERFLOW_POLICIES = ("drop_oldest", "drop_newest", "reject")


class PortHost(Protocol):
    """What a port (and a connector delivering to it) needs from its component's container."""

    name: str
    clock: Clock

    def invoke_internal(
        self, instance: PortOwner, method: str, args: tuple[Any, ...], port: Port
    ) -> Any:
        """Deliver into the component (a notification handler, a stream source or sink)."""
        ...

    def invoke_port(
        self, port: Port, operation: str, args: tuple[Any, ...], kwargs: dict[str, Any]
    ) -> Any:
        """A call arriving at a synchronous provided port."""
        ...


class PortOwner(Protocol):
    """What a port needs from its component (a hosted :class:`~acordcs.runtime.component.CtxComponent`)."""

    name: str
    alive: bool
    container: PortHost


@dataclass(frozen=True)
class PortSpec:
    """Declaration of a port on a component class (``ports = (PortSpec(...), ...)``).

    ``handler``: method receiving notifications or stream items (default ``on_<name>`` if it exists).
    ``source``: method a stream producer calls at each tick to get the next item.
    ``operations``: for a synchronous provided port, the operations it exposes (None: all).
    """

    name: str
    kind: str = "synchronous"
    role: str = "provided"
    capacity: int = 64
    overflow: str = "drop_oldest"
    rate: float = 0.0
    handler: str | None = None
    source: str | None = None
    operations: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise PortError(
                f"port {self.name!r}: kind {self.kind!r} is not one of {', '.join(KINDS)}"
            )
        if self.role not in ROLES:
            raise PortError(
                f"port {self.name!r}: role {self.role!r} is not one of {', '.join(ROLES)}"
            )
        if self.overflow not in OVERFLOW_POLICIES:
            raise PortError(
                f"port {self.name!r}: overflow {self.overflow!r} is not one of "
                f"{', '.join(OVERFLOW_POLICIES)}"
            )
        if self.capacity < 1:
            raise PortError(f"port {self.name!r}: capacity must be >= 1, not {self.capacity}")
        if self.rate < 0:
            raise PortError(f"port {self.name!r}: rate must be >= 0 Hz, not {self.rate}")


class Port:
    """A port of one component instance. Its properties (``rate``, ``capacity``, ``overflow``, plus any
    the spec's component adds) are adapted through ``container.set_property("Comp.port", ...)``."""

    def __init__(self, component: PortOwner, spec: PortSpec) -> None:
        self.component = component
        self.spec = spec
        self.name = spec.name
        self.kind = spec.kind
        self.role = spec.role
        self.connections: list[Connection] = []
        self.properties: dict[str, object] = {
            "rate": float(spec.rate),
            "capacity": spec.capacity,
            "overflow": spec.overflow,
        }
        self.queue: deque[Any] = deque()
        self.dropped = 0
        self.received = 0
        self._pump_timer: Timer | None = None
        self._tick_timer: Timer | None = None
        handler = spec.handler or f"on_{spec.name}"
        self.handler = handler if callable(getattr(component, handler, None)) else None
        if spec.handler and self.handler is None:
            raise PortError(
                f"port {spec.name!r} of {type(component).__name__}: handler {spec.handler!r} "
                "is not a method of the component",
                hint="define the method or fix PortSpec.handler",
            )

    @property
    def qualified_name(self) -> str:
        return f"{self.component.name}.{self.name}"

    def __repr__(self) -> str:
        return f"<Port {self.qualified_name} {self.kind}/{self.role}>"

    # ---------------------------------------------------------------------------------- sending
    def call(self, operation: str, *args: Any, **kwargs: Any) -> Any:
        """Request-reply through the one connection of a synchronous required port."""
        self._expect("synchronous", "required", "call")
        if not self.connections:
            raise self._unconnected("call")
        conn = self.connections[0]
        return conn.connector.call(conn, conn.peer_of(self), operation, args, kwargs)

    def notify(self, message: Any, *, size: int | None = None) -> None:
        """Send a notification to every connected peer (no reply)."""
        if self.kind != "asynchronous":
            raise self._wrong_kind("notify", "asynchronous")
        if not self.connections:
            raise self._unconnected("notify")
        for conn in list(self.connections):
            conn.connector.notify(conn, conn.peer_of(self), message, size)

    def push(self, item: Any, *, size: int | None = None) -> None:
        """Send one stream item to every connected consumer (unconnected: the item is dropped)."""
        self._expect("stream", "provided", "push")
        for conn in list(self.connections):
            conn.connector.stream(conn, conn.peer_of(self), item, size)

    # -------------------------------------------------------------------------------- receiving
    def deliver(self, message: Any) -> None:
        """A notification or stream item arrives at this port (called by connectors)."""
        container = self.component.container
        if self.kind == "stream":
            self.received += 1
            if self.handler is not None:
                # A raising consumer is recorded as a component fault; the producer goes on.
                with contextlib.suppress(ComponentError):
                    container.invoke_internal(self.component, self.handler, (message,), self)
            else:
                self._enqueue(message)
            return
        self._enqueue(message)
        if self.handler is not None and self._pump_timer is None:
            # Delivery is decoupled from the sender: the queue is pumped by the clock, so a slow or
            # raising receiver never runs inside the sender's call.
            self._pump_timer = container.clock.call_later(0.0, self._pump)

    def take(self) -> Any:
        """The oldest queued message, or None when the queue is empty."""
        return self.queue.popleft() if self.queue else None

    def pending(self) -> int:
        return len(self.queue)

    def _enqueue(self, message: Any) -> None:
        capacity = int(self.properties["capacity"])  # type: ignore[call-overload]
        if len(self.queue) >= capacity:
            policy = self.properties["overflow"]
            if policy == "reject":
                self.dropped += 1
                raise QueueFullError(
                    f"queue of port {self.qualified_name} is full ({capacity} messages)",
                    where=f"container {self.component.container.name!r}",
                    hint="slow down the sender, raise the port's capacity or use drop_oldest",
                )
            self.dropped += 1
            if policy == "drop_newest":
                return
            self.queue.popleft()
        self.queue.append(message)
        self.received += 1

    def _pump(self) -> None:
        self._pump_timer = None
        container = self.component.container
        while self.queue and self.component.alive:
            message = self.queue.popleft()
            # A raising handler is recorded as a component fault by invoke_internal; later
            # messages are still delivered.
            try:
                container.invoke_internal(self.component, self.handler, (message,), self)
            except ComponentError:
                continue

    # ----------------------------------------------------------------------------------- stream
    def restart_stream(self) -> None:
        """(Re)schedule the producer tick after a rate change; rate 0 pauses the stream."""
        if self._tick_timer is not None:
            self._tick_timer.cancel()
            self._tick_timer = None
        rate = float(self.properties["rate"])  # type: ignore[arg-type]
        if self.kind != "stream" or self.role != "provided" or not self.spec.source or rate <= 0:
            return
        self._tick_timer = self.component.container.clock.call_every(1.0 / rate, self._tick)

    def _tick(self) -> None:
        if not self.component.alive:
            return
        try:
            item = self.component.container.invoke_internal(
                self.component, self.spec.source, (), self
            )
        except ComponentError:
            return
        if item is not None:
            self.push(item)

    def stop(self) -> None:
        for timer in (self._tick_timer, self._pump_timer):
            if timer is not None:
                timer.cancel()
        self._tick_timer = self._pump_timer = None

    # ----------------------------------------------------------------------------------- errors
    def _expect(self, kind: str, role: str, what: str) -> None:
        if self.kind != kind:
            raise self._wrong_kind(what, kind)
        if self.role != role:
            raise PortError(
                f"{what}() needs a port of role {role}; {self.qualified_name} is {self.role}",
                where=f"container {self.component.container.name!r}",
            )

    def _wrong_kind(self, what: str, kind: str) -> PortError:
        return PortError(
            f"{what}() needs a port of kind {kind}; {self.qualified_name} is {self.kind}",
            where=f"container {self.component.container.name!r}",
        )

    def _unconnected(self, what: str) -> PortError:
        return PortError(
            f"{what}() on port {self.qualified_name}, which is not connected",
            where=f"container {self.component.container.name!r}",
            hint="connect it first: container.connect(required, provided)",
        )


def sync_port(name: str, role: str = "provided", **kw: Any) -> PortSpec:
    return PortSpec(name, "synchronous", role, **kw)


def async_port(name: str, role: str = "provided", **kw: Any) -> PortSpec:
    return PortSpec(name, "asynchronous", role, **kw)


def stream_port(name: str, role: str = "provided", **kw: Any) -> PortSpec:
    return PortSpec(name, "stream", role, **kw)
