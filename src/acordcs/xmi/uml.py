"""A neutral view of a UML model, the same whichever tool wrote the XMI.

It keeps what the file says (names, kinds, ids, lines, stereotype applications with their tagged values)
and nothing ACORD-CS specific: :mod:`acordcs.model.architecture` interprets it. Classes are slotted
dataclasses because a 4 MB export makes tens of thousands of them; readers pass id, kind, name, line
and owner positionally (half the cost of keywords).
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
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
    """A classifier. Its attributes, ends and operations may be read when first asked for: a
    reader can leave them unread (``features_pending``) when nothing in them needs saying at once
    (no reference it could not resolve, no stereotype, no missing id), so that a check that looks
    at a few hundred classes of a model does not pay for building the features of thousands."""

    literals: list[str] = field(default_factory=list)
    generals: list[str] = field(default_factory=list)  # ids of general classifiers
    nested: list[Classifier] = field(default_factory=list)
    member_ends: list[str] = field(default_factory=list)  # for AssociationClass
    _attributes: list[Property] = field(default_factory=list)  # owned, not association ends
    _ends: list[Property] = field(default_factory=list)  # owned association ends
    _operations: list[Operation] = field(default_factory=list)
    # The reader's way to read the features later: called once, with this classifier.
    features_pending: Callable[[Classifier], None] | None = None

    def read_pending(self) -> None:
        read, self.features_pending = self.features_pending, None
        if read is not None:
            read(self)

    @property
    def attributes(self) -> list[Property]:
        if self.features_pending is not None:
            self.read_pending()
        return self._attributes

    @property
    def ends(self) -> list[Property]:
        if self.features_pending is not None:
            self.read_pending()
        return self._ends

    @property
    def operations(self) -> list[Operation]:
        if self.features_pending is not None:
            self.read_pending()
        return self._operations


@dataclass(slots=True, eq=False)
class Association(Element):
    """An association. Its owned ends may be read when first asked for, as a classifier's
    features (see :class:`Classifier`)."""

    member_ends: list[str] = field(default_factory=list)  # ids of the end properties
    _owned_ends: list[Property] = field(default_factory=list)
    features_pending: Callable[[Association], None] | None = None

    def read_pending(self) -> None:
        read, self.features_pending = self.features_pending, None
        if read is not None:
            read(self)

    @property
    def owned_ends(self) -> list[Property]:
        if self.features_pending is not None:
            self.read_pending()
        return self._owned_ends


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
    id: str | None = None
    places: set[str] = field(default_factory=set)  # root, extension, xmi12, eclipse

    @property
    def key(self) -> str:
        return f"{self.profile}:{self.name}" if self.profile else self.name


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


class Elements(dict):
    """Every element of a model by id. The features of a classifier that a reader left unread
    (see :class:`Classifier`) are in ``pending`` (id -> classifier) and read as soon as one of them
    is asked for, by ``[]``, ``get`` or ``in``, and all of them when the elements are listed: to
    whoever looks, the dict is complete. The reader fills it with ``setdefault``, not wrapped."""

    __slots__ = ("pending", "pending_types")

    def __init__(self) -> None:
        super().__init__()
        self.pending: dict[str, Classifier | Association] = {}
        self.pending_types: dict[str, str | None] = {}  # unread property -> its type's id

    def property_type(self, ident: str) -> tuple[bool, str | None]:
        """Whether ``ident`` is a property, and the id of its type, without reading the features
        of a classifier for it: what decides whether an association joins two roles."""
        found = dict.get(self, ident)
        if found is None and ident in self.pending:
            return (ident in self.pending_types, self.pending_types.get(ident))
        if isinstance(found, Property):
            return True, found.type_ref
        return False, None

    def _read(self, ident: object) -> Element | None:
        owner = self.pending.pop(ident, None) if self.pending else None  # type: ignore[call-overload]
        if owner is None:
            return None
        owner.read_pending()  # ``ident`` among them
        return dict.get(self, ident)

    def __missing__(self, ident: str) -> Element:
        found = self._read(ident)
        if found is None:
            raise KeyError(ident)
        return found

    def get(self, ident: str, default: Element | None = None) -> Element | None:  # type: ignore[override]
        found = dict.get(self, ident)
        if found is None and self.pending:
            found = self._read(ident)
        return default if found is None else found

    def __contains__(self, ident: object) -> bool:
        return dict.__contains__(self, ident) or self._read(ident) is not None

    def read_all(self) -> None:
        """Read every feature left unread."""
        while self.pending:
            _, owner = self.pending.popitem()
            owner.read_pending()

    def __iter__(self):
        self.read_all()
        return dict.__iter__(self)

    def __len__(self) -> int:
        self.read_all()
        return dict.__len__(self)

    def keys(self):  # type: ignore[override]
        self.read_all()
        return dict.keys(self)

    def values(self):  # type: ignore[override]
        self.read_all()
        return dict.values(self)

    def items(self):  # type: ignore[override]
        self.read_all()
        return dict.items(self)


@dataclass(eq=False)
class UmlModel:
    """Everything read from one file."""

    file: str
    dialect: str  # bouml-xmi2, omg-xmi2, eclipse-uml2, bouml-xmi12, xmi1
    name: str = ""
    exporter: str | None = None  # as the file states it: name and version
    tool: str | None = None  # the known tool it names (see readers.exporters.KNOWN_TOOLS)
    elements: Elements = field(default_factory=lambda: Elements())  # by id
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
        operations = sum(len(c.operations) for c in self.classifiers)
        return {
            "classifiers": dict(sorted(Counter(c.kind for c in self.classifiers).items())),
            "attributes": attributes,
            "operations": operations,
            "associations": len(self.associations),
            "generalizations": len(self.generalizations),
            "dependencies": len(self.dependencies),
            "packages": len(self.packages),
            "stereotype_applications": dict(
                sorted(Counter(a.key for a in self.applications.values()).items())
            ),
        }
