"""Reader for XMI 2.x as BOUML (exporters 1.10 to 5.x, UML 2.0 to 2.3), Eclipse UML2 / Papyrus, Modelio,
Enterprise Architect, MagicDraw / Cameo and Visual Paradigm write it.

All follow the UML 2 XMI mapping, so one walker serves them; they differ in how they write references
(BOUML: ``<type xmi:idref=..>`` children; Eclipse: ``type=".."`` attributes holding ids), comments
(BOUML: a ``body`` attribute owned implicitly; Eclipse: a ``<body>`` child and ``annotatedElement``),
stereotype tags (BOUML also repeats them in ``xmi:Extension`` blocks) and where stereotype applications
stand: after the model at the root (BOUML, Eclipse, MagicDraw) or inside ``uml:Model`` (Enterprise
Architect). ``xmi:Extension`` blocks of other tools (EA's types and diagrams, MagicDraw's copies of its
own profiles and its diagrams) are not model content and are not read. See
``shared/reference/bouml-xmi.md`` and ``docs/uml-tools.md``.
"""

from __future__ import annotations

import re

from lxml import etree

from acordcs.diagnostics import diagnostic
from acordcs.xmi.readers.common import (
    primitive_from_href,
)
from acordcs.xmi.readers.references import References
from acordcs.xmi.readers.skipped import Skipped, metamodel_of
from acordcs.xmi.readers.stereotypes import StereotypeApplications, local_name
from acordcs.xmi.source import XmlInput
from acordcs.xmi.uml import (
    CLASSIFIER_KINDS,
    Association,
    Classifier,
    Dependency,
    Element,
    Generalization,
    Operation,
    Package,
    Parameter,
    Property,
    UmlModel,
)

# Eclipse profile schemas (http://www.eclipse.org/uml2/schemas/Ecore/5) share the prefix: match only
# the UML metamodel's own URI.
# The metamodel's URI ends at its version: MagicDraw also binds .../UML/20131001/StandardProfile and
# .../MagicDrawProfile, profiles whose elements are stereotype applications, not UML.
_UML_NS = re.compile(
    r"^https?://(schema\.omg\.org|www\.omg\.org)/spec/UML/\d+(\.\d+)*/?$"
    r"|^http://www\.eclipse\.org/uml2/\d+(\.\d+)*/UML$"
)
_XMI_NS = re.compile(r"^https?://(schema\.omg\.org|www\.omg\.org)/(spec/)?XMI")
# Containment of packageable elements: a package's members, and what a classifier owns in UML 2.5
# (nested classifiers, use cases, behaviours; a node's nodes, an artifact's artifacts), each with
# the metaclass an element without xmi:type has there (Eclipse UML2 writes the type only when it
# differs from the feature's; an abstract one, never read, says the type is missing).
_MEMBER_KINDS = {
    "packagedElement": "Package",
    "ownedMember": "Package",
    "ownedElement": "Package",
    "ownedStereotype": "Stereotype",
    "nestedClassifier": "Classifier",
    "ownedType": "Type",
    "ownedUseCase": "UseCase",
    "ownedBehavior": "Behavior",
    "nestedNode": "Node",
    "nestedArtifact": "Artifact",
}
_MEMBER_TAGS = frozenset(_MEMBER_KINDS)
# Children that are no model content of their own: references and machinery, read where needed
# (a profile application's profile is named by its applications' namespace) or not at all.
_NOT_CONTENT = frozenset(
    ["profileApplication", "packageImport", "elementImport", "packageMerge", "eAnnotations"]
)
_PACKAGE_KINDS = frozenset(("Package", "Model", "Profile"))
# What the children of a property or an operation are, by local tag name.
_TYPE, _DEFAULT, _LOWER, _UPPER, _EXT, _COMMENT, _PARAM = range(7)
_DEPENDENCY_KINDS = frozenset(
    ("Dependency", "Realization", "Usage", "Abstraction", "Substitution", "InterfaceRealization")
)


def _namespaces(root: etree._Element) -> tuple[str | None, str | None]:
    uml = xmi = None
    for uri in (root.nsmap or {}).values():
        if uri and _UML_NS.match(uri):
            uml = uri
        elif uri and (_XMI_NS.match(uri) or uri == "http://www.omg.org/XMI"):
            xmi = uri
    return uml, xmi


def accepts(root: etree._Element) -> bool:
    uml, _ = _namespaces(root)
    return uml is not None


def read(xml: XmlInput, tool: str | None = None) -> UmlModel:
    """The UML view of ``xml``; ``tool``, the known tool that wrote it (see
    :mod:`acordcs.xmi.readers.exporters`), decides how a type no UML version defines is reported."""
    return _Reader(xml, tool).read()


class _Reader(References):
    def __init__(self, xml: XmlInput, tool: str | None = None) -> None:
        self.xml = xml
        self.tool = tool
        root = xml.root
        uml, xmi = _namespaces(root)
        self.uml_ns = uml
        self.xmi_ns = xmi or "http://schema.omg.org/spec/XMI/2.1"
        self.XID = f"{{{self.xmi_ns}}}id"
        self.XTYPE = f"{{{self.xmi_ns}}}type"
        self.XIDREF = f"{{{self.xmi_ns}}}idref"
        self.EXTENSION = f"{{{self.xmi_ns}}}Extension"
        dialect = "eclipse-uml2" if "eclipse.org" in uml else "bouml-xmi2"
        self.model = UmlModel(file=xml.path, dialect=dialect)
        self.stereotypes = StereotypeApplications(self.model, self.XID)
        self.skipped = Skipped(self.model, "uml:")
        self._roles: dict[str, str] | None = None  # ids of ACORD-CS elements, for R201
        self._handlers = {
            "ownedAttribute": self._on_attribute,
            "ownedPort": self._on_attribute,  # Enterprise Architect: ports apart from attributes
            "ownedEnd": self._on_end,
            "memberEnd": self._on_member_end,
            "ownedOperation": self._on_operation,
            "ownedLiteral": self._on_literal,
            "generalization": self._generalization,
            "ownedComment": self._comment,
            self.EXTENSION: self.stereotypes.extension,
            "profileApplication": self._profile_application,
            **{tag: self._member(kind) for tag, kind in _MEMBER_KINDS.items()},
        }
        self._property_children = {
            "type": _TYPE,
            "defaultValue": _DEFAULT,
            "lowerValue": _LOWER,
            "upperValue": _UPPER,
            "ownedComment": _COMMENT,
            self.EXTENSION: _EXT,
        }
        self._operation_children = {
            "ownedParameter": _PARAM,
            "ownedComment": _COMMENT,
            self.EXTENSION: _EXT,
        }
        self.elements = self.model.elements
        self._href_names: dict[str, str] = {}  # a few distinct hrefs, written thousands of times
        self.annotated: list[tuple[str, str]] = []  # (element id, comment body), Eclipse comments
        self.refs: list[tuple[str, str, int, Element]] = []  # (id, what, line, from element)
        self.type_refs: list[Element] = []
        self._own_prefixes = (f"{{{self.uml_ns}}}", f"{{{self.xmi_ns}}}")

    # ------------------------------------------------------------------ entry
    def read(self) -> UmlModel:
        root = self.xml.root
        model = self.model
        top = root
        if local_name(root.tag) == "XMI":
            for child in root:
                if not isinstance(child.tag, str):
                    continue
                local = local_name(child.tag)
                if child.tag == f"{{{self.xmi_ns}}}Documentation":
                    model.exporter = (
                        f"{child.get('exporter', '')} {child.get('exporterVersion', '')}".strip()
                        or None
                    )
                elif local == "Diagram" and child.tag.startswith(f"{{{self.uml_ns}}}"):
                    continue  # Visual Paradigm's diagrams after the model: not model content
                elif child.tag.startswith(f"{{{self.uml_ns}}}"):
                    self._packageable(child, None)
                    if local == "Model" and not model.name:
                        model.name = child.get("name", "")
                elif child.tag == self.EXTENSION or child.tag == "profileApplication":
                    continue
                elif child.tag in _MEMBER_TAGS:  # BOUML's "no model" option: packages at the top
                    self._packageable(child, None)
                else:
                    self.stereotypes.root_application(child)
        else:  # Eclipse: a single uml:Model (or Package/Profile) as the document root
            self._packageable(top, None)
            model.name = top.get("name", "")
        ids = self.xml.ids(self.xmi_ns)
        self._resolve(ids, set(ids))
        if self.skipped:
            self.skipped.report(self.tool if self.tool != "acordcs" else None, self._acordcs_in)
        return model

    # ------------------------------------------------------------------ structure
    def _kind(self, el: etree._Element, default: str) -> str:
        xtype = el.get(self.XTYPE)
        if xtype:
            return xtype.rpartition(":")[2]
        if el.tag.startswith(f"{{{self.uml_ns}}}"):
            return local_name(el.tag)
        return default

    def _base(self, el: etree._Element, kind: str, owner: Element | None, cls=Element):
        ident = el.get(self.XID)
        line = el.sourceline or 0
        if ident is None:
            ident = f"<line {line}>"
            if kind == "Model":  # Enterprise Architect writes none; nothing refers to the model
                obj = cls(ident, kind, el.get("name", ""), line, owner)
                self.elements.setdefault(ident, obj)
                return obj
            self.model.diagnostics.append(
                diagnostic(
                    "R207",
                    f"{kind} {el.get('name', '')!r} has no xmi:id; references to it cannot work",
                    file=self.model.file,
                    line=line,
                )
            )
        obj = cls(ident, kind, el.get("name", ""), line, owner)
        self.elements.setdefault(ident, obj)
        return obj

    def _member(self, default: str):
        """The handler of a containment tag whose untyped elements are ``default``s."""
        if default == "Package":
            return self._packageable
        return lambda el, owner: self._packageable(el, owner, default)

    def _packageable(
        self, el: etree._Element, owner: Element | None, default: str = "Package"
    ) -> None:
        kind = self._kind(el, default)
        model = self.model
        if kind in _PACKAGE_KINDS:
            pkg = self._base(el, kind, owner, Package)
            if kind != "Model":
                model.packages.append(pkg)
            self._members(el, pkg)
        elif kind in CLASSIFIER_KINDS:
            cls = self._base(el, kind, owner, Classifier)
            model.classifiers.append(cls)
            if isinstance(owner, Classifier):
                owner.nested.append(cls)
            if kind == "AssociationClass":
                model.associations.append(cls)
            self._members(el, cls)
        elif kind == "Association":
            assoc = self._base(el, kind, owner, Association)
            model.associations.append(assoc)
            self._members(el, assoc)
        elif kind in _DEPENDENCY_KINDS:
            dep = self._base(el, kind, owner, Dependency)
            dep.clients = self._refs(el, "client")
            dep.suppliers = self._refs(el, "supplier")
            model.dependencies.append(dep)
            for ident in dep.clients + dep.suppliers:
                self.refs.append((ident, f"{kind} {dep.name!r}".strip(), dep.line, dep))
            self._extensions_only(el, dep)
        elif metamodel_of(kind) is not None:
            self._base(el, kind, owner)  # kept for its id: instances, events, extensions, ...
            # A profile's extensions are read from its stereotypes' applications (base_Class)
            if kind != "Extension" or owner is None or owner.kind != "Profile":
                self.skipped.add(kind, el.sourceline, el.get(self.XID), el)
        else:
            self.skipped.add(kind, el.sourceline, el.get(self.XID), el)

    def _profile_application(self, el: etree._Element, owner: Element) -> None:
        """Not model content; the profile it references is noted (the checks look for its file)."""
        for child in el:
            if child.tag == "appliedProfile" and child.get("href"):
                self.model.profile_references.append((child.get("href"), child.sourceline or 0))

    def _members(self, el: etree._Element, owner: Element) -> None:
        # One dict lookup per child: a 4 MB export has some 40,000 of them.
        handlers = self._handlers
        for child in el:
            handler = handlers.get(child.tag) or _by_local_name(handlers, child.tag)
            if handler is not None:
                handler(child, owner)
            elif (
                isinstance(child.tag, str)  # not an XML comment or processing instruction
                and child.tag[0:1] == "{"
                and not child.tag.startswith(self._own_prefixes)
            ):
                self._inner_application(child)
            elif isinstance(child.tag, str):
                self._unread_child(child)
        member_ends = el.get("memberEnd")
        if member_ends and isinstance(owner, Association | Classifier):
            owner.member_ends.extend(member_ends.split())

    def _unread_child(self, el: etree._Element) -> None:
        """A child the walk does not read: noted (R211) when it is a model element (it has a type
        or an id), not when it is a reference or machinery (imports, profile applications)."""
        xtype = el.get(self.XTYPE)
        if xtype is None and el.get(self.XID) is None:
            return
        local = local_name(el.tag)
        if local in _NOT_CONTENT:
            return
        kind = xtype.rpartition(":")[2] if xtype else f"<{local}>"
        self.skipped.add(kind, el.sourceline, el.get(self.XID), el)

    def _inner_application(self, el: etree._Element) -> None:
        """An element of a profile's namespace inside the model: Enterprise Architect writes its
        stereotype applications there (``<thecustomprofile:boundary base_Class=".."/>`` as the last
        children of ``uml:Model``), not after it."""
        if any(key.startswith("base_") for key in el.attrib):
            self.stereotypes.root_application(el)

    def _on_attribute(self, child: etree._Element, owner: Element) -> None:
        """An owned property: an association end, a port (``xmi:type="uml:Port"``, in
        ``ownedAttribute`` as Papyrus, BOUML and MagicDraw write it, or in Enterprise Architect's
        ``ownedPort``), or an attribute. A port is a Property in UML, but never an attribute of
        the application: the architecture reads it as a port (owned by its classifier) only."""
        if isinstance(owner, Classifier):
            prop = self._property(child, owner)
            if prop.association:
                owner.ends.append(prop)
            elif prop.kind == "Port" or local_name(child.tag) == "ownedPort":
                prop.kind = "Port"  # an ownedPort is one whatever its xmi:type says
                owner.ports.append(prop)
            else:
                owner.attributes.append(prop)

    def _on_end(self, child: etree._Element, owner: Element) -> None:
        if isinstance(owner, Association | Classifier):
            prop = self._property(child, owner)
            prop.navigable = child.get("isNavigable") != "false"
            if isinstance(owner, Association):
                owner.owned_ends.append(prop)

    def _on_member_end(self, child: etree._Element, owner: Element) -> None:
        if isinstance(owner, Association | Classifier):
            owner.member_ends.extend(self._refs_of(child))

    def _on_operation(self, child: etree._Element, owner: Element) -> None:
        if isinstance(owner, Classifier):
            owner.operations.append(self._operation(child, owner))

    def _on_literal(self, child: etree._Element, owner: Element) -> None:
        if isinstance(owner, Classifier):
            owner.literals.append(child.get("name", ""))
            self._base(child, "EnumerationLiteral", owner)

    def _extensions_only(self, el: etree._Element, owner: Element) -> None:
        for child in el:
            if child.tag == self.EXTENSION:
                self.stereotypes.extension(child, owner)
            elif isinstance(child.tag, str) and local_name(child.tag) == "ownedComment":
                self._comment(child, owner)

    def _refs_of(self, el: etree._Element) -> list[str]:
        ref = el.get(self.XIDREF)
        return [ref] if ref else []

    def _refs(self, el: etree._Element, name: str) -> list[str]:
        """Ids named by attribute ``name`` (space-separated) or by ``<name xmi:idref=..>`` children."""
        found = (el.get(name) or "").split()
        for child in el.iterchildren(name, f"{{{self.uml_ns}}}{name}"):
            found += self._refs_of(child)
        return found

    def _type_child(self, child: etree._Element, obj) -> None:
        href = child.get("href")
        if href:
            name = self._href_names.get(href)
            if name is None:
                name = self._href_names[href] = primitive_from_href(href)
            obj.type_name = name
        else:
            obj.type_ref = child.get(self.XIDREF) or obj.type_ref

    def _typed(self, el: etree._Element, obj) -> None:
        type_ids = el.get("type")
        if type_ids and (type_ids := type_ids.split()):
            obj.type_ref = type_ids[0]
        if len(el):
            for child in el.iterchildren("type"):
                self._type_child(child, obj)
        if obj.type_ref:
            self.type_refs.append(obj)

    def _property(self, el: etree._Element, owner: Element) -> Property:
        # The hottest code of a read (a large model has tens of thousands of properties and
        # parameters): one pass over the children, dispatched on the tag as written.
        xtype = el.get(self.XTYPE)
        prop = self._base(el, xtype.rpartition(":")[2] if xtype else "Property", owner, Property)
        prop.association = association = el.get("association")
        prop.aggregation = el.get("aggregation", "none")
        type_ids = el.get("type")
        if type_ids and (type_ids := type_ids.split()):
            prop.type_ref = type_ids[0]
        if len(el):
            children = self._property_children
            for child in el:
                code = children.get(child.tag)
                if code is None and (code := _by_local_name(children, child.tag)) is None:
                    continue
                if code == _TYPE:
                    self._type_child(child, prop)
                elif code == _DEFAULT:
                    prop.default = _literal(child)
                elif code == _LOWER:
                    prop.lower = _literal(child)
                elif code == _UPPER:
                    prop.upper = _literal(child)
                elif code == _EXT:
                    self.stereotypes.extension(child, prop)
                else:
                    self._comment(child, prop)
        if prop.type_ref:
            self.type_refs.append(prop)
        if association:
            self.refs.append((association, f"end {prop.name!r}", prop.line, prop))
        return prop

    def _operation(self, el: etree._Element, owner: Classifier) -> Operation:
        op = self._base(el, "Operation", owner, Operation)
        children = self._operation_children
        for child in el:
            code = children.get(child.tag)
            if code is None and (code := _by_local_name(children, child.tag)) is None:
                continue
            if code == _PARAM:
                param = self._base(child, "Parameter", op, Parameter)
                direction = child.get("direction")
                if direction is not None:
                    param.direction = direction.removeprefix("pk_")
                self._typed(child, param)
                op.parameters.append(param)
            elif code == _EXT:
                self.stereotypes.extension(child, op)
            elif code == _COMMENT:
                self._comment(child, op)
        return op

    def _generalization(self, el: etree._Element, owner: Element) -> None:
        gen = self._base(el, "Generalization", owner, Generalization)
        gen.specific = owner.id
        general = self._refs(el, "general")
        gen.general = general[0] if general else ""
        if isinstance(owner, Classifier) and gen.general:
            owner.generals.append(gen.general)
            self.refs.append((gen.general, f"generalization of {owner.name!r}", gen.line, owner))
        self.model.generalizations.append(gen)

    def _comment(self, el: etree._Element, owner: Element) -> None:
        body = el.get("body")
        if body is None:
            body = "".join(b.text or "" for b in el.iterchildren("body"))
        annotated = (el.get("annotatedElement") or "").split()
        if annotated:
            self.annotated += [(ident, body) for ident in annotated]
        else:
            owner.comments.append(body)


def _by_local_name(table: dict, tag: object):
    """``table``'s entry for a namespace-qualified tag (rare) by its local name; None for XML
    comments and processing instructions, and for plain tags (already looked up as written)."""
    if not isinstance(tag, str) or tag[0] != "{":
        return None
    return table.get(local_name(tag))


def _literal(el: etree._Element) -> str | None:
    value = el.get("value")
    if value is not None:
        return value
    kind = next((v for k, v in el.items() if k.endswith("}type")), "").rpartition(":")[2]
    return {"LiteralInteger": "0", "LiteralBoolean": "false", "LiteralReal": "0"}.get(kind)
