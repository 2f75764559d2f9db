"""Reader for XMI 1.1 and 1.2 (UML 1.3 and 1.4): BOUML's old plug-out (1.4.x), Umbrello, ArgoUML, Visual
Paradigm, MagicDraw 9 and Rational Rose (Unisys exporter).

The tools agree on the structure (``XMI.content``, ``UML:Namespace.ownedElement``,
``UML:Classifier.feature``) and differ in four ways, all read here:

- the UML namespace: ``org.omg.xmi.namespace.UML`` (BOUML, ArgoUML), ``http://schema.omg.org/spec/UML/1.3``
  (Umbrello), ``org.omg/UML/1.4`` (Visual Paradigm, MagicDraw 9), or unqualified elements (Rose's
  ``<Model>``, with ``xmlns:UML`` declared but unused);
- references: ``<UML:X.y><UML:Z xmi.idref=..>`` children (UML 1.4 form) or attributes holding ids
  (``type=``, ``stereotype=``, ``child=``/``parent=``, ``client=``/``supplier=``: Umbrello, Visual
  Paradigm);
- stereotypes: by name (BOUML), by ``xmi.idref`` to a ``UML:Stereotype`` (ArgoUML, Visual Paradigm), by
  a ``stereotype`` attribute holding its id (Umbrello), or from the stereotype's ``extendedElement``
  list (UML 1.3); all are free stereotypes (UML 1.x has no profiles);
- tagged values: ``tag=``/``value=`` attributes (UML 1.3, BOUML), ``TaggedValue.dataValue`` with a
  ``TagDefinition`` reference (UML 1.4), or at the content's top level with ``modelElement=`` (Rose).

``XMI.extension`` blocks (diagrams, tool options) are not model content: Umbrello's diagram widgets
reuse the ids of the classes they show, which are therefore not duplicates. Ids of BOUML's plug-out are
memory addresses (unstable across exports) and association ends may have none: the reader gives each
end an id derived from its association's.
"""

from __future__ import annotations

from lxml import etree

from acordcs.xmi.readers import ea
from acordcs.xmi.readers.common import (
    acordcs_roles,
    check_ids,
    dangling,
    described,
    primitive_from_href,
    relates,
    touched,
)
from acordcs.xmi.readers.skipped import Skipped
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
    StereotypeApplication,
    UmlModel,
)

NS = "org.omg.xmi.namespace.UML"  # BOUML's and ArgoUML's; other tools use other URIs (see above)


# Read as classifiers; AssociationClass is read with the associations, and in UML 1.x a
# Stereotype is a definition, no classifier.
_CLASSIFIERS = CLASSIFIER_KINDS - {"AssociationClass", "Stereotype"}


def accepts(root: etree._Element) -> bool:
    """XMI 1.x: an unqualified ``XMI`` root (XMI 2 puts it in the XMI namespace)."""
    return root.tag == "XMI" and (
        root.get("xmi.version") is not None or root.find("XMI.content") is not None
    )


def read(xml: XmlInput, exporter=None) -> UmlModel:
    return _Reader(xml, exporter).read()


def _idref(el: etree._Element | None) -> str | None:
    if el is None:
        return None
    for child in el:
        if isinstance(child.tag, str) and child.get("xmi.idref"):
            return child.get("xmi.idref")
    return None


def _uml_prefix(content: etree._Element | None) -> str:
    """``{namespace}`` of the UML elements as this file writes them ("" when unqualified)."""
    for el in content if content is not None else ():
        if isinstance(el.tag, str) and not el.tag.startswith("XMI."):
            return el.tag.rpartition("}")[0] + "}" if el.tag[0] == "{" else ""
    return f"{{{NS}}}"


class _Reader:
    def __init__(self, xml: XmlInput, exporter=None) -> None:
        self.xml = xml
        root = xml.root
        bouml = exporter is not None and exporter.tool == "bouml"
        version = root.get("xmi.version", "1.x")
        self.model = UmlModel(file=xml.path, dialect="bouml-xmi12" if bouml else f"xmi{version}")
        self.typed: list = []
        self.refs: list[tuple[str, str, int, Element]] = []
        self.ids: list[tuple[str, int]] = []
        self.content = root.find("XMI.content")
        self.U = U = _uml_prefix(self.content)
        self.OWNED = f"{U}Namespace.ownedElement"
        self.stereotype_refs: list[tuple[str, Element, int]] = []  # (Stereotype id, element, line)
        self.stereotype_names: dict[str, str] = {}  # Stereotype id -> name
        self.tag_names: dict[str, str] = {}  # TagDefinition id -> name
        self.tag_refs: list[tuple[str, str, Element]] = []  # (TagDefinition id, value, element)
        self.loose_tags: list[etree._Element] = []  # Rose: TaggedValue modelElement=".."
        self.ea = exporter is not None and exporter.tool == "enterprise-architect"
        self.tool = exporter.tool if exporter is not None and exporter.tool != "acordcs" else None
        self.profiled: set[tuple[str, str]] = set()  # (element, stereotype) EA gave a profile
        self.ea_twins: list[tuple[str, str, int]] = []  # (package id, $ea_xref_property, line)
        self.skipped = Skipped(self.model, "UML:")
        self._roles: dict[str, str] | None = None  # ids of ACORD-CS elements, for R201

    def read(self) -> UmlModel:
        root = self.xml.root
        exporter = root.find("XMI.header/XMI.documentation/XMI.exporter")
        version = root.find("XMI.header/XMI.documentation/XMI.exporterVersion")
        if exporter is not None:
            self.model.exporter = (
                f"{exporter.text or ''} {version.text if version is not None else ''}".strip()
            )
        content = self.content
        U = self.U
        for el in content if content is not None else ():
            if not isinstance(el.tag, str) or el.tag.startswith("XMI."):
                continue  # XMI.extension: diagrams and tool options
            if el.tag == f"{U}Model" and not self.model.name:
                self.model.name = el.get("name", "")
            self._element(el, None)
        self._resolve()
        if self.skipped:
            self.skipped.report(self.tool, self._acordcs_in)
        return self.model

    def _new(
        self,
        el: etree._Element,
        kind: str,
        owner: Element | None,
        cls=Element,
        ident: str | None = None,
    ):
        line = el.sourceline or 0
        own = el.get("xmi.id")
        ident = ident or own or f"<line {line}>"
        if own:
            self.ids.append((ident, line))
        obj = cls(ident, kind, el.get("name", ""), line, owner)  # positional: half the cost
        self.model.elements.setdefault(ident, obj)
        if len(el) or "stereotype" in el.attrib:
            self._stereotypes(el, obj)
        return obj

    def _owned(self, el: etree._Element, owner: Element) -> None:
        for child in el.iterchildren(self.OWNED):
            for member in child:
                if isinstance(member.tag, str) and not member.tag.startswith("XMI."):
                    self._element(member, owner)

    def _element(self, el: etree._Element, owner: Element | None) -> None:
        tag = el.tag
        model = self.model
        U = self.U
        if not tag.startswith(U):
            return  # another namespace: a tool's own element
        local = tag[len(U) :]  # compared as plain strings: a large export has thousands
        if local in _CLASSIFIERS:
            cls = self._new(el, local, owner, Classifier)
            model.classifiers.append(cls)
            if len(el):  # most data types and many classes of a large export have no children
                self._features(el, cls)
                if cls.kind == "Enumeration":
                    self._literals(el, cls)
                self._owned(el, cls)
        elif local == "Model" or local == "Package":
            pkg = self._new(el, local, owner, Package)
            if local == "Package":
                model.packages.append(pkg)
            self._owned(el, pkg)
        elif local == "Association" or local == "AssociationClass":
            self._association(el, owner)
        elif local == "Stereotype":  # UML 1.x: a stereotype is no classifier
            self._stereotype_definition(el)
        elif local == "Generalization":
            gen = self._new(el, "Generalization", owner, Generalization)
            gen.specific = self._ref(el, "child", "subtype") or ""
            gen.general = self._ref(el, "parent", "supertype") or ""
            model.generalizations.append(gen)
            for ident in (gen.specific, gen.general):
                if ident:
                    self.refs.append((ident, "generalization", gen.line, gen))
        elif local in ("Dependency", "Abstraction", "Usage"):
            dep = self._new(el, local, owner, Dependency)
            dep.clients = self._refs(el, "Dependency", "client")
            dep.suppliers = self._refs(el, "Dependency", "supplier")
            model.dependencies.append(dep)
            for ident in dep.clients + dep.suppliers:
                self.refs.append((ident, "dependency", dep.line, dep))
        elif local == "Comment" and owner is not None:
            owner.comments.append(el.get("body", ""))
        elif local == "TagDefinition":
            self.tag_names[el.get("xmi.id", "")] = el.get("name") or el.get("tagType", "")
        elif local == "TaggedValue" and el.get("modelElement"):
            self.loose_tags.append(el)
        elif local == "ClassifierRole" and self.ea and self._ea_package_twin(el):
            pass  # read for its package's stereotypes
        elif local != "Diagram":  # a diagram is a view of the model, not model content
            self.skipped.add(local, el.sourceline, el.get("xmi.id"), el)

    def _ref(self, el: etree._Element, *names: str) -> str | None:
        """The id a UML 1.x reference names: ``<UML:X.name><UML:Y xmi.idref=..>`` (UML 1.4) or an
        attribute ``name=".."`` (UML 1.3, Umbrello)."""
        kind = el.tag[len(self.U) :]
        for name in names:
            found = _idref(el.find(f"{self.U}{kind}.{name}")) or el.get(name)
            if found:
                return found.split()[0]
        return None

    def _refs(self, el: etree._Element, kind: str, name: str) -> list[str]:
        holder = el.find(f"{self.U}{kind}.{name}")
        found = (
            [c.get("xmi.idref") for c in holder if isinstance(c.tag, str)]
            if holder is not None
            else []
        )
        return [i for i in found if i] or (el.get(name) or "").split()

    def _literals(self, el: etree._Element, cls: Classifier) -> None:
        U = self.U
        for lit in [
            *el.iterchildren(f"{U}EnumerationLiteral"),
            *el.iterfind(f"{U}Enumeration.literal/{U}EnumerationLiteral"),
        ]:
            cls.literals.append(lit.get("name", ""))
            self._new(lit, "EnumerationLiteral", cls)

    def _stereotype_definition(self, el: etree._Element) -> None:
        ident = el.get("xmi.id")
        name = el.get("name", "")
        if ident:
            self.stereotype_names[ident] = name
            self.ids.append((ident, el.sourceline or 0))
        # UML 1.3: the stereotype lists them, as an attribute or (XMI 1.0) as references
        targets = (el.get("extendedElement") or "").split()
        for holder in el.iterchildren(f"{self.U}Stereotype.extendedElement"):
            targets += [
                c.get("xmi.idref") for c in holder if isinstance(c.tag, str) and c.get("xmi.idref")
            ]
        for target in targets:
            self.stereotype_refs.append((ident or name, target, el.sourceline or 0))

    def _features(self, el: etree._Element, cls: Classifier) -> None:
        U = self.U
        for feature in el.iterchildren(f"{U}Classifier.feature"):
            for f in feature:
                if f.tag == f"{U}Attribute":
                    prop = self._new(f, "Property", cls, Property)
                    self._type(f, prop, f"{U}StructuralFeature.type")
                    initial = f.find(f"{U}Attribute.initialValue/{U}Expression")
                    if initial is not None:
                        prop.default = initial.get("body")
                    cls.attributes.append(prop)
                elif f.tag == f"{U}Operation":
                    op = self._new(f, "Operation", cls, Operation)
                    for params in f.iterchildren(f"{U}BehavioralFeature.parameter"):
                        for p in params.iterchildren(f"{U}Parameter"):
                            param = self._new(p, "Parameter", op, Parameter)
                            param.direction = p.get("kind", "in").removeprefix("pk_")
                            self._type(p, param, f"{U}Parameter.type")
                            op.parameters.append(param)
                    cls.operations.append(op)
                elif (
                    isinstance(f.tag, str) and f.tag.startswith(U) and not f.tag.startswith("XMI.")
                ):
                    self.skipped.add(f.tag[len(U) :], f.sourceline, f.get("xmi.id"), f)

    def _type(self, el: etree._Element, obj, wrapper: str) -> None:
        if el.get("type"):
            obj.type_ref = el.get("type")
        ref = _idref(el.find(wrapper))
        if ref:
            obj.type_ref = ref
        holder = el.find(wrapper)
        if holder is not None:
            for child in holder:
                if isinstance(child.tag, str) and child.get("href"):
                    obj.type_name = primitive_from_href(child.get("href"))
        if obj.type_ref:
            self.typed.append(obj)

    def _association(self, el: etree._Element, owner: Element | None) -> None:
        U = self.U
        is_class = el.tag == f"{U}AssociationClass"
        cls = Classifier if is_class else Association
        assoc = self._new(el, "AssociationClass" if is_class else "Association", owner, cls)
        self.model.associations.append(assoc)
        if is_class:
            self.model.classifiers.append(assoc)
            self._features(el, assoc)
        for n, end in enumerate(el.iterfind(f"{U}Association.connection/{U}AssociationEnd")):
            prop = self._new(
                end, "Property", assoc, Property, ident=end.get("xmi.id") or f"{assoc.id}#end{n}"
            )
            prop.association = assoc.id
            prop.aggregation = end.get("aggregation", "none")
            prop.navigable = end.get("isNavigable") != "false"
            prop.type_ref = (
                end.get("type")
                or _idref(end.find(f"{U}AssociationEnd.participant"))  # UML 1.4
                or _idref(end.find(f"{U}AssociationEnd.type"))  # UML 1.3 in XMI 1.0
            )
            if prop.type_ref:
                self.typed.append(prop)
            assoc.member_ends.append(prop.id)
            if isinstance(assoc, Association):
                assoc.owned_ends.append(prop)

    def _apply(self, name: str, obj: Element, line: int, profile: str | None = None) -> None:
        key = (obj.id, f"{profile}:{name}" if profile else name)
        if name and key not in self.model.applications:
            app = StereotypeApplication(profile=profile, name=name, base=obj.id, line=line)
            app.places.add("xmi12")
            self.model.applications[key] = app

    def _stereotypes(self, el: etree._Element, obj: Element) -> None:
        U = self.U
        if el.get("stereotype"):  # Umbrello, UML 1.3: the stereotype's id
            for ident in el.get("stereotype").split():
                self.stereotype_refs.append((ident, obj, el.sourceline or 0))
        if not len(el):
            return
        for holder in el.iterchildren(f"{U}ModelElement.stereotype"):
            for st in holder.iterchildren(f"{U}Stereotype"):
                if st.get("xmi.idref"):  # ArgoUML, Visual Paradigm: a reference
                    self.stereotype_refs.append((st.get("xmi.idref"), obj, st.sourceline or 0))
                else:
                    self._apply(st.get("name", ""), obj, st.sourceline or 0)
        for holder in el.iterchildren(f"{U}ModelElement.taggedValue"):
            for tv in holder.iterchildren(f"{U}TaggedValue"):
                tag = tv.get("tag", "")
                value = tv.get("value")
                if value is None:  # UML 1.4: <TaggedValue.dataValue> and a TagDefinition
                    value = tv.findtext(f"{U}TaggedValue.dataValue") or ""
                if not tag:
                    definition = _idref(tv.find(f"{U}TaggedValue.type"))
                    if definition:
                        self.tag_refs.append((definition, value, obj))
                    continue
                if self.ea:
                    self._ea_tag(tag, value, obj, tv.sourceline or 0)
                elif tag != "stereotype":  # BOUML repeats the stereotype as a tag
                    obj.tagged_values[tag] = value

    def _ea_tag(self, tag: str, value: str, obj: Element, line: int) -> None:
        """Enterprise Architect's XMI 1.1: profile stereotypes in ``$ea_xref_property``; its own
        element properties (``ea_guid``, ...) are not the modeller's tags."""
        if tag == ea.XREF_TAG:
            for profile, name in ea.stereotypes(value):
                self._apply(name, obj, line, profile)
                if profile:  # EA also names it as a free stereotype: one application
                    self.model.applications.pop((obj.id, name), None)
                    self.profiled.add((obj.id, name))
        elif not ea.own_tag(tag):
            obj.tagged_values[tag] = value

    def _ea_package_twin(self, el: etree._Element) -> bool:
        """Enterprise Architect writes each package a second time, as a ``UML:ClassifierRole`` of
        the parent package's ``Collaborations`` (the package as an element of a diagram), with
        tagged values ``ea_stype="Package"``, ``package2`` (the package's own id, ``EAID_<guid>``
        where the ``UML:Package`` is ``EAPK_<guid>``) and, there rather than on the package, the
        ``$ea_xref_property`` whose ``FQName`` names the profile of the package's stereotypes.
        Whether ``el`` is such a twin; if so, its stereotypes are the package's."""
        values = {
            tv.get("tag"): tv.get("value", "")
            for holder in el.iterchildren(f"{self.U}ModelElement.taggedValue")
            for tv in holder.iterchildren(f"{self.U}TaggedValue")
        }
        if values.get("ea_stype") != "Package":
            return False
        xref = values.get(ea.XREF_TAG)
        if xref:
            for ident in (values.get("package2"), el.get("xmi.id")):
                if ident:
                    self.ea_twins.append((ident, xref, el.sourceline or 0))
        return True

    def _ea_twin_stereotypes(self) -> None:
        elements = self.model.elements
        for ident, xref, line in self.ea_twins:
            package = elements.get(ident) or elements.get(ident.replace("EAID_", "EAPK_", 1))
            if package is None or package.kind not in ("Package", "Model"):
                continue
            for profile, name in ea.stereotypes(xref):
                if profile:
                    self._apply(name, package, line, profile)
                    self.model.applications.pop((package.id, name), None)
                    self.profiled.add((package.id, name))

    def _resolve_stereotypes(self) -> None:
        self._ea_twin_stereotypes()
        elements = self.model.elements
        for ident, target, line in self.stereotype_refs:
            obj = target if isinstance(target, Element) else elements.get(target)
            if obj is not None:
                self._apply(self.stereotype_names.get(ident, ident), obj, line)
        for key in self.profiled:  # a free stereotype read after EA's profiled one
            self.model.applications.pop(key, None)
        for ident, value, obj in self.tag_refs:
            obj.tagged_values[self.tag_names.get(ident, ident)] = value
        for tv in self.loose_tags:  # Rose: tagged values listed after the model
            obj = elements.get(tv.get("modelElement", ""))
            if obj is not None and tv.get("tag"):
                obj.tagged_values[tv.get("tag")] = tv.get("value", "")

    def _acordcs_in(self, el: etree._Element) -> str | None:
        """What ACORD-CS reads in a skipped element ``el`` (R201): an element in it (or it) with an
        ACORD-CS stereotype, by name (``<UML:Stereotype name="CtxComponent"/>``, EA's
        ``FQName=ACORDCS::...``) or by reference to a stereotype so named, or references from it
        to two elements that have one (a relation ACORD-CS would read). None when there is none."""
        from acordcs.profile import stereotype

        if self._roles is None:  # once per file: thousands of skipped elements are possible
            self._roles = acordcs_roles(self.model)
        roles = self._roles
        named = {i for i, n in self.stereotype_names.items() if stereotype(n) is not None}
        related: list[str] = []
        for node in el.iter(etree.Element):
            ident = node.get("xmi.id")
            if ident in roles:
                return "holds " + described(self.model, roles, ident, node.get("name", ""))
            local = node.tag.rpartition("}")[2]
            if local == "Stereotype" and stereotype(node.get("name", "")) is not None:
                return f"has the stereotype <<{node.get('name')}>>"
            if local == "TaggedValue" and "FQName=ACORDCS::" in node.get("value", ""):
                return "has an ACORDCS stereotype (Enterprise Architect's $ea_xref_property)"
            for key, value in node.attrib.items():
                if key in ("xmi.id", "name"):
                    continue
                for token in value.split():
                    if token in named:
                        return f"has the stereotype <<{self.stereotype_names[token]}>>"
                    if token in roles:
                        related.append(token)
        return relates(self.model, roles, related)

    def _joined(self, source: Element) -> list[str]:
        """The ids a relation joins: a dependency's clients and suppliers, a generalization's
        classes, an association end's association's ends and their types."""
        if isinstance(source, Dependency):
            return source.clients + source.suppliers
        if isinstance(source, Generalization):
            return [source.specific, source.general]
        if isinstance(source, Property) and isinstance(source.owner, Association):
            ends = source.owner.owned_ends
            return [e.type_ref for e in ends if e.type_ref and e is not source]
        return []

    def _resolve(self) -> None:
        model = self.model
        self._resolve_stereotypes()
        known = check_ids(model, self.ids)
        known |= set(model.elements)
        roles = acordcs_roles(model)  # what makes a reference out of the file an error
        for obj in self.typed:
            target = model.elements.get(obj.type_ref)
            if target is not None:
                obj.type_name = target.name
            else:
                dangling(
                    model,
                    obj.type_ref,
                    f"type of {obj.name!r}",
                    obj.line,
                    obj.qualified_name(),
                    touched(model, roles, obj, self._joined(obj)),
                )
        for ident, what, line, source in self.refs:
            if ident not in known:
                dangling(
                    model,
                    ident,
                    what,
                    line,
                    source.qualified_name(),
                    touched(model, roles, source, self._joined(source)),
                )
        generals: dict[str, list[str]] = {}
        for gen in model.generalizations:
            if gen.general:
                generals.setdefault(gen.specific, []).append(gen.general)
        for cls in model.classifiers:
            cls.generals = generals.get(cls.id, [])
