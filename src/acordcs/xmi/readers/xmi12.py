"""Reader for XMI 1.2 (UML 1.4) as BOUML's old plug-out (1.4.x) writes it.

Ids there are memory addresses (unstable across exports) and association ends have none: the reader
gives each end an id derived from its association's. Stereotypes are free names
(``<UML:ModelElement.stereotype><UML:Stereotype name=..>``) and tags are the element's tagged values.
"""

from __future__ import annotations

import difflib

from lxml import etree

from acordcs.diagnostics import diagnostic
from acordcs.xmi.readers.common import check_ids, dangling, primitive_from_href
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

NS = "org.omg.xmi.namespace.UML"
# UML 1.4 metaclasses that may stand in a namespace: anything else is reported (R201).
UML14_METACLASSES = frozenset(
    """Model Package Subsystem Class Interface DataType Primitive Enumeration
    ProgrammingLanguageDataType Actor UseCase Component Node Signal Exception Association
    AssociationClass Generalization Dependency Abstraction Usage Permission Binding Comment
    Stereotype TagDefinition Collaboration Instance Object Link Stimulus StateMachine
    ActivityGraph Constraint ClassifierRole AssociationRole Artifact Include Extend
    CallEvent SignalEvent TimeEvent ChangeEvent Flow""".split()
)
U = f"{{{NS}}}"
_CLASSIFIER_TAGS = {f"{U}{k}": k for k in CLASSIFIER_KINDS}


def accepts(root: etree._Element) -> bool:
    return root.tag == "XMI" and NS in (root.nsmap or {}).values()


def read(xml: XmlInput) -> UmlModel:
    return _Reader(xml).read()


def _idref(el: etree._Element | None) -> str | None:
    if el is None:
        return None
    for child in el:
        if isinstance(child.tag, str) and child.get("xmi.idref"):
            return child.get("xmi.idref")
    return None


class _Reader:
    def __init__(self, xml: XmlInput) -> None:
        self.xml = xml
        self.model = UmlModel(file=xml.path, dialect="bouml-xmi12")
        self.typed: list = []
        self.refs: list[tuple[str, str, int, Element]] = []
        self.ids: list[tuple[str, int]] = []

    def read(self) -> UmlModel:
        root = self.xml.root
        exporter = root.find("XMI.header/XMI.documentation/XMI.exporter")
        version = root.find("XMI.header/XMI.documentation/XMI.exporterVersion")
        if exporter is not None:
            self.model.exporter = (
                f"{exporter.text or ''} {version.text if version is not None else ''}".strip()
            )
        content = root.find("XMI.content")
        for el in content if content is not None else ():
            if el.tag == f"{U}Model":
                self.model.name = el.get("name", "")
            self._element(el, None)
        self._resolve()
        return self.model

    def _new(
        self,
        el: etree._Element,
        kind: str,
        owner: Element | None,
        cls=Element,
        ident: str | None = None,
    ):
        ident = ident or el.get("xmi.id") or f"<line {el.sourceline}>"
        if el.get("xmi.id"):
            self.ids.append((ident, el.sourceline or 0))
        obj = cls(
            id=ident, kind=kind, name=el.get("name", ""), line=el.sourceline or 0, owner=owner
        )
        self.model.elements.setdefault(ident, obj)
        self._stereotypes(el, obj)
        return obj

    def _owned(self, el: etree._Element, owner: Element) -> None:
        for child in el.iterchildren(f"{U}Namespace.ownedElement"):
            for member in child:
                if isinstance(member.tag, str):
                    self._element(member, owner)

    def _element(self, el: etree._Element, owner: Element | None) -> None:
        tag = el.tag
        model = self.model
        if tag in (f"{U}Model", f"{U}Package"):
            pkg = self._new(el, "Model" if tag == f"{U}Model" else "Package", owner, Package)
            if pkg.kind == "Package":
                model.packages.append(pkg)
            self._owned(el, pkg)
        elif tag == f"{U}Association" or tag == f"{U}AssociationClass":
            self._association(el, owner)
        elif tag in _CLASSIFIER_TAGS:
            cls = self._new(el, _CLASSIFIER_TAGS[tag], owner, Classifier)
            model.classifiers.append(cls)
            self._features(el, cls)
            self._owned(el, cls)
        elif tag == f"{U}Generalization":
            gen = self._new(el, "Generalization", owner, Generalization)
            gen.specific = _idref(el.find(f"{U}Generalization.child")) or ""
            gen.general = _idref(el.find(f"{U}Generalization.parent")) or ""
            model.generalizations.append(gen)
            for ident in (gen.specific, gen.general):
                if ident:
                    self.refs.append((ident, "generalization", gen.line, gen))
        elif tag in (f"{U}Dependency", f"{U}Abstraction", f"{U}Usage"):
            dep = self._new(el, etree.QName(el).localname, owner, Dependency)
            dep.clients = [i for i in [_idref(el.find(f"{U}Dependency.client"))] if i]
            dep.suppliers = [i for i in [_idref(el.find(f"{U}Dependency.supplier"))] if i]
            model.dependencies.append(dep)
            for ident in dep.clients + dep.suppliers:
                self.refs.append((ident, "dependency", dep.line, dep))
        elif tag == f"{U}Comment" and owner is not None:
            owner.comments.append(el.get("body", ""))
        elif isinstance(tag, str) and tag.startswith(U) and tag[len(U) :] not in UML14_METACLASSES:
            name = tag[len(U) :]
            close = difflib.get_close_matches(name, UML14_METACLASSES, n=1)
            hint = f" (did you mean UML:{close[0]}?)" if close else ""
            model.diagnostics.append(
                diagnostic(
                    "R201",
                    f"unknown element UML:{name}{hint}; it is skipped",
                    file=model.file,
                    line=el.sourceline,
                    xmi_id=el.get("xmi.id"),
                )
            )

    def _features(self, el: etree._Element, cls: Classifier) -> None:
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
            prop.type_ref = end.get("type") or _idref(end.find(f"{U}AssociationEnd.participant"))
            if prop.type_ref:
                self.typed.append(prop)
            assoc.member_ends.append(prop.id)
            if isinstance(assoc, Association):
                assoc.owned_ends.append(prop)

    def _stereotypes(self, el: etree._Element, obj: Element) -> None:
        for holder in el.iterchildren(f"{U}ModelElement.stereotype"):
            for st in holder.iterchildren(f"{U}Stereotype"):
                name = st.get("name", "")
                key = (obj.id, name)
                if name and key not in self.model.applications:
                    app = StereotypeApplication(
                        profile=None, name=name, base=obj.id, line=st.sourceline or 0
                    )
                    app.places.add("xmi12")
                    self.model.applications[key] = app
        for holder in el.iterchildren(f"{U}ModelElement.taggedValue"):
            for tv in holder.iterchildren(f"{U}TaggedValue"):
                tag = tv.get("tag", "")
                if tag and tag != "stereotype":  # BOUML repeats the stereotype as a tag
                    obj.tagged_values[tag] = tv.get("value", "")

    def _resolve(self) -> None:
        model = self.model
        known = check_ids(model, self.ids)
        known |= set(model.elements)
        for obj in self.typed:
            target = model.elements.get(obj.type_ref)
            if target is not None:
                obj.type_name = target.name
            else:
                dangling(
                    model, obj.type_ref, f"type of {obj.name!r}", obj.line, obj.qualified_name()
                )
        for ident, what, line, source in self.refs:
            if ident not in known:
                dangling(model, ident, what, line, source.qualified_name())
        generals: dict[str, list[str]] = {}
        for gen in model.generalizations:
            if gen.general:
                generals.setdefault(gen.specific, []).append(gen.general)
        for cls in model.classifiers:
            cls.generals = generals.get(cls.id, [])
