"""Build running containers from an ACORD-CS model (a pyecore ``Application``).

Each ``CtxContainer`` of the model becomes a :class:`Container` (all sharing one clock); a model with
no container gets one named after the application. Components are created from the factories given
by component name; a component without one gets a generic class made from the model (its attributes
as properties, its ports), which runs but has no operations. Monitors likewise (a generic
:class:`Monitor` is fed from outside with ``update``). Connections get the connector of their
``connector`` tag, their attributes as QoS properties; an end in a container not built here must be
given as ``remote={container name: uri}``. Policy sets get their engine by the ``engine`` tag, their
linguistic variables from the attributes' ``CtxVariable`` s.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from typing import Any

from acordcs.runtime.clock import Clock, VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors import (
    InProcessConnector,
    RemoteConnector,
    RemotePort,
    ShapedConnector,
)
from acordcs.runtime.connectors.base import Connector
from acordcs.runtime.container import Container
from acordcs.runtime.errors import BindingError, ConfigurationError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.policy import PolicySet
from acordcs.runtime.ports import Port, PortSpec
from acordcs.runtime.registry import Variable

MonitorMaker = Callable[..., Monitor]
_FCL = {
    "trapezoid": "trape",
    "triangle": "trian",
    "gaussian": "gauss",
    "bell": "gbell",
    "sigmoid": "sigm",
}


class RunningApplication:
    """The containers built from one model; ``close()`` stops them all."""

    def __init__(self, name: str, clock: Clock, containers: dict[str, Container]) -> None:
        self.name = name
        self.clock = clock
        self.containers = containers

    def container(self, name: str | None = None) -> Container:
        if name is None:
            return next(iter(self.containers.values()))
        try:
            return self.containers[name]
        except KeyError:
            raise BindingError(
                f"application {self.name!r} has no container {name!r} here "
                f"(built: {', '.join(self.containers)})"
            ) from None

    def close(self) -> None:
        for container in self.containers.values():
            container.close()
        self.clock.close()

    def __enter__(self) -> RunningApplication:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def attribute_default(attr: Any) -> object:
    """An Attribute's default value, typed by its UML type name."""
    try:
        return _typed_default(attr)
    except ValueError:
        owner = attr.eContainer()
        raise ConfigurationError(
            f"attribute {getattr(owner, 'name', '?')}.{attr.name}: default {attr.defaultValue!r} "
            f"is not of type {attr.type!r}",
            hint="fix the attribute's default value or its type in the model",
        ) from None


def _typed_default(attr: Any) -> object:
    kind = (attr.type or "").lower()
    text = attr.defaultValue
    var = attr.variable
    if kind in ("int", "integer", "long", "short"):
        return int(float(text)) if text not in (None, "") else int(var.rangeMin or 0) if var else 0
    if kind in ("double", "float", "real", "number") or var is not None:
        return float(text) if text not in (None, "") else float(var.rangeMin or 0.0) if var else 0.0
    if kind in ("bool", "boolean"):
        return str(text).strip().lower() in ("true", "1", "yes")
    return text if text is not None else ""


def terms_text(variable: Any) -> str:
    """A CtxVariable's terms, FCL style (``slow := trape 0 0 40 80; ...``)."""
    parts = []
    for term in variable.terms:
        shape = term.shape.name
        params = [f"{p:g}" for p in term.parameters]
        if shape == "points":
            body = " ".join(f"({params[i]}, {params[i + 1]})" for i in range(0, len(params) - 1, 2))
        elif shape == "singleton":
            body = params[0]
        else:
            body = f"{_FCL[shape]} {' '.join(params)}"
        parts.append(f"{term.name} := {body}")
    return "; ".join(parts)


def generic_component(model: Any) -> type[CtxComponent]:
    """A component class from a model CtxComponent: properties and ports, no operations."""
    props = {a.name: attribute_default(a) for a in model.attributes}
    ports = tuple(PortSpec(p.name, p.kind.name, p.role.name) for p in model.ports)
    return type(model.name, (CtxComponent,), {"properties": props, "ports": ports})


def build_application(
    model: Any,
    *,
    factories: Mapping[str, type[CtxComponent] | ComponentFactory] | None = None,
    monitors: Mapping[str, MonitorMaker] | None = None,
    clock: Clock | None = None,
    only: Iterable[str] | None = None,
    remote: Mapping[str, str] | None = None,
    remote_timeout: float = 5.0,
) -> RunningApplication:
    """Build the containers of ``model`` (all, or those named in ``only``) on one clock
    (default: a :class:`VirtualClock` with seed 0)."""
    clock = clock or VirtualClock()
    factories = dict(factories or {})
    monitors = dict(monitors or {})
    remote = dict(remote or {})
    wanted = set(only) if only is not None else None
    placed: dict[int, str] = {}  # id(model element) -> container name
    containers: dict[str, Container] = {}
    model_containers = list(model.containers)
    for mc in model_containers:
        for element in [*mc.components, *mc.monitors, *mc.policySets]:
            placed[id(element)] = mc.name
        if wanted is None or mc.name in wanted:
            props = {a.name: attribute_default(a) for a in mc.attributes}
            containers[mc.name] = Container(mc.name, clock=clock, properties=props)
    if not model_containers:
        containers[model.name] = Container(model.name, clock=clock)
    default = model_containers[0].name if model_containers else model.name

    def home(element: Any) -> Container | None:
        return containers.get(placed.get(id(element), default))

    variables: dict[str, Variable] = {}
    for comp in model.components:
        target = home(comp)
        if target is None:
            continue
        given = factories.get(comp.name) or generic_component(comp)
        factory = (
            given if isinstance(given, ComponentFactory) else ComponentFactory(comp.name, given)
        )
        target.install_factory(factory)
        target.create(factory.type_name, comp.name)
        _collect_variables(variables, comp.name, comp.attributes)
        for port in comp.ports:
            _collect_variables(variables, f"{comp.name}.{port.name}", port.attributes)
    for mon in model.monitors:
        target = home(mon)
        if target is None:
            continue
        attrs = {a.name: attribute_default(a) for a in mon.attributes}
        freq = mon.frequency if mon.eIsSet("frequency") else None
        maker = monitors.get(mon.name, Monitor)
        sources = [_element_name(s) for s in mon.sources]
        target.add_monitor(maker(mon.name, frequency=freq, sources=sources, attributes=attrs))
        _collect_variables(variables, mon.name, mon.attributes)
    for conn in model.connections:
        _connect(conn, containers, placed, default, remote, clock, remote_timeout, variables)
    for ps in model.policySets:
        target = home(ps)
        if target is None:
            continue
        fed_by = [m.name for m in model.monitors if ps in m.feeds and home(m) is target]
        policies = {
            p.name: [f"{r.label}: {r.text}" if r.label else r.text for r in p.rules]
            for p in ps.policies
        }
        target.add_policy_set(
            PolicySet(
                ps.name,
                policies,
                engine=ps.engine.name,
                trigger=ps.trigger.name,
                frequency=ps.frequency if ps.eIsSet("frequency") else None,
                semantics=ps.semantics.name,
                adapts=[_element_name(a) for a in ps.adapts],
                fed_by=fed_by,
                variables=variables,
            )
        )
    return RunningApplication(model.name, clock, containers)


def _collect_variables(out: dict[str, Variable], element: str, attributes: Iterable[Any]) -> None:
    for attr in attributes:
        var = attr.variable
        if var is not None:
            out[f"{element}.{attr.name}"] = Variable(
                var.rangeMin or 0.0, var.rangeMax or 0.0, terms_text(var)
            )


def _element_name(element: Any) -> str:
    owner = element.eContainer()
    if element.eClass.name == "CtxPort" and owner is not None:
        return f"{owner.name}.{element.name}"
    return element.name


def _connect(
    conn: Any,
    containers: dict[str, Container],
    placed: dict[int, str],
    default: str,
    remote: dict[str, str],
    clock: Clock,
    timeout: float,
    variables: dict[str, Variable],
) -> None:
    if conn.provided is None or conn.required is None:
        raise BindingError(
            f"connection {conn.name!r} needs a provided and a required port in the model"
        )
    ends = []
    for port in (conn.required, conn.provided):
        owner = port.eContainer()
        where = placed.get(id(owner), default)
        ends.append((where, owner.name, port.name))
    local = [e for e in ends if e[0] in containers]
    if not local:
        return
    host = containers[local[0][0]]
    qos = {a.name: attribute_default(a) for a in conn.attributes}
    _collect_variables(variables, conn.name, conn.attributes)
    resolved: list[Port | RemotePort] = []
    for where, comp, port in ends:
        if where in containers:
            resolved.append(containers[where].port_of(comp, port))
        elif where in remote:
            resolved.append(RemotePort(remote[where], comp, port))
        else:
            raise BindingError(
                f"connection {conn.name!r}: {comp}.{port} is in container {where!r}, not built here",
                hint=f"pass remote={{{where!r}: uri}} to build_application",
            )
    kind = conn.connector.name
    connector: Connector
    if kind == "remote":
        connector = RemoteConnector(timeout=timeout)
    elif kind == "shaped":
        connector = ShapedConnector(clock)
    else:
        connector = InProcessConnector()
    host.connect(resolved[0], resolved[1], connector=connector, name=conn.name, qos=qos)
