"""What a model in the text notation says, as plain data: the packages, the elements with their
stereotype's tags, members and relations, each with where the text says it.

Every form goes through it: the text is parsed into it (:mod:`acordcs.notation.syntax`), written
from it (:mod:`acordcs.notation.text_form`), read as the neutral UML view from it
(:mod:`acordcs.notation.text_model`), turned into XMI from it (:mod:`acordcs.notation.xmi_forms`),
and made from any model the XMI readers read (:mod:`acordcs.model.outline_builder`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

# The notation's element keywords: one per stereotype of the profile the architecture reads
# (a test holds the table equal to the profile; CtxVariable is written on an attribute).
KINDS = {
    "container": "CtxContainer",
    "component": "CtxComponent",
    "port": "CtxPort",
    "connection": "CtxPortConnection",
    "monitor": "CtxMonitor",
    "policyset": "CtxPolicySet",
    "policy": "CtxPolicy",
}
KEYWORDS = {stereotype: keyword for keyword, stereotype in KINDS.items()}
VARIABLE = "CtxVariable"
# Relation keyword -> the architecture's relation, read from the element that states it.
RELATIONS = {
    "hosts": "hosts",
    "owns": "owns_port",
    "joins": "joins",
    "contains": "contains",
    "adapts": "adapts",
    "feeds": "feeds",
    "sources": "sources",
}
RELATION_KEYWORDS = {relation: keyword for keyword, relation in RELATIONS.items()}
RULE_TAG = "Rule"  # rules NAME { } is the tag Rule + NAME
TERMS_TAG = "terms"


@dataclass(frozen=True)
class Place:
    """Where the text says something: 1-based line and column (0: not from a text)."""

    line: int = 0
    column: int = 0


@dataclass
class Tag:
    name: str
    value: str
    place: Place = Place()


@dataclass
class Block:
    """A rules or terms block: its lines as written, each with where it starts."""

    lines: list[tuple[str, Place]] = field(default_factory=list)
    place: Place = Place()


@dataclass
class Parameter:
    name: str
    type: str | None
    direction: str = "in"
    id: str | None = None  # None: derived from the qualified name
    place: Place = Place()


@dataclass
class Operation:
    name: str
    parameters: list[Parameter] = field(default_factory=list)
    returns: str | None = None
    doc: list[str] = field(default_factory=list)
    id: str | None = None
    place: Place = Place()


@dataclass
class Variable:
    tags: list[Tag] = field(default_factory=list)
    terms: Block | None = None
    id: str | None = None
    place: Place = Place()


@dataclass
class Attribute:
    name: str
    type: str | None = None
    default: str | None = None
    variable: Variable | None = None
    doc: list[str] = field(default_factory=list)
    id: str | None = None
    place: Place = Place()


@dataclass
class Relation:
    keyword: str
    targets: list[tuple[tuple[str, ...], Place]] = field(default_factory=list)
    place: Place = Place()


@dataclass
class Element:
    keyword: str  # container, component, ...
    name: str
    tags: list[Tag] = field(default_factory=list)
    rules: list[tuple[str, Block]] = field(default_factory=list)  # (tag name, block)
    attributes: list[Attribute] = field(default_factory=list)
    operations: list[Operation] = field(default_factory=list)
    relations: list[Relation] = field(default_factory=list)
    nested: list[Element] = field(default_factory=list)
    doc: list[str] = field(default_factory=list)
    id: str | None = None
    place: Place = Place()

    @property
    def stereotype(self) -> str:
        return KINDS[self.keyword]


@dataclass
class Package:
    name: str
    items: list[Package | Element] = field(default_factory=list)
    doc: list[str] = field(default_factory=list)
    id: str | None = None
    place: Place = Place()


@dataclass
class Outline:
    """A whole model: its name and its top-level packages and elements."""

    name: str = ""
    items: list[Package | Element] = field(default_factory=list)
    doc: list[str] = field(default_factory=list)
    id: str | None = None
    place: Place = Place()


def derived_id(path: tuple[str, ...]) -> str:
    """The id a package, or an element of a package, whose qualified name is ``path`` gets when
    the text gives none: ``_`` and its names joined by dots (``_Deployment.House``)."""
    return "_" + ".".join(path)


def member_id(owner_id: str, name: str) -> str:
    """The id a member of an element (an attribute, an operation, a parameter of one, a port or
    another element inside it) gets when the text gives none: its owner's id, a dot and its name
    (``_Fan.speed``, ``_Fan.setSpeed.level``), the shape of the Papyrus samples' ids."""
    return f"{owner_id}.{name}"
