"""The descriptor's schema, ``acordcs-descriptor.xsd``, written from the declaration.

What the document holds (elements, attributes, their types, order and whether they may be left
out) is read from the layouts of :mod:`acordcs.descriptor.xml_form` over the dataclasses of
:mod:`acordcs.descriptor.application`, and the enumerations' values from the model's vocabularies and
the metamodel's EEnums (:mod:`acordcs.vocabularies`). This module adds only what the schema says
beyond the declaration: where each definition stands in the file (:data:`LAYOUT`), the shared
groups (:data:`ATTRIBUTE_GROUPS`, :data:`GROUPS`), the documentation of types and elements, and
the keys (:data:`IDENTITY`, whose selectors are paths of fields, written with the fields' tags).

The package ships the file (the ``config`` target copies it, users' stylesheets read it);
``tests/descriptor/test_schema_is_the_declarations.py`` holds it byte-equal to :func:`schema_text`,
and ``tools/write_schema_enumerations.py`` writes it. Not on the start path: reading a descriptor
uses the shipped file.
"""

from __future__ import annotations

from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from xml.sax.saxutils import escape, quoteattr

from acordcs import vocabularies
from acordcs.descriptor.application import Application
from acordcs.descriptor.xml_form import NAMESPACE, Layout, Part, Simple, layout

HEADER = f"""\
<?xml version="1.0" encoding="UTF-8"?>
<!--
  The ACORD-CS application descriptor, version 1.0 (XSD 1.0).

  Written by acordcs.descriptor.to_xml from a model, read by acordcs.descriptor.from_xml, and the
  input of the code generator's stylesheets. Names are resolved (a port as "Component.Port" where
  a reference names it), every element from the UML model keeps its xmi:id (@id) and its qualified
  UML name (@qname). Lists are sorted by name, then id; properties, operations, parameters and
  rules keep the model's order. The enumerations of kinds, roles, connectors, acquisitions,
  engines, semantics, triggers, languages, directions and shapes are the metamodel's
  (acordcs.ecore, shipped in acordcs/metamodel), written into this file from it by
  tools/write_schema_enumerations.py of the source repository.
-->
<xs:schema xmlns:xs="http://www.w3.org/2001/XMLSchema"
           xmlns:d="{NAMESPACE}"
           targetNamespace="{NAMESPACE}"
           elementFormDefault="qualified"
           attributeFormDefault="unqualified"
           version="1.0">
"""

LAYOUT = (
    "== simple types",
    *("real", "frequency", "reals", "valueKind", "elementKind", "language", "portKind"),
    *("portRole", "connector", "acquisition", "engine", "semantics", "trigger", "direction"),
    "shape",
    "== shared parts",
    *("traced", "property", "parameter", "operation", "ref", "members"),
    "== elements",
    *("endpoint", "container", "port", "component", "end", "connection", "monitor", "rule"),
    *("memberKind", "names", "bound", "variableName", "policy", "term", "variable", "policySet"),
    "== the document",
    "application",
)
"""Where each definition of the schema stands (``==`` a section's heading): every definition the
declaration needs, each once; :func:`schema_text` refuses one missing or not needed."""

ATTRIBUTE_GROUPS = {"traced": ("id", "name", "qname")}
"""Attributes that types share, written once: a type whose attributes run so refers to the group."""

GROUPS = {"members": ("property", "operation")}
"""Child elements that types share, written once, likewise."""

DOCUMENTATION = {
    "property": "An attribute; @default is the typed initial value, a literal of @kind (int: xsd:int digits, double: a finite xsd:double, bool: true or false).",
    "ref": "A resolved reference: the element's kind, name (a port as Component.Port) and id.",
    "endpoint": "Where remote connectors reach the container: PYRO:{@object}@{@host}:{port}, the port being @port (the model's tag) or, without it, chosen at deployment.",
    "monitor": "@acquisition intercept: the calls through its source port (or to its source component) and that component's property changes; subscribe: the context provider's documents @xpath selects something in; poll: its source component's @operation called at @frequency Hz; custom: its own code (acquire at @frequency Hz when set).",
    "rule": "The rule's text without its label; @label as written, or when the model wrote none (@assigned-label true) the default label rule<n>, n its position; @tag is the tag it was read from; @priority its 1-based rank in its policy (a crisp engine tries the rules in that order).",
    "bound": "A name the set's rules write, resolved: an attribute (the engine's variable @element.@member, typed by @value-kind and @type, with its @default) or an operation (@arity: its in and inout parameters) of an element in the set's scope (@element: a port as Component.Port); @ref is the member's id, @names every way the rules write it.",
    "variableName": "A variable of the set's engine, Element.attribute, as a bound attribute names it.",
    "variable": "A linguistic variable in the set's scope: @element.@attribute, universe [@min, @max]; @id is the attribute's.",
    (
        "container",
        "reaches",
    ): "Another container this one's process must be given the address of (--remote): across a connection it calls, calling one of its ports that is not synchronous, or hosting a policy set its monitors feed.",
    ("policySet", "bound"): "What the rules' names stand for, in order of first use.",
    ("policySet", "input"): "The variables an engine is given before each firing, in this order.",
    (
        "policySet",
        "output",
    ): "The variables read back after each firing and written to their attributes, in this order.",
    (
        "policySet",
        "trigger",
    ): "The variables the conditions read: a change of one fires an event-triggered set.",
}
"""The documentation of a type (by its name) or of a type's child element (type, tag)."""


@dataclass(frozen=True, slots=True)
class Identity:
    """A key of the document (``unique``, ``key`` or ``keyref`` to ``refer``): the elements
    ``selectors`` reach (each a path of fields from ``scope``'s element, the application's when
    empty) are told apart by their field ``field`` (a name list's elements: ``name``)."""

    kind: str
    name: str
    selectors: tuple[tuple[str, ...], ...]
    field: str
    refer: str = ""
    scope: tuple[str, ...] = ()
    comment: str = ""  # a comment written above it


IDENTITY = (
    Identity(
        "unique",
        "elementId",
        (
            ("containers",),
            ("components",),
            ("components", "ports"),
            ("connections",),
            ("monitors",),
            ("policy_sets",),
            ("policy_sets", "policies"),
        ),
        "id",
        comment="every element read from the model has its own xmi:id",
    ),
    Identity("unique", "containerName", (("containers",),), "name"),
    Identity("key", "componentName", (("components",),), "name"),
    Identity("key", "monitorName", (("monitors",),), "name"),
    Identity("key", "policySetName", (("policy_sets",),), "name"),
    Identity("unique", "connectionName", (("connections",),), "name"),
    Identity(
        "keyref",
        "endComponent",
        (("connections", "required"), ("connections", "provided")),
        "component",
        refer="componentName",
        comment="connection ends and fed policy sets name elements described here",
    ),
    Identity("keyref", "reachedContainer", (("containers", "reaches"),), "name", "containerName"),
    Identity("keyref", "fedPolicySet", (("monitors", "feeds"),), "name", "policySetName"),
    Identity("unique", "portName", (("ports",),), "name", scope=("components",)),
)


def enumeration_values(simple: Simple) -> tuple[str, ...]:
    """The values an enumerated type allows: its own, or its EEnum's literals less those left out."""
    if not simple.eenum:
        return simple.values
    return tuple(v for v in vocabularies.literals(simple.eenum) if v not in simple.left_out)


def enumerations() -> dict[str, Simple]:
    """Every named enumerated type of the schema, by name, in the order of :data:`LAYOUT`."""
    found = _Definitions().simple_types
    return {n: found[n] for n in LAYOUT if n in found and (found[n].values or found[n].eenum)}


def schema_text() -> str:
    """The schema, as the package ships it."""
    definitions = _Definitions()
    written = definitions.written()
    placed = [n for n in LAYOUT if not n.startswith("==")]
    if sorted(placed) != sorted(written):
        missing = sorted(set(written) - set(placed))
        extra = sorted(set(placed) - set(written))
        raise ValueError(f"LAYOUT does not place {missing} or places what is not needed: {extra}")
    out = [HEADER]
    previous = ""
    for name in LAYOUT:
        # a blank line between definitions, but before a heading's first and between simple types
        simple = name in definitions.simple_types
        if not (previous == "==" or (simple and previous == "simple")):
            out.append("\n")
        if name.startswith("=="):
            out.append(f"  <!-- {'=' * 60} {name[2:].strip()} -->\n")
            previous = "=="
        else:
            out.extend(line + "\n" for line in written[name])
            previous = "simple" if simple else "complex"
    out.append("</xs:schema>\n")
    return "".join(out)


class _Definitions:
    """The schema's definitions, found by walking the declaration from the application."""

    def __init__(self) -> None:
        self.root = layout(Application)
        self.types: dict[str, Layout] = {}
        self.name_lists: dict[str, Part] = {}
        self.simple_types: dict[str, Simple] = {}
        self.group_lines: dict[str, list[str]] = {}
        self.documented: set[str | tuple[str, str]] = set()
        self._walk(self.root)

    def _walk(self, declared: Layout) -> None:
        for part in declared.fields:
            if part.node.role == "attribute":
                self._simple(part.node.type)
            if part.node.role == "names" and part.node.schema_type:
                self.name_lists[part.node.schema_type] = part
            if part.layout is not None and part.layout.element.name not in self.types:
                self.types[part.layout.element.name] = part.layout
                self._walk(part.layout)

    def _simple(self, simple: Simple | None) -> None:
        while simple is not None and simple.name and not simple.name.startswith("xs:"):
            self.simple_types[simple.name] = simple
            self._simple(simple.item)
            simple = simple.base

    def documentation(self, key: str | tuple[str, str]) -> str | None:
        if key in DOCUMENTATION:
            self.documented.add(key)
        return DOCUMENTATION.get(key)

    # ------------------------------------------------------------------------------ writing
    def written(self) -> dict[str, list[str]]:
        out = {name: self.simple_type(s) for name, s in self.simple_types.items()}
        out.update({name: self.complex_type(p) for name, p in self.types.items()})
        out.update({name: self.name_list_type(name) for name in self.name_lists})
        out["application"] = self.document()
        # after the types: writing them finds the groups' lines
        for name, lines in self.group_lines.items():
            if name in ATTRIBUTE_GROUPS:
                out[name] = [
                    f'  <xs:attributeGroup name="{name}">',
                    *lines,
                    "  </xs:attributeGroup>",
                ]
            else:
                sequence = ["    <xs:sequence>", *lines, "    </xs:sequence>"]
                out[name] = [f'  <xs:group name="{name}">', *sequence, "  </xs:group>"]
        unused = set(DOCUMENTATION) - self.documented
        if unused:
            raise ValueError(f"DOCUMENTATION documents what the schema does not have: {unused}")
        return out

    def simple_type(self, simple: Simple) -> list[str]:
        lines = [f'  <xs:simpleType name="{simple.name}">']
        documentation = simple.doc
        if simple.eenum:
            documentation = f"The literals of EEnum {simple.eenum} of the metamodel, acordcs.ecore"
            if simple.left_out:
                documentation += f", but {', '.join(simple.left_out)} ({simple.why})"
            documentation += "."
        lines += _annotation(documentation, 4)
        return [*lines, *_restriction(simple, 4), "  </xs:simpleType>"]

    def complex_type(self, declared: Layout, indent: int = 2) -> list[str]:
        pad = " " * indent
        name = declared.element.name
        lines = [f'{pad}<xs:complexType name="{name}">', *_annotation(self.documentation(name), 4)]
        if declared.text is not None:
            lines += [
                "    <xs:simpleContent>",
                f'      <xs:extension base="{declared.text.node.type.reference}">',
                *self.attributes(declared.attributes, 8),
                "      </xs:extension>",
                "    </xs:simpleContent>",
            ]
        else:
            particles = [(p.xml, self.particle(name, p, 6)) for p in declared.children]
            if particles:
                lines += ["    <xs:sequence>", *self.grouped(particles, GROUPS, "group", 6)]
                lines.append("    </xs:sequence>")
            lines += self.attributes(declared.attributes, 4)
        return [*lines, f"{pad}</xs:complexType>"]

    def name_list_type(self, name: str) -> list[str]:
        return [
            f'  <xs:complexType name="{name}">',
            *_annotation(self.documentation(name), 4),
            '    <xs:attribute name="name" type="xs:string" use="required"/>',
            "  </xs:complexType>",
        ]

    def attributes(self, parts: tuple[Part, ...], indent: int) -> list[str]:
        written = [(p.xml, _attribute(p, indent)) for p in parts]
        return self.grouped(written, ATTRIBUTE_GROUPS, "attributeGroup", indent)

    def grouped(
        self,
        written: list[tuple[str, list[str]]],
        groups: Mapping[str, tuple[str, ...]],
        kind: str,
        indent: int,
    ) -> list[str]:
        """``written`` (name, lines) with each run of a group's names as a reference to it."""
        names = [n for n, _ in written]
        out: list[str] = []
        i = 0
        while i < len(written):
            for group, members in groups.items():
                if tuple(names[i : i + len(members)]) == members:
                    lines = [line for _, ls in written[i : i + len(members)] for line in ls]
                    own = 4 if kind == "attributeGroup" else 6  # the indent in the group
                    shared = [line[indent - own :] for line in lines]
                    if self.group_lines.setdefault(group, shared) != shared:
                        raise ValueError(f"{group}: its members differ where it is used")
                    out.append(f'{" " * indent}<xs:{kind} ref="d:{group}"/>')
                    i += len(members)
                    break
            else:
                out += written[i][1]
                i += 1
        return out

    def particle(self, owner: str, part: Part, indent: int) -> list[str]:
        pad = " " * indent
        role = part.node.role
        if role == "documentation":
            typed = ' type="xs:string"'
        elif role == "names":
            schema_type = part.node.schema_type
            typed = f' type="d:{schema_type}"' if schema_type else ""
        else:
            assert part.layout is not None
            typed = f' type="d:{part.layout.element.name}"'
        occurs = ' minOccurs="0"' if role == "documentation" or part.optional else ""
        if role in ("children", "names"):
            occurs = ' minOccurs="0" maxOccurs="unbounded"'
        head = f'{pad}<xs:element name="{part.xml}"{typed}{occurs}'
        inner = _annotation(self.documentation((owner, part.xml)), indent + 2)
        if role == "names" and not part.node.schema_type:
            inner += [
                f"{pad}  <xs:complexType>",
                f'{pad}    <xs:attribute name="name" type="xs:string" use="required"/>',
                f"{pad}  </xs:complexType>",
            ]
        return [head + ">", *inner, f"{pad}</xs:element>"] if inner else [head + "/>"]

    def document(self) -> list[str]:
        root = self.root
        lines = [f'  <xs:element name="{root.element.name}">', "    <xs:complexType>"]
        lines.append("      <xs:sequence>")
        for part in root.children:  # the groups
            assert part.layout is not None
            item = part.layout.element.name
            lines += [
                f'        <xs:element name="{part.xml}">',
                "          <xs:complexType><xs:sequence>",
                *self.particle_of_group(part, item),
                "          </xs:sequence></xs:complexType>",
                "        </xs:element>",
            ]
        lines.append("      </xs:sequence>")
        lines += self.attributes(root.attributes, 6)
        lines += ["    </xs:complexType>", "", *self.constraints((), 4), "  </xs:element>"]
        return lines

    def particle_of_group(self, part: Part, item: str) -> list[str]:
        head = f'            <xs:element name="{part.node.item}" type="d:{item}" minOccurs="0" maxOccurs="unbounded"'
        inner = self.constraints((part.field,), 14)
        return [head + ">", *inner, "            </xs:element>"] if inner else [head + "/>"]

    def constraints(self, scope: tuple[str, ...], indent: int) -> list[str]:
        pad = " " * indent
        lines: list[str] = []
        for key in IDENTITY:
            if key.scope != scope:
                continue
            if key.comment:
                lines.append(f"{pad}<!-- {key.comment} -->")
            refer = f' refer="d:{key.refer}"' if key.refer else ""
            selector = " | ".join(self.xpath(key.scope, path) for path in key.selectors)
            field = self.attribute_of(key.scope, key.selectors[0], key.field)
            lines += [
                f'{pad}<xs:{key.kind} name="{key.name}"{refer}>',
                f'{pad}  <xs:selector xpath="{selector}"/>',
                f'{pad}  <xs:field xpath="@{field}"/>',
                f"{pad}</xs:{key.kind}>",
            ]
        return lines

    def _steps(self, scope: tuple[str, ...], path: tuple[str, ...]) -> Iterator[Part]:
        declared: Layout | None = self.root
        for name in (*scope, *path):
            if declared is None:
                raise ValueError(f"IDENTITY: {'.'.join(path)} goes past a name list")
            part = declared.part(name)
            yield part
            declared = part.layout

    def xpath(self, scope: tuple[str, ...], path: tuple[str, ...]) -> str:
        steps = list(self._steps(scope, path))[len(scope) :]
        tags = [
            t for p in steps for t in ((p.xml, p.node.item) if p.node.role == "group" else (p.xml,))
        ]
        return "/".join("d:" + t for t in tags)

    def attribute_of(self, scope: tuple[str, ...], path: tuple[str, ...], field: str) -> str:
        last = list(self._steps(scope, path))[-1]
        if last.layout is None:  # a name list's elements have their name
            if field != "name":
                raise ValueError(f"IDENTITY: a name list's elements have no {field}")
            return "name"
        return last.layout.part(field).xml


def _annotation(documentation: str | None, indent: int) -> list[str]:
    if not documentation:
        return []
    text = escape(documentation)
    return [
        f"{' ' * indent}<xs:annotation><xs:documentation>{text}</xs:documentation></xs:annotation>"
    ]


def _restriction(simple: Simple, indent: int) -> list[str]:
    """A simple type's content: a list, or a restriction of its base by its facets (an inline
    one with a single facet on one line, as the endpoint's protocol is written)."""
    pad = " " * indent
    if simple.item is not None:
        return [f'{pad}<xs:list itemType="{simple.item.reference}"/>']
    assert simple.base is not None, simple
    facets = [(k, v) for k, v in simple.facets]
    facets += [("enumeration", v) for v in enumeration_values(simple)]
    written = [f"<xs:{k} value={quoteattr(v)}/>" for k, v in facets]
    head = f'{pad}<xs:restriction base="{simple.base.reference}">'
    if not simple.name and len(written) == 1:
        return [f"{head}{written[0]}</xs:restriction>"]
    return [head, *(f"{pad}  {w}" for w in written), f"{pad}</xs:restriction>"]


def _attribute(part: Part, indent: int) -> list[str]:
    pad = " " * indent
    simple = part.node.type
    use = ""
    if part.codec == "flag":
        use = ' default="false"'  # written only when true
    elif not (part.optional or part.node.empty_absent):
        use = ' use="required"'
    if simple.name:
        return [f'{pad}<xs:attribute name="{part.xml}" type="{simple.reference}"{use}/>']
    return [
        f'{pad}<xs:attribute name="{part.xml}"{use}>',
        f"{pad}  <xs:simpleType>",
        *_restriction(simple, indent + 4),
        f"{pad}  </xs:simpleType>",
        f"{pad}</xs:attribute>",
    ]
