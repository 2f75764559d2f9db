"""The application descriptor as plain data: frozen, slotted dataclasses of strings, numbers and tuples.

What a running ACORD-CS application is made of, with every name resolved: containers (host, remote
endpoint, what each hosts), components (typed properties with their defaults, ports, operations),
connections (connector, the two ends as component and port names, QoS properties), monitors
(frequency, how they acquire context, sources, the policy sets they feed), policy sets (engine,
semantics, trigger, period, policies and their rules, adapted elements, linguistic variables).

Every element that comes from a UML element carries its ``id`` (the xmi:id, stable across exports)
and its ``qualified_name`` (``Model::Package::Class``) for traceability. Lists of elements are in a
deterministic order (see :func:`acordcs.generator.describe.describe`). Nothing here refers to the UML view,
the architecture index or pyecore: a descriptor is written to and read from XML
(:mod:`acordcs.descriptor.xml`) without loss, and ``assemble`` builds running containers from it.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from typing import Any

from acordcs.errors import AcordError
from acordcs.typed_values import Value

KINDS = ("int", "double", "bool", "string")
"""How a property's UML type is read (see :func:`acordcs.typed_values.typed_default`)."""

ELEMENT_KINDS = ("container", "component", "port", "connection", "monitor", "policy-set")


class DescriptorError(AcordError):
    """A model that cannot be described (a default that does not fit its type, a connection
    without two ends), a descriptor that cannot be written (a string XML 1.0 cannot hold), or a
    descriptor document that is not well-formed or does not validate against the schema.

    Carries ``file``, ``line`` and ``column`` where known, and a ``hint`` saying what to fix.
    """

    exit_code = 2


@dataclass(frozen=True, slots=True)
class Property:
    """An attribute of an element: a component or container property, a port property, a QoS
    property of a connection, a monitor's context attribute. ``type`` is the UML type as written
    (``""`` when untyped); ``kind`` says how ``default`` is typed (one of :data:`KINDS`)."""

    id: str
    name: str
    qualified_name: str
    type: str
    kind: str
    default: Value
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Parameter:
    """An input parameter of an operation; ``direction`` is ``in``, ``out`` or ``inout``."""

    id: str
    name: str
    type: str
    direction: str = "in"


@dataclass(frozen=True, slots=True)
class Operation:
    """An operation (an action a crisp rule may call); parameters in declaration order,
    ``return_type`` None for none."""

    id: str
    name: str
    qualified_name: str
    parameters: tuple[Parameter, ...] = ()
    return_type: str | None = None
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Ref:
    """A resolved reference to another element: its kind (one of :data:`ELEMENT_KINDS`), its
    name (a port as ``Component.Port``) and its id."""

    kind: str
    name: str
    id: str


@dataclass(frozen=True, slots=True)
class Port:
    """A port of a component: ``kind`` synchronous, asynchronous or stream; ``role`` provided or
    required."""

    id: str
    name: str
    qualified_name: str
    kind: str
    role: str
    properties: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Component:
    id: str
    name: str
    qualified_name: str
    language: str
    properties: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    ports: tuple[Port, ...] = ()
    documentation: str = ""

    def port(self, name: str) -> Port | None:
        return next((p for p in self.ports if p.name == name), None)


@dataclass(frozen=True, slots=True)
class Endpoint:
    """Where a container is reached by remote connectors: a Pyro5 object on the container's host.

    The TCP port is not in the model: the container's server picks it when it starts (or the
    deployment sets it), so the URI is made with :meth:`uri` once it is known.
    """

    protocol: str
    object_name: str
    host: str
    port: int | None = None  # the model's tag port; None: chosen at deployment

    def uri(self, port: int) -> str:
        """The URI the container's server publishes on ``port``."""
        return f"PYRO:{self.object_name}@{self.host}:{port}"


@dataclass(frozen=True, slots=True)
class Container:
    """A container, the host it runs on, its remote endpoint (None when no remote connection
    reaches it), the components, monitors and policy sets it hosts (``hosts``) and ``reaches``:
    the names of the other containers its process must be given the address of (``--remote``;
    :func:`acordcs.runtime.assembly.assemble` refuses to build it without them): those across a
    connection whose required end it hosts, those calling one of its ports that is not
    synchronous, and those hosting the policy sets its monitors feed; in the order of
    :attr:`Application.containers`."""

    id: str
    name: str
    qualified_name: str
    host: str
    endpoint: Endpoint | None = None
    hosts: tuple[Ref, ...] = ()
    properties: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    documentation: str = ""
    reaches: tuple[str, ...] = ()

    def hosted(self, kind: str) -> tuple[str, ...]:
        """Names of the hosted elements of ``kind`` (component, monitor, policy-set)."""
        return tuple(r.name for r in self.hosts if r.kind == kind)


@dataclass(frozen=True, slots=True)
class End:
    """One end of a connection: a port of a component, by names, and the port's id."""

    component: str
    port: str
    id: str


@dataclass(frozen=True, slots=True)
class Connection:
    """A port connection from a required port to a provided one, realised by ``connector``
    (inprocess, remote, shaped); ``qos`` are its attributes, which policies may adapt."""

    id: str
    name: str
    qualified_name: str
    connector: str
    required: End
    provided: End
    qos: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Monitor:
    """A monitor. ``acquisition`` says how it acquires context: ``intercept`` (the calls through its
    source port, or to its source component, and that component's property changes), ``subscribe``
    (the context provider's documents ``xpath`` selects something in), ``poll`` (its source
    component's ``operation`` called at ``frequency`` Hz) or ``custom`` (its own code: ``acquire``
    at ``frequency`` Hz when one is set). ``feeds`` are the policy sets its ``properties`` (the
    context attributes) feed."""

    id: str
    name: str
    qualified_name: str
    frequency: float | None
    acquisition: str
    xpath: str | None = None
    operation: str | None = None
    sources: tuple[Ref, ...] = ()
    feeds: tuple[Ref, ...] = ()
    properties: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Rule:
    """One rule: its ``label`` (as written, or when the model wrote none, ``assigned_label`` and
    the default label ``rule<n>``, n its position: :func:`acordcs.rules.binding.default_label`),
    its text without the label, the tag it was read from (``Rule`` or another tag starting with
    ``Rule``) and its ``priority``, its 1-based rank in its policy: a crisp engine tries the
    rules in that order (CLIPS salience 9999 for the first, 9998 for the next...)."""

    label: str
    text: str
    tag: str
    priority: int = 1
    assigned_label: bool = False

    @property
    def line(self) -> str:
        """The rule as an engine's ``defrule`` takes it: ``label: text``."""
        return f"{self.label}: {self.text}"


@dataclass(frozen=True, slots=True)
class Policy:
    id: str
    name: str
    qualified_name: str
    rules: tuple[Rule, ...] = ()
    documentation: str = ""


@dataclass(frozen=True, slots=True)
class Term:
    """A linguistic term: ``shape`` as the metamodel names it (trapezoid, triangle, gaussian, bell,
    sigmoid, points, singleton), parameters in FCL order (points: x1 y1 x2 y2 ...)."""

    name: str
    shape: str
    parameters: tuple[float, ...]

    @property
    def fcl(self) -> str:
        """The term's definition as the rule language and FCL write it (``trian 30 70 110``)."""
        params = [_number(p) for p in self.parameters]
        if self.shape == "points":
            return " ".join(f"({params[i]}, {params[i + 1]})" for i in range(0, len(params) - 1, 2))
        if self.shape == "singleton":
            return params[0] if params else ""
        return f"{_FCL[self.shape]} {' '.join(params)}"


_FCL = {
    "trapezoid": "trape",
    "triangle": "trian",
    "gaussian": "gauss",
    "bell": "gbell",
    "sigmoid": "sigm",
}


def _number(value: float) -> str:
    return f"{value:g}" if value == float(f"{value:g}") else repr(value)


@dataclass(frozen=True, slots=True)
class Variable:
    """A linguistic variable (a ``CtxVariable`` attribute) in a policy set's scope: the element
    that has it (``element``, a port as ``Component.Port``), the attribute's name, its universe
    [``minimum``, ``maximum``] and its terms. ``id`` is the attribute's."""

    id: str
    element: str
    attribute: str
    qualified_name: str
    minimum: float
    maximum: float
    terms: tuple[Term, ...] = ()

    @property
    def name(self) -> str:
        """``Element.attribute``, as engines bind the variable."""
        return f"{self.element}.{self.attribute}"

    @property
    def terms_text(self) -> str:
        """All terms, FCL style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``."""
        return "; ".join(f"{t.name} := {t.fcl}" for t in self.terms)


@dataclass(frozen=True, slots=True)
class Bound:
    """A name the policy set's rules write, resolved (by :func:`acordcs.rules.binding.bind`):
    ``kind`` ``attribute`` (a variable of the engine, named ``target``: ``element.member``) or
    ``operation``; the element's name in the application (a port as ``Component.Port``), the
    member's name and ``id``; ``names``, every way the rules write it (``cycleRate``,
    ``Control.cycleRate``). An attribute carries its typing (``value_kind``, one of :data:`KINDS`;
    its UML ``type``) and ``default``; an operation its ``arity`` (its in and inout parameters)."""

    kind: str
    element: str
    member: str
    id: str
    names: tuple[str, ...]
    value_kind: str | None = None
    type: str = ""
    default: Value | None = None
    arity: int | None = None

    @property
    def target(self) -> str:
        """``element.member``: the engine's name for the variable, or the operation called."""
        return f"{self.element}.{self.member}"


def bound_names(found: Iterable[tuple[Any, Sequence[str]]]) -> tuple[Bound, ...]:
    """The :class:`Bound` records of a set's resolved names: each ``(target, names written)`` of
    :meth:`acordcs.rules.binding.Binding.targets`, whose payloads are this module's
    :class:`Property` (an attribute) or :class:`Operation`."""
    out = []
    for target, names in found:
        member = target.payload
        if target.kind == "operation":
            arity = sum(1 for p in member.parameters if p.direction in ("in", "inout"))
            out.append(
                Bound(
                    "operation",
                    target.element.name,
                    target.member,
                    member.id,
                    tuple(names),
                    type=member.return_type or "",
                    arity=arity,
                )
            )
        else:
            out.append(
                Bound(
                    "attribute",
                    target.element.name,
                    target.member,
                    member.id,
                    tuple(names),
                    member.kind,
                    member.type,
                    member.default,
                )
            )
    return tuple(out)


@dataclass(frozen=True, slots=True)
class PolicySet:
    """A policy set: its ``engine`` (fuzzy, clips), fuzzy ``semantics``, ``trigger`` (event,
    periodic) and ``frequency`` (Hz, None when unset), its policies, the elements it ``adapts`` and
    the linguistic variables of its scope (the monitors feeding it, the elements it adapts and
    their ports): every variable its rules may name."""

    id: str
    name: str
    qualified_name: str
    engine: str
    semantics: str
    trigger: str
    frequency: float | None = None
    adapts: tuple[Ref, ...] = ()
    policies: tuple[Policy, ...] = ()
    variables: tuple[Variable, ...] = ()
    properties: tuple[Property, ...] = ()
    operations: tuple[Operation, ...] = ()
    documentation: str = ""
    bound: tuple[Bound, ...] = ()
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    triggers: tuple[str, ...] = ()

    def rules(self) -> tuple[Rule, ...]:
        """Every rule of every policy, in order."""
        return tuple(r for p in self.policies for r in p.rules)


@dataclass(frozen=True, slots=True)
class Application:
    """One context-aware application: what :func:`~acordcs.generator.describe.describe` finds in a model."""

    name: str
    containers: tuple[Container, ...] = ()
    components: tuple[Component, ...] = ()
    connections: tuple[Connection, ...] = ()
    monitors: tuple[Monitor, ...] = ()
    policy_sets: tuple[PolicySet, ...] = ()

    def container_of(self, name: str) -> str | None:
        """The container hosting the component, monitor or policy set ``name``, or None."""
        return next((c.name for c in self.containers if any(r.name == name for r in c.hosts)), None)

    def fed_by(self, policy_set: str) -> tuple[str, ...]:
        """Names of the monitors feeding ``policy_set``."""
        return tuple(m.name for m in self.monitors if any(r.name == policy_set for r in m.feeds))
