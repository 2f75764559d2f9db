"""The container's element namespace: properties of components, ports, connections, monitors and the
container itself, and the port connections between them.

Element names: a component (``Camera``), one of its ports (``Camera.frames``), a connection (its
name), a monitor, or the container. A property change goes through :meth:`Wiring.set_property`, which
emits ``property.changed`` (only when the value really changes, so an idempotent action cannot loop).
"""

from __future__ import annotations

import functools
import threading
from collections import Counter
from collections.abc import Callable
from contextlib import AbstractContextManager
from typing import TYPE_CHECKING, Any

from acordcs.runtime import events as ev
from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.connectors.inprocess import InProcessConnector
from acordcs.runtime.connectors.remote import RemotePort
from acordcs.runtime.errors import BindingError, ComponentNotFoundError, PortError
from acordcs.runtime.ports import Port

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock
    from acordcs.runtime.component import Hosted
    from acordcs.runtime.events import FaultLog
    from acordcs.runtime.monitor import Monitor


class Wiring:
    """The element namespace and the connections of a container.

    Mixed into :class:`~acordcs.runtime.container.Container`, which keeps the attributes declared
    below and provides ``_hosted(name)``, ``guard`` and ``emit``.
    """

    name: str
    clock: Clock
    faults: FaultLog
    properties: dict[str, object]
    stats: Counter[str]
    guard: Callable[..., AbstractContextManager[None]]
    _where: str
    _lock: threading.RLock
    _components: dict[str, Hosted]
    _monitors: dict[str, Monitor]

    def __init__(self) -> None:
        self._connections: dict[str, Connection] = {}
        self._connectors: list[Connector] = []

    # ------------------------------------------------------------------------------ elements
    def _properties_of(self, element: str) -> tuple[str, dict[str, object], object]:
        """(kind, property dict, owner) of an element name."""
        hosted = self._components.get(element)
        if hosted is not None:
            return "component", hosted.instance.props, hosted.instance
        conn = self._connections.get(element)
        if conn is not None:
            return "connection", conn.qos, conn
        monitor = self._monitors.get(element)
        if monitor is not None:
            return "monitor", monitor.attributes, monitor
        if element == self.name:
            return "container", self.properties, self
        comp, dot, port_name = element.rpartition(".")
        if dot and comp in self._components:
            port = self._components[comp].instance.port_map.get(port_name)
            if port is not None:
                return "port", port.properties, port
        raise ComponentNotFoundError(
            f"no element named {element!r} (a component, 'Component.port', connection, monitor "
            "or this container)",
            where=self._where,
        )

    def _no_attribute(self, element: str, attribute: str, props: dict[str, object]) -> BindingError:
        return BindingError(
            f"element {element!r} has no property {attribute!r} (properties: "
            f"{', '.join(sorted(props)) or 'none'})",
            where=self._where,
            hint="declare it (CtxComponent.properties, Monitor attributes, connection qos)",
        )

    def has_property(self, element: str, attribute: str) -> bool:
        try:
            return attribute in self._properties_of(element)[1]
        except ComponentNotFoundError:
            return False

    def get_property(self, element: str, attribute: str) -> object:
        _kind, props, _owner = self._properties_of(element)
        try:
            return props[attribute]
        except KeyError:
            raise self._no_attribute(element, attribute, props) from None

    def set_property(self, element: str, attribute: str, value: object) -> None:
        """Change a property; emits ``property.changed`` when the value differs."""
        kind, props, owner = self._properties_of(element)
        if attribute not in props:
            raise self._no_attribute(element, attribute, props)
        old = props[attribute]
        if old == value and type(old) is type(value):
            return
        if (kind == "port" and attribute in ("rate", "capacity")) and (
            not isinstance(value, int | float) or value < (0 if attribute == "rate" else 1)
        ):
            raise PortError(
                f"port {element}: {attribute} must be a number >= "
                f"{0 if attribute == 'rate' else 1}, not {value!r}",
                where=self._where,
            )
        props[attribute] = value
        if kind == "port" and attribute == "rate":
            assert isinstance(owner, Port)
            owner.restart_stream()
        self.stats["property_changes"] += 1
        self.emit(ev.PROPERTY_CHANGED, element, attribute, value=value, old=old)
        if kind == "component":
            # The component's own hook, after everyone subscribed has seen the change; a hook that
            # raises is a fault of the component, never of whoever set the property.
            with self.guard("component", f"{element}.on_property_changed", attribute=attribute):
                owner.on_property_changed(attribute, old, value)  # type: ignore[union-attr]

    def elements(self) -> dict[str, dict[str, object]]:
        """Every element name with its properties (policy variable resolution reads this)."""
        out: dict[str, dict[str, object]] = {self.name: self.properties}
        for name, hosted in self._components.items():
            out[name] = hosted.instance.props
            for port in hosted.instance.port_map.values():
                out[port.qualified_name] = port.properties
        for name, conn in self._connections.items():
            out[name] = conn.qos
        for name, monitor in self._monitors.items():
            out[name] = monitor.attributes
        return out

    # --------------------------------------------------------------------------- connections
    def port_of(self, component: str, port: str) -> Port:
        return self._hosted(component).instance.port(port)

    def _endpoint(self, end: str | Port | RemotePort) -> Port | RemotePort:
        if isinstance(end, Port | RemotePort):
            return end
        comp, dot, port = end.rpartition(".")
        if not dot:
            raise PortError(f"a port is named 'Component.port', not {end!r}", where=self._where)
        return self.port_of(comp, port)

    def connect(
        self,
        required: str | Port | RemotePort,
        provided: str | Port | RemotePort,
        *,
        connector: Connector | None = None,
        name: str | None = None,
        qos: dict[str, object] | None = None,
    ) -> Connection:
        """Connect two complementary ports (``"Comp.port"`` strings, or a :class:`RemotePort`)."""
        a, b = self._endpoint(required), self._endpoint(provided)
        if isinstance(a, RemotePort) and isinstance(b, RemotePort):
            raise PortError(
                "at least one end of a connection must be a port of this container",
                where=self._where,
            )
        if isinstance(a, Port) and isinstance(b, Port):
            if a.kind != b.kind:
                raise PortError(
                    f"cannot connect {a.qualified_name} ({a.kind}) to {b.qualified_name} ({b.kind})",
                    where=self._where,
                    hint="connected ports must be of the same kind",
                )
            if a.role == b.role:
                raise PortError(
                    f"cannot connect {a.qualified_name} to {b.qualified_name}: both are {a.role}",
                    where=self._where,
                    hint="connect a required port to a provided port",
                )
            if a.role == "provided":
                a, b = b, a
        for end in (a, b):
            if (
                isinstance(end, Port)
                and end.kind == "synchronous"
                and end.role == "required"
                and end.connections
            ):
                raise PortError(
                    f"synchronous required port {end.qualified_name} is already connected",
                    where=self._where,
                    hint="disconnect it first: a request-reply port has one provider",
                )
        connector = connector or InProcessConnector()
        label = name or f"{_label(a)}->{_label(b)}"
        with self._lock:
            if label in self._connections:
                raise PortError(f"a connection named {label!r} already exists", where=self._where)
            conn = Connection(label, a, b, connector, {**connector.default_qos(), **(qos or {})})
            conn.on_fault = functools.partial(self._connection_fault, label)
            for end in (a, b):
                if isinstance(end, Port):
                    end.connections.append(conn)
            self._connections[label] = conn
            if connector not in self._connectors:
                self._connectors.append(connector)
        self.emit(ev.CONNECTION_CHANGED, label, value="connected")
        return conn

    def disconnect(self, name: str) -> None:
        with self._lock:
            conn = self._connections.pop(name, None)
            if conn is None:
                raise PortError(
                    f"no connection named {name!r} (connections: {', '.join(self._connections) or 'none'})",
                    where=self._where,
                )
            for end in conn.ends():
                if isinstance(end, Port) and conn in end.connections:
                    end.connections.remove(conn)
        self.emit(ev.CONNECTION_CHANGED, name, value="disconnected")

    def connections(self) -> list[Connection]:
        return list(self._connections.values())

    def connection(self, name: str) -> Connection:
        try:
            return self._connections[name]
        except KeyError:
            raise PortError(f"no connection named {name!r}", where=self._where) from None

    def _drop_connections_of(self, instance: Any) -> None:
        for port in instance.port_map.values():
            for conn in list(port.connections):
                if conn.name in self._connections:
                    self.disconnect(conn.name)

    def _connection_fault(self, label: str, error: BaseException | str) -> None:
        self.faults.record("connection", label, error, self.clock.now())

    def close_connectors(self) -> None:
        for connector in self._connectors:
            with self.guard("connector", type(connector).__name__, phase="close"):
                connector.close()
        self._connectors.clear()


def _label(end: Port | RemotePort) -> str:
    return end.qualified_name
