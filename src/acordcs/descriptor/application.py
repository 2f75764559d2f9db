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

This module is also the one declaration of the XML form: each class's ``XML`` names its element
type, each field's ``metadata`` says what it is in the document and its value type (see
:mod:`acordcs.descriptor.xml_form`); the writer, the reader and the schema
(``acordcs-descriptor.xsd``, written by :mod:`acordcs.descriptor.xsd`) are derived from it.
"""

# No ``from __future__ import annotations``: the fields' annotations are evaluated as the classes
# are made, so that the layouts of the declaration read them as they are (resolving them as strings
# with typing.get_type_hints costs about 1.7 ms of a generated application's start).

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, ClassVar

from acordcs.descriptor.xml_form import (
    BOOLEAN,
    FREQUENCY,
    NAMES,
    NON_NEGATIVE_INTEGER,
    POSITIVE_INTEGER,
    REAL,
    REALS,
    TCP_PORT,
    Element,
    attr,
    child,
    children,
    content,
    doc,
    enumeration,
    group,
    name_list,
)
from acordcs.errors import AcordError
from acordcs.typed_values import Value

# The descriptor's own vocabularies: no EEnum of acordcs.ecore declares them (those that one does
# are named by their EEnum below, and acordcs.vocabularies reads their literals from the file).
KINDS = ("int", "double", "bool", "string")
"""How a property's UML type is read (see :func:`acordcs.typed_values.typed_default`)."""

ELEMENT_KINDS = ("container", "component", "port", "connection", "monitor", "policy-set")
"""What a :class:`Ref` refers to."""

MEMBER_KINDS = ("attribute", "operation")
"""What a :class:`Bound` name stands for."""

PROTOCOLS = ("pyro",)
"""How remote connectors reach a container's :class:`Endpoint`."""

# The enumerated value types of the document's attributes.
VALUE_KIND = enumeration("valueKind", KINDS)
ELEMENT_KIND = enumeration("elementKind", ELEMENT_KINDS)
MEMBER_KIND = enumeration("memberKind", MEMBER_KINDS)
PROTOCOL = enumeration("", PROTOCOLS)  # declared inline: the endpoint's attribute alone has it
LANGUAGE = enumeration("language", eenum="ImplementationLanguage")
PORT_KIND = enumeration("portKind", eenum="PortKind")
PORT_ROLE = enumeration("portRole", eenum="PortRole")
CONNECTOR = enumeration("connector", eenum="ConnectorKind")
ACQUISITION = enumeration("acquisition", eenum="MonitorAcquisition")
ENGINE = enumeration("engine", eenum="EngineKind")
SEMANTICS = enumeration("semantics", eenum="FuzzySemantics")
TRIGGER = enumeration("trigger", eenum="PolicyTrigger")
DIRECTION = enumeration(
    "direction",
    eenum="ParameterDirection",
    left_out=("return",),
    why="an operation's result is its returnType, not one of its parameters",
)
SHAPE = enumeration("shape", eenum="MembershipShape")


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

    XML: ClassVar[Element] = Element("property", "property")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    type: str = field(metadata=attr())
    kind: str = field(metadata=attr(type=VALUE_KIND))
    default: Value = field(metadata=attr(typed_by="kind"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Parameter:
    """An input parameter of an operation; ``direction`` is ``in``, ``out`` or ``inout``."""

    XML: ClassVar[Element] = Element("parameter")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    type: str = field(metadata=attr())
    direction: str = field(default="in", metadata=attr(type=DIRECTION))


@dataclass(frozen=True, slots=True)
class Operation:
    """An operation (an action a crisp rule may call); parameters in declaration order,
    ``return_type`` None for none."""

    XML: ClassVar[Element] = Element("operation", "operation")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    parameters: tuple[Parameter, ...] = field(default=(), metadata=children("parameter"))
    return_type: str | None = field(default=None, metadata=attr("returns"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Ref:
    """A resolved reference to another element: its kind (one of :data:`ELEMENT_KINDS`), its
    name (a port as ``Component.Port``) and its id."""

    XML: ClassVar[Element] = Element("ref")
    kind: str = field(metadata=attr(type=ELEMENT_KIND))
    name: str = field(metadata=attr())
    id: str = field(metadata=attr("ref"))


@dataclass(frozen=True, slots=True)
class Port:
    """A port of a component: ``kind`` synchronous, asynchronous or stream; ``role`` provided or
    required."""

    XML: ClassVar[Element] = Element("port", "port")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    kind: str = field(metadata=attr(type=PORT_KIND))
    role: str = field(metadata=attr(type=PORT_ROLE))
    properties: tuple[Property, ...] = field(default=(), metadata=children("property"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Component:
    XML: ClassVar[Element] = Element("component", "component")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    language: str = field(metadata=attr(type=LANGUAGE))
    properties: tuple[Property, ...] = field(default=(), metadata=children("property"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    ports: tuple[Port, ...] = field(default=(), metadata=children("port"))
    documentation: str = field(default="", metadata=doc())
    # the model's tag persistent: its state kept in the run directory across restarts
    persistent: bool = field(default=False, metadata=attr(type=BOOLEAN))

    def port(self, name: str) -> Port | None:
        return next((p for p in self.ports if p.name == name), None)


@dataclass(frozen=True, slots=True)
class Endpoint:
    """Where a container is reached by remote connectors: a Pyro5 object on the container's host.

    The TCP port is not in the model: the container's server picks it when it starts (or the
    deployment sets it), so the URI is made with :meth:`uri` once it is known.
    """

    XML: ClassVar[Element] = Element("endpoint")
    protocol: str = field(metadata=attr(type=PROTOCOL))
    object_name: str = field(metadata=attr("object"))
    host: str = field(metadata=attr())
    # the model's tag port; None: chosen at deployment
    port: int | None = field(default=None, metadata=attr(type=TCP_PORT))

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

    XML: ClassVar[Element] = Element("container", "container")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    host: str = field(metadata=attr())
    endpoint: Endpoint | None = field(default=None, metadata=child("endpoint"))
    hosts: tuple[Ref, ...] = field(default=(), metadata=children("hosts"))
    properties: tuple[Property, ...] = field(default=(), metadata=children("property"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    documentation: str = field(default="", metadata=doc())
    # a field added last (positional construction keeps its place) but written before the members
    reaches: tuple[str, ...] = field(default=(), metadata=name_list("reaches", before="properties"))

    def hosted(self, kind: str) -> tuple[str, ...]:
        """Names of the hosted elements of ``kind`` (component, monitor, policy-set)."""
        return tuple(r.name for r in self.hosts if r.kind == kind)


@dataclass(frozen=True, slots=True)
class End:
    """One end of a connection: a port of a component, by names, and the port's id."""

    XML: ClassVar[Element] = Element("end")
    component: str = field(metadata=attr())
    port: str = field(metadata=attr())
    id: str = field(metadata=attr("ref"))


@dataclass(frozen=True, slots=True)
class Connection:
    """A port connection from a required port to a provided one, realised by ``connector``
    (inprocess, remote, shaped); ``qos`` are its attributes, which policies may adapt."""

    XML: ClassVar[Element] = Element("connection", "connection")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    connector: str = field(metadata=attr(type=CONNECTOR))
    required: End = field(metadata=child("required"))
    provided: End = field(metadata=child("provided"))
    qos: tuple[Property, ...] = field(default=(), metadata=children("qos"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Monitor:
    """A monitor. ``acquisition`` says how it acquires context: ``intercept`` (the calls through its
    source port, or to its source component, and that component's property changes), ``subscribe``
    (the context provider's documents ``xpath`` selects something in), ``poll`` (its source
    component's ``operation`` called at ``frequency`` Hz) or ``custom`` (its own code: ``acquire``
    at ``frequency`` Hz when one is set). ``feeds`` are the policy sets its ``properties`` (the
    context attributes) feed."""

    XML: ClassVar[Element] = Element("monitor", "monitor")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    frequency: float | None = field(metadata=attr(type=FREQUENCY))
    acquisition: str = field(metadata=attr(type=ACQUISITION, before="frequency"))
    xpath: str | None = field(default=None, metadata=attr())
    operation: str | None = field(default=None, metadata=attr())
    sources: tuple[Ref, ...] = field(default=(), metadata=children("source"))
    feeds: tuple[Ref, ...] = field(default=(), metadata=children("feeds"))
    properties: tuple[Property, ...] = field(default=(), metadata=children("property"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Rule:
    """One rule: its ``label`` (as written, or when the model wrote none, ``assigned_label`` and
    the default label ``rule<n>``, n its position: :func:`acordcs.rules.binding.default_label`),
    its text without the label, the tag it was read from (``Rule`` or another tag starting with
    ``Rule``) and its ``priority``, its 1-based rank in its policy: a crisp engine tries the
    rules in that order (CLIPS salience 9999 for the first, 9998 for the next...)."""

    XML: ClassVar[Element] = Element("rule")
    label: str = field(metadata=attr())
    text: str = field(metadata=content())
    tag: str = field(metadata=attr())
    priority: int = field(default=1, metadata=attr(type=POSITIVE_INTEGER))
    assigned_label: bool = field(default=False, metadata=attr(type=BOOLEAN))

    @property
    def line(self) -> str:
        """The rule as an engine's ``defrule`` takes it: ``label: text``."""
        return f"{self.label}: {self.text}"


@dataclass(frozen=True, slots=True)
class Policy:
    XML: ClassVar[Element] = Element("policy", "policy")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    rules: tuple[Rule, ...] = field(default=(), metadata=children("rule"))
    documentation: str = field(default="", metadata=doc())


@dataclass(frozen=True, slots=True)
class Term:
    """A linguistic term: ``shape`` as the metamodel names it (trapezoid, triangle, gaussian, bell,
    sigmoid, points, singleton), parameters in FCL order (points: x1 y1 x2 y2 ...)."""

    XML: ClassVar[Element] = Element("term")
    name: str = field(metadata=attr())
    shape: str = field(metadata=attr(type=SHAPE))
    parameters: tuple[float, ...] = field(metadata=attr(type=REALS, item="parameter"))

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

    XML: ClassVar[Element] = Element("variable", "variable")
    id: str = field(metadata=attr())
    element: str = field(metadata=attr())
    attribute: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    minimum: float = field(metadata=attr("min", REAL))
    maximum: float = field(metadata=attr("max", REAL))
    terms: tuple[Term, ...] = field(default=(), metadata=children("term"))

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

    XML: ClassVar[Element] = Element("bound", "bound name", "target")
    kind: str = field(metadata=attr(type=MEMBER_KIND))
    element: str = field(metadata=attr())
    member: str = field(metadata=attr())
    id: str = field(metadata=attr("ref"))
    names: tuple[str, ...] = field(
        metadata=attr(
            type=NAMES, hint="bound names are the rule names as written (Element.attribute)"
        )
    )
    value_kind: str | None = field(default=None, metadata=attr(type=VALUE_KIND))
    type: str = field(default="", metadata=attr(empty_absent=True))
    default: Value | None = field(default=None, metadata=attr(typed_by="value_kind"))
    arity: int | None = field(default=None, metadata=attr(type=NON_NEGATIVE_INTEGER))

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

    XML: ClassVar[Element] = Element("policySet", "policy set")
    id: str = field(metadata=attr())
    name: str = field(metadata=attr())
    qualified_name: str = field(metadata=attr("qname"))
    engine: str = field(metadata=attr(type=ENGINE))
    semantics: str = field(metadata=attr(type=SEMANTICS))
    trigger: str = field(metadata=attr(type=TRIGGER))
    frequency: float | None = field(default=None, metadata=attr(type=FREQUENCY))
    adapts: tuple[Ref, ...] = field(default=(), metadata=children("adapts"))
    policies: tuple[Policy, ...] = field(default=(), metadata=children("policy"))
    variables: tuple[Variable, ...] = field(default=(), metadata=children("variable"))
    properties: tuple[Property, ...] = field(default=(), metadata=children("property"))
    operations: tuple[Operation, ...] = field(default=(), metadata=children("operation"))
    documentation: str = field(default="", metadata=doc())
    bound: tuple[Bound, ...] = field(default=(), metadata=children("bound"))
    inputs: tuple[str, ...] = field(
        default=(), metadata=name_list("input", schema_type="variableName")
    )
    outputs: tuple[str, ...] = field(
        default=(), metadata=name_list("output", schema_type="variableName")
    )
    triggers: tuple[str, ...] = field(
        default=(), metadata=name_list("trigger", schema_type="variableName")
    )

    def rules(self) -> tuple[Rule, ...]:
        """Every rule of every policy, in order."""
        return tuple(r for p in self.policies for r in p.rules)


@dataclass(frozen=True, slots=True)
class Application:
    """One context-aware application: what :func:`~acordcs.generator.describe.describe` finds in a model."""

    XML: ClassVar[Element] = Element("application", "application")
    name: str = field(metadata=attr())
    containers: tuple[Container, ...] = field(default=(), metadata=group("containers", "container"))
    components: tuple[Component, ...] = field(default=(), metadata=group("components", "component"))
    connections: tuple[Connection, ...] = field(
        default=(), metadata=group("connections", "connection")
    )
    monitors: tuple[Monitor, ...] = field(default=(), metadata=group("monitors", "monitor"))
    policy_sets: tuple[PolicySet, ...] = field(
        default=(), metadata=group("policy-sets", "policy-set")
    )

    def container_of(self, name: str) -> str | None:
        """The container hosting the component, monitor or policy set ``name``, or None."""
        return next((c.name for c in self.containers if any(r.name == name for r in c.hosts)), None)

    def fed_by(self, policy_set: str) -> tuple[str, ...]:
        """Names of the monitors feeding ``policy_set``."""
        return tuple(m.name for m in self.monitors if any(r.name == policy_set for r in m.feeds))
