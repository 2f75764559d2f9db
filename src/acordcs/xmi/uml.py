"""A neutral view of a UML model, the same whichever tool wrote the XMI.

It keeps what the file says (names, kinds, ids, lines, stereotype applications with their tagged values)
and nothing ACORD-CS specific: :mod:`acordcs.model.architecture` interprets it. Classes are slotted
dataclasses because a 4 MB export makes tens of thousands of them; readers pass id, kind, name, line
and owner positionally (half the cost of keywords).
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from acordcs.diagnostics import Diagnostic


@dataclass(slots=True, eq=False)
class Element:
    id: str
    kind: str  # the UML metaclass: Class, Property, Association, ...
    name: str = ""
    line: int = 0
    owner: Element | None = None
    comments: list[str] = field(default_factory=list)
    tagged_values: dict[str, str] = field(default_factory=dict)  # tags not tied to a stereotype

    def qualified_name(self) -> str:
        parts = []
        node: Element | None = self
        while node is not None:
            if node.kind != "Model":
                parts.append(node.name or f"<{node.kind}>")
            node = node.owner
        return "::".join(reversed(parts)) or self.name or f"<{self.kind}>"


@dataclass(slots=True, eq=False)
class Package(Element):
    members: list[Element] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class TypedElement(Element):
    type_name: str | None = None  # the type as the modeller wrote it (int, double, varchar(20))
    type_ref: str | None = None  # id of a classifier of the model, when typed by one


@dataclass(slots=True, eq=False)
class Property(TypedElement):
    association: str | None = None  # set on association ends
    aggregation: str = "none"
    default: str | None = None
    lower: str | None = None
    upper: str | None = None
    navigable: bool = True


@dataclass(slots=True, eq=False)
class Parameter(TypedElement):
    direction: str = "in"


@dataclass(slots=True, eq=False)
class Operation(Element):
    parameters: list[Parameter] = field(default_factory=list)

    @property
    def inputs(self) -> list[Parameter]:
        return [p for p in self.parameters if p.direction != "return"]

    @property
    def return_type(self) -> str | None:
        return next((p.type_name for p in self.parameters if p.direction == "return"), None)


@dataclass(slots=True, eq=False)
class Classifier(Element):
    literals: list[str] = field(default_factory=list)
    generals: list[str] = field(default_factory=list)  # ids of general classifiers
    nested: list[Classifier] = field(default_factory=list)
    member_ends: list[str] = field(default_factory=list)  # for AssociationClass
    attributes: list[Property] = field(
        default_factory=list
    )  # owned, not association ends nor ports
    ports: list[Property] = field(
        default_factory=list
    )  # owned uml:Port (a Property in UML, never an attribute here)
    ends: list[Property] = field(default_factory=list)  # owned association ends
    operations: list[Operation] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class Association(Element):
    member_ends: list[str] = field(default_factory=list)  # ids of the end properties
    owned_ends: list[Property] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class Dependency(Element):
    clients: list[str] = field(default_factory=list)
    suppliers: list[str] = field(default_factory=list)


@dataclass(slots=True, eq=False)
class Generalization(Element):
    specific: str = ""
    general: str = ""


@dataclass(slots=True, eq=False, kw_only=True)
class StereotypeApplication:
    """A stereotype applied to one element, merged from every place the file states it."""

    profile: str | None  # None for a free stereotype (BOUML's ``entity``, XMI 1.2 names)
    name: str
    base: str  # id of the element it is applied to
    line: int = 0
    tags: dict[str, str] = field(default_factory=dict)
    tag_lines: dict[str, int] = field(default_factory=dict)
    tag_columns: dict[str, int] = field(
        default_factory=dict
    )  # when the file says (the text notation)
    # Where a tag's value is in the file when the file writes it in pieces of its own (the text
    # notation's rules and terms blocks): (offset in the value, line, column) of each piece's
    # start, in order; empty for XMI, where a value is one attribute.
    tag_places: dict[str, tuple[tuple[int, int, int], ...]] = field(default_factory=dict)
    id: str | None = None
    places: set[str] = field(default_factory=set)  # root, extension, xmi12, eclipse, text

    @property
    def key(self) -> str:
        return f"{self.profile}:{self.name}" if self.profile else self.name

    def place_in_file(self, tag: str, offset: int) -> tuple[int, int] | None:
        """The file's (line, column) of the character at ``offset`` (0-based) of tag ``tag``'s
        value, when the file says where the value's pieces are; None otherwise."""
        found = None
        for start, line, column in self.tag_places.get(tag, ()):
            if start > offset:
                break
            found = (line, column + offset - start)
        return found


CLASSIFIER_KINDS = frozenset(
    [
        "Class",
        "Interface",
        "Enumeration",
        "Actor",
        "AssociationClass",
        "DataType",
        "PrimitiveType",
        "Stereotype",
        "Component",
        "Signal",
        "UseCase",
        "Artifact",
        "Node",
        "Device",
        "ExecutionEnvironment",
        "Collaboration",
        "InformationItem",
        "Activity",
        "StateMachine",
        "ProtocolStateMachine",
        "Interaction",
        "OpaqueBehavior",
        "FunctionBehavior",
    ]
)


@dataclass(eq=False)
class UmlModel:
    """Everything read from one file."""

    file: str
    dialect: str  # bouml-xmi2, omg-xmi2, eclipse-uml2, bouml-xmi12, xmi1, acord-text
    name: str = ""
    exporter: str | None = None  # as the file states it: name and version
    tool: str | None = None  # the known tool it names (see readers.exporters.KNOWN_TOOLS)
    elements: dict[str, Element] = field(default_factory=dict)  # by id
    packages: list[Package] = field(default_factory=list)
    classifiers: list[Classifier] = field(default_factory=list)
    associations: list[Association | Classifier] = field(default_factory=list)
    dependencies: list[Dependency] = field(default_factory=list)
    generalizations: list[Generalization] = field(default_factory=list)
    applications: dict[tuple[str, str], StereotypeApplication] = field(default_factory=dict)
    diagnostics: list[Diagnostic] = field(default_factory=list)
    # The profiles the model applies by reference (Eclipse's appliedProfile href), with the line.
    profile_references: list[tuple[str, int]] = field(default_factory=list)

    def applications_of(self, element_id: str) -> list[StereotypeApplication]:
        return [a for (base, _), a in self.applications.items() if base == element_id]

    def counts(self) -> dict:
        """What ``acordcs-gen inspect`` reports (see the README for each count's definition)."""
        attributes = sum(len(c.attributes) for c in self.classifiers)
        ports = sum(len(c.ports) for c in self.classifiers)
        operations = sum(len(c.operations) for c in self.classifiers)
        return {
            "classifiers": dict(sorted(Counter(c.kind for c in self.classifiers).items())),
            "attributes": attributes,
            "ports": ports,
            "operations": operations,
            "associations": len(self.associations),
            "generalizations": len(self.generalizations),
            "dependencies": len(self.dependencies),
            "packages": len(self.packages),
            "stereotype_applications": dict(
                sorted(Counter(a.key for a in self.applications.values()).items())
            ),
        }
