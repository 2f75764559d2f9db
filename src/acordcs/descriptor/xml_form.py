"""How the descriptor declares its XML form, once, and the layouts that writing, reading and the
schema are derived from.

Each field of the dataclasses of :mod:`acordcs.descriptor.application` says in its ``metadata`` (made
by :func:`attr`, :func:`content`, :func:`doc`, :func:`child`, :func:`children`, :func:`name_list`
or :func:`group`) what it is in the document: an attribute and its value type, the element's text,
its documentation, one child element, a list of them, a list of names, or one of the application's
groups. Its place in the document is its place among the fields, except that an element's
documentation is its first child and a ``before`` puts a field ahead of another. Each dataclass
names its element type in a class variable ``XML`` (:class:`Element`). Whether a value may be left
out is its annotation's: an ``X | None`` field is written only when set.

Nothing else says what the document holds: :mod:`acordcs.descriptor.xml` writes it,
:mod:`acordcs.descriptor.reader` reads it and :mod:`acordcs.descriptor.xsd` writes its schema,
each by walking :func:`layout`.
"""

from __future__ import annotations

import dataclasses
import typing
from functools import cache
from typing import Any, Literal

NAMESPACE = "http://acordcs.org/descriptor/1.0"
NS = "{" + NAMESPACE + "}"

KEY = "acordcs.descriptor"
"""The key of a field's declaration (a :class:`Node`) in its ``metadata``."""

Codec = Literal["string", "real", "integer", "flag", "names", "reals", "typed"]
"""How an attribute's value is written and read: ``string`` as it is; ``real`` a finite number
(``1``, ``0.5``: :func:`acordcs.typed_values.parse_real` reads it back); ``integer``; ``flag`` a
bool written ``true`` only when true; ``names`` and ``reals`` lists separated by spaces; ``typed``
a property's default, a literal of the value kind another field holds."""

Role = Literal["attribute", "text", "documentation", "child", "children", "names", "group"]


class _Record:
    """A record of the declaration, read-only by convention. Plain classes with slots, not
    dataclasses: the declaration is made each time a generated application starts, and making a
    dataclass (its generated methods) costs about 1 ms of that start, each."""

    __slots__ = ()

    def __repr__(self) -> str:
        names: tuple[str, ...] = self.__slots__
        shown = ", ".join(f"{name}={getattr(self, name)!r}" for name in names)
        return f"{type(self).__name__}({shown})"


class Simple(_Record):
    """A value type of the document: how its values are written and read (``codec``) and what the
    schema says of it. ``name`` is a built-in ``xs:`` type, a simple type of the schema, or ``""``
    for one declared inline on the attribute having it; a restriction of ``base`` by ``facets``,
    a list of ``item``, or an enumeration of ``values`` (or of the literals of the metamodel's
    EEnum ``eenum``, read when the schema is written, less ``left_out``: ``why`` says why)."""

    __slots__ = (
        "base",
        "codec",
        "doc",
        "eenum",
        "facets",
        "item",
        "left_out",
        "name",
        "values",
        "why",
    )

    def __init__(
        self,
        codec: Codec,
        name: str = "",
        base: Simple | None = None,
        facets: tuple[tuple[str, str], ...] = (),
        item: Simple | None = None,
        values: tuple[str, ...] = (),
        eenum: str = "",
        left_out: tuple[str, ...] = (),
        why: str = "",
        doc: str = "",
    ) -> None:
        self.codec = codec
        self.name = name
        self.base = base
        self.facets = facets
        self.item = item
        self.values = values
        self.eenum = eenum
        self.left_out = left_out
        self.why = why
        self.doc = doc

    @property
    def reference(self) -> str:
        """How the schema refers to the type: ``xs:string``, ``d:real``; ``""`` inline."""
        return self.name if self.name.startswith("xs:") or not self.name else "d:" + self.name


def enumeration(
    name: str,
    values: tuple[str, ...] = (),
    *,
    eenum: str = "",
    left_out: tuple[str, ...] = (),
    why: str = "",
) -> Simple:
    """A string type whose values are ``values``, or the literals of EEnum ``eenum`` of
    ``acordcs.ecore`` but ``left_out`` (``why``: the reason, which the schema states)."""
    return Simple("string", name, XS_STRING, values=values, eenum=eenum, left_out=left_out, why=why)


# The document's lexical types. REAL's pattern is the lexical form parse_real reads (no NaN, INF).
XS_STRING = Simple("string", "xs:string")
XS_INT = Simple("integer", "xs:int")
XS_DOUBLE = Simple("real", "xs:double")
POSITIVE_INTEGER = Simple("integer", "xs:positiveInteger")
NON_NEGATIVE_INTEGER = Simple("integer", "xs:nonNegativeInteger")
BOOLEAN = Simple("flag", "xs:boolean")
REAL = Simple(
    "real",
    "real",
    XS_DOUBLE,
    (("pattern", r"[+\-]?([0-9]+(\.[0-9]*)?|\.[0-9]+)([eE][+\-]?[0-9]+)?"),),
    doc="A finite xsd:double (no NaN, no INF).",
)
FREQUENCY = Simple("real", "frequency", REAL, (("minExclusive", "0"),), doc="Hz, above 0.")
REALS = Simple("reals", "reals", item=REAL)
NAMES = Simple("names", "names", item=XS_STRING)
TCP_PORT = Simple("integer", "", XS_INT, (("minInclusive", "1"), ("maxInclusive", "65535")))


class Node(_Record):
    """What one field is in the document (see the module's documentation): its ``role``, its XML
    ``name`` ("" the field's, with '-' for '_'), an attribute's value ``type``; ``typed_by``, the
    field whose value kind types a default; ``empty_absent``, "" written as no attribute (and no
    attribute read as ""); ``item``, how an error names one of a list of reals, or the tag of a
    group's elements; ``hint``, that of the error refusing a name with a blank; ``schema_type``,
    the schema's complex type of a name list's elements ("" inline); ``before``, the field whose
    node this one stands before in the document."""

    __slots__ = (
        "before",
        "empty_absent",
        "hint",
        "item",
        "name",
        "role",
        "schema_type",
        "type",
        "typed_by",
    )

    def __init__(
        self,
        role: Role,
        name: str = "",
        type: Simple = XS_STRING,
        typed_by: str = "",
        empty_absent: bool = False,
        item: str = "",
        hint: str = "",
        schema_type: str = "",
        before: str = "",
    ) -> None:
        self.role = role
        self.name = name
        self.type = type
        self.typed_by = typed_by
        self.empty_absent = empty_absent
        self.item = item
        self.hint = hint
        self.schema_type = schema_type
        self.before = before


def _declared(node: Node) -> dict[str, Node]:
    return {KEY: node}


def attr(
    name: str = "",
    type: Simple = XS_STRING,
    *,
    typed_by: str = "",
    empty_absent: bool = False,
    item: str = "",
    hint: str = "",
    before: str = "",
) -> dict[str, Node]:
    """An attribute of the element, named ``name`` (default: the field's name, '-' for '_')."""
    node = Node("attribute", name, type, typed_by, empty_absent, item, hint, before=before)
    return _declared(node)


def content() -> dict[str, Node]:
    """The element's text (an element with text has no child elements)."""
    return _declared(Node("text"))


def doc() -> dict[str, Node]:
    """The element's ``documentation`` child, its first; ``""`` is written as none."""
    return _declared(Node("documentation", "documentation"))


def child(tag: str) -> dict[str, Node]:
    """One child element ``tag`` of the field's dataclass."""
    return _declared(Node("child", tag))


def children(tag: str, *, before: str = "") -> dict[str, Node]:
    """A tuple of the field's dataclass, each a child element ``tag``, in order."""
    return _declared(Node("children", tag, before=before))


def name_list(tag: str, *, schema_type: str = "", before: str = "") -> dict[str, Node]:
    """A tuple of names, each a child element ``tag`` with the attribute ``name``; the schema
    declares their type inline, or as the complex type ``schema_type`` when others share it."""
    return _declared(Node("names", tag, schema_type=schema_type, before=before))


def group(tag: str, item: str) -> dict[str, Node]:
    """A tuple of the field's dataclass, each an element ``item`` inside one element ``tag``,
    written even when empty (the application's lists)."""
    return _declared(Node("group", tag, item=item))


class Element(_Record):
    """A dataclass's element type: ``name``, its complex type in the schema (the application's:
    the document element's name); ``label``, how an error names one (``container 'UserSide'``,
    after the enclosing element's: ``component 'A', port 'P'``), by its attribute ``label_by``;
    without a label, an error names the enclosing element."""

    __slots__ = ("label", "label_by", "name")

    def __init__(self, name: str, label: str = "", label_by: str = "name") -> None:
        self.name = name
        self.label = label
        self.label_by = label_by


class Part(_Record):
    """One field as the document has it: ``xml`` its attribute name or child tag (``tag`` with
    the namespace), ``optional`` when its annotation admits None, ``codec`` an attribute's,
    ``layout`` the layout of the dataclass a child, children or group field holds, ``item_tag`` the
    tag (with the namespace) of a group's elements."""

    __slots__ = ("codec", "field", "item_tag", "layout", "node", "optional", "tag", "xml")

    def __init__(
        self,
        field: str,
        node: Node,
        xml: str,
        tag: str,
        optional: bool,
        codec: Codec | None,
        layout: Layout | None,
        item_tag: str,
    ) -> None:
        self.field = field
        self.node = node
        self.xml = xml
        self.tag = tag
        self.optional = optional
        self.codec = codec
        self.layout = layout
        self.item_tag = item_tag


class Layout(_Record):
    """A dataclass's element: its fields in their order (the constructor's), its attributes and
    children in the document's, the field holding its text if any."""

    __slots__ = ("attributes", "children", "cls", "element", "fields", "text")

    def __init__(
        self,
        cls: type,
        element: Element,
        fields: tuple[Part, ...],
        attributes: tuple[Part, ...],
        text: Part | None,
        children: tuple[Part, ...],
    ) -> None:
        self.cls = cls
        self.element = element
        self.fields = fields
        self.attributes = attributes
        self.text = text
        self.children = children

    def __repr__(self) -> str:  # the parts' layouts would repeat every held dataclass's
        return f"Layout({self.cls.__name__})"

    def part(self, field: str) -> Part:
        return next(p for p in self.fields if p.field == field)


@cache
def layout(cls: type) -> Layout:
    """The layout of dataclass ``cls`` (of its children's, recursively), made once; ``TypeError``
    for a field that declares no XML form or a declaration that does not hold together."""
    element = getattr(cls, "XML", None)
    if not isinstance(element, Element):
        raise TypeError(f"{cls.__name__} declares no XML element type (XML: ClassVar[Element])")
    fields = dataclasses.fields(cls)
    # annotations as objects (the model's module evaluates them), else resolved from their text
    hints = (
        {f.name: f.type for f in fields}
        if not any(isinstance(f.type, str) for f in fields)
        else typing.get_type_hints(cls)
    )
    parts = [_part(cls, f.name, f.metadata.get(KEY), hints[f.name]) for f in fields]
    attributes = [p for p in parts if p.node.role == "attribute"]
    texts = [p for p in parts if p.node.role == "text"]
    docs = [p for p in parts if p.node.role == "documentation"]
    others = [p for p in parts if p.node.role not in ("attribute", "text", "documentation")]
    if len(texts) > 1 or len(docs) > 1 or (texts and (docs or others)):
        raise TypeError(f"{cls.__name__}: an element has text or child elements, not both")
    for part in parts:
        if part.node.typed_by and part.node.typed_by not in {a.field for a in attributes}:
            raise TypeError(f"{cls.__name__}.{part.field}: typed by no attribute field")
    return Layout(
        cls,
        element,
        tuple(parts),
        _placed(cls, attributes),
        texts[0] if texts else None,
        tuple(docs) + _placed(cls, others),
    )


def _part(cls: type, name: str, node: Any, hint: Any) -> Part:
    if not isinstance(node, Node):
        raise TypeError(f"{cls.__name__}.{name} declares no XML form (metadata={{KEY: Node}})")
    args = typing.get_args(hint)
    optional = type(None) in args
    held: Layout | None = None
    if node.role in ("child", "children", "group"):
        # tuple[X, ...] for lists, X or X | None for one: X is a dataclass declaring its element
        found = [a for a in args if a is not Ellipsis and a is not type(None)] or [hint]
        if len(found) != 1 or not dataclasses.is_dataclass(found[0]):
            raise TypeError(f"{cls.__name__}.{name}: {hint} holds no one declared dataclass")
        held = layout(typing.cast(type, found[0]))
    xml = node.name or name.replace("_", "-")
    codec: Codec | None = None
    if node.role == "attribute":
        codec = "typed" if node.typed_by else node.type.codec
    item_tag = NS + node.item if node.role == "group" else ""
    return Part(name, node, xml, NS + xml, optional, codec, held, item_tag)


def _placed(cls: type, parts: list[Part]) -> tuple[Part, ...]:
    """``parts`` in field order, each with a ``before`` moved ahead of the field it names."""
    out = list(parts)
    for part in parts:
        if part.node.before:
            out.remove(part)
            at = [i for i, p in enumerate(out) if p.field == part.node.before]
            if not at:
                raise TypeError(f"{cls.__name__}.{part.field}: before {part.node.before!r}?")
            out.insert(at[0], part)
    return tuple(out)
