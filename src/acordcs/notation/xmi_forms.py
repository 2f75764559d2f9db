"""A model read from the text written as XMI: the Eclipse UML2 form Papyrus opens (the profile
applied from ``ACORDCS.profile.uml`` beside it) or the XMI 2.1 form BOUML reads (stereotypes in
both places BOUML writes them: an ``xmi:Extension`` in the element and an application after the
model).

Both are written from the UML view the text reader made (:mod:`acordcs.notation.text_model`),
so that reading either back gives the same view: the same ids, names, types, defaults, comments,
tags and relations (the round trip ``acordcs-gen convert`` promises, held by a test). Written
with lxml, so that no name or rule needs escaping by hand.
"""

from __future__ import annotations

from lxml import etree

from acordcs import __version__
from acordcs.profile.declaration import PROFILE_NAME, PROFILE_URI
from acordcs.xmi.uml import (
    Classifier,
    Element,
    Operation,
    Package,
    Property,
    UmlModel,
)

XSI = "http://www.w3.org/2001/XMLSchema-instance"
ECORE = "http://www.eclipse.org/emf/2002/Ecore"
PROFILE_FILE = "ACORDCS.profile.uml"
_ECLIPSE = {
    "xmi": "http://www.omg.org/spec/XMI/20131001",
    "uml": "http://www.eclipse.org/uml2/5.0.0/UML",
}
_OMG = {"xmi": "http://schema.omg.org/spec/XMI/2.1", "uml": "http://schema.omg.org/spec/UML/2.1"}
# The type names a modeller writes -> the primitive type of UML's library (the readers read them
# back as these names: acordcs.xmi.readers.common.PRIMITIVE_TYPES); any other becomes a type of
# the model of that name.
ECLIPSE_PRIMITIVES = {"double": "Real", "int": "Integer", "bool": "Boolean", "string": "String"}
OMG_PRIMITIVES = {
    "int": "Integer",
    "bool": "Boolean",
    "string": "String",
    "long": "UnlimitedNatural",
}
_ECLIPSE_LIBRARY = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#"
_OMG_LIBRARY = "http://schema.omg.org/spec/UML/2.1/uml.xml#"


def papyrus_form(uml: UmlModel) -> bytes:
    """``uml`` as the Eclipse UML2 file Papyrus opens, applying ``ACORDCS.profile.uml``."""
    return _Writer(uml, eclipse=True).write()


def bouml_form(uml: UmlModel) -> bytes:
    """``uml`` as the XMI 2.1 BOUML reads (its xmi2 import)."""
    return _Writer(uml, eclipse=False).write()


class _Writer:
    def __init__(self, uml: UmlModel, *, eclipse: bool) -> None:
        self.uml = uml
        self.eclipse = eclipse
        ns = _ECLIPSE if eclipse else _OMG
        self.XMI, self.UML = ns["xmi"], ns["uml"]
        self.ID, self.TYPE = f"{{{self.XMI}}}id", f"{{{self.XMI}}}type"
        self.types: dict[str, str] = {}  # a type of the model by name -> its id
        self.counter = 0

    # -------------------------------------------------------------------------------- helpers
    def new(self, parent: etree._Element, tag: str, kind: str | None, ident: str | None, **attrs):
        el = etree.SubElement(parent, tag)
        if kind is not None:
            el.set(self.TYPE, f"uml:{kind}")
        if ident is not None:
            el.set(self.ID, ident)
        for key, value in attrs.items():
            if value is not None:
                el.set(key, value)
        return el

    def comments(self, parent: etree._Element, element: Element) -> None:
        for n, body in enumerate(c for c in element.comments if c):
            ident = f"{element.id}.comment" + (f"{n + 1}" if n else "")
            if self.eclipse:
                comment = self.new(
                    parent, "ownedComment", "Comment", ident, annotatedElement=element.id
                )
                etree.SubElement(comment, "body").text = body
            else:
                self.new(parent, "ownedComment", "Comment", ident, body=body)

    def typed(self, parent: etree._Element, type_name: str | None) -> None:
        if not type_name:
            return
        primitives = ECLIPSE_PRIMITIVES if self.eclipse else OMG_PRIMITIVES
        if type_name in primitives:
            library = _ECLIPSE_LIBRARY if self.eclipse else _OMG_LIBRARY
            self.new(parent, "type", "PrimitiveType", None, href=library + primitives[type_name])
            return
        ident = self.types.setdefault(type_name, f"_type.{len(self.types) + 1}")
        if self.eclipse:
            parent.set("type", ident)
        else:
            self.new(parent, "type", "Class", None).set(f"{{{self.XMI}}}idref", ident)

    def stereotype(self, parent: etree._Element, element: Element) -> None:
        """BOUML's copy of the element's stereotype and tags, inside it."""
        if self.eclipse:
            return
        for app in self.uml.applications_of(element.id):
            ext = etree.SubElement(parent, f"{{{self.XMI}}}Extension", extender="Bouml")
            etree.SubElement(ext, "stereotype", name=app.key)
            for tag, value in app.tags.items():
                etree.SubElement(ext, "taggedValue", tag=f"{app.key}:{tag}", value=value)

    # -------------------------------------------------------------------------------- the model
    def write(self) -> bytes:
        uml = self.uml
        nsmap = {"xmi": self.XMI, "uml": self.UML, PROFILE_NAME: PROFILE_URI}
        if self.eclipse:
            nsmap.update(xsi=XSI, ecore=ECORE)
        root = etree.Element(f"{{{self.XMI}}}XMI", nsmap=nsmap)
        root.set(f"{{{self.XMI}}}version", "20131001" if self.eclipse else "2.1")
        if self.eclipse:
            root.set(
                f"{{{XSI}}}schemaLocation",
                f"{PROFILE_URI} {PROFILE_FILE}#_ACORDCS.definition.EPackage",
            )
        else:
            etree.SubElement(
                root,
                f"{{{self.XMI}}}Documentation",
                exporter="acordcs",
                exporterVersion=__version__,
            )
        model = next((e for e in uml.elements.values() if e.kind == "Model"), None)
        model_id = model.id if model is not None else "_model"
        top = self.new(root, f"{{{self.UML}}}Model", None, model_id, name=uml.name)
        if not self.eclipse:
            top.set(self.TYPE, "uml:Model")
        if model is not None:
            self.comments(top, model)
        if self.eclipse:
            imports = self.new(top, "packageImport", "PackageImport", f"{model_id}.primitives")
            self.new(imports, "importedPackage", "Model", None, href=_ECLIPSE_LIBRARY + "_0")
        for member in self.members(model):
            self.member(top, member)
        for dep in self.dependencies(None):
            self.dependency(top, dep)
        for name, ident in self.types.items():
            kind = "PrimitiveType" if self.eclipse else "DataType"
            self.new(top, "packagedElement", kind, ident, name=name)
        if self.eclipse:
            self.profile_application(top, model_id)
        for app in uml.applications.values():
            base = uml.elements[app.base]
            feature = "base_Element"
            if self.eclipse:
                feature = "base_Port" if base.kind == "Port" else f"base_{_metaclass(base)}"
            attrs = {self.ID: app.id or f"{app.base}.app", feature: app.base}
            attrs.update((k, v) for k, v in app.tags.items())
            etree.SubElement(root, f"{{{PROFILE_URI}}}{app.name}", attrs)
        return etree.tostring(root, xml_declaration=True, encoding="UTF-8", pretty_print=True)

    def profile_application(self, top: etree._Element, model_id: str) -> None:
        app = self.new(top, "profileApplication", "ProfileApplication", f"{model_id}.ACORDCS")
        note = etree.SubElement(app, "eAnnotations")
        note.set(self.TYPE, "ecore:EAnnotation")
        note.set(self.ID, f"{model_id}.ACORDCS.annotation")
        note.set("source", "http://www.eclipse.org/uml2/2.0.0/UML")
        ref = etree.SubElement(
            note, "references", href=f"{PROFILE_FILE}#_ACORDCS.definition.EPackage"
        )
        ref.set(self.TYPE, "ecore:EPackage")
        self.new(app, "appliedProfile", "Profile", None, href=f"{PROFILE_FILE}#_ACORDCS")

    def members(self, owner: Element | None) -> list[Element]:
        return [
            e
            for e in self.uml.elements.values()
            if e.owner is owner and isinstance(e, Package | Classifier) and e.kind != "Model"
        ]

    def dependencies(self, owner: Element | None) -> list:
        model = owner is None
        return [
            d
            for d in self.uml.dependencies
            if d.owner is owner or (model and d.owner is not None and d.owner.kind == "Model")
        ]

    def member(self, parent: etree._Element, element: Element, tag: str = "packagedElement"):
        if isinstance(element, Package):
            el = self.new(parent, tag, "Package", element.id, name=element.name)
            self.comments(el, element)
            for member in self.members(element):
                self.member(el, member)
            for dep in self.dependencies(element):
                self.dependency(el, dep)
            return
        assert isinstance(element, Classifier)
        el = self.new(parent, tag, "Class", element.id, name=element.name)
        self.comments(el, element)
        self.stereotype(el, element)
        for prop in element.attributes:
            self.attribute(el, prop)
        for port in element.ports:
            if self.eclipse:
                p = self.new(
                    el, "ownedAttribute", "Port", port.id, name=port.name, aggregation="composite"
                )
                self.comments(p, port)
            else:  # BOUML has no ports in a class model: a class inside the component
                self.member(el, _as_class(port), "nestedClassifier")
        for op in element.operations:
            self.operation(el, op)
        for nested in element.nested:
            self.member(el, nested, "nestedClassifier")

    def attribute(self, parent: etree._Element, prop: Property) -> None:
        el = self.new(parent, "ownedAttribute", "Property", prop.id, name=prop.name)
        self.comments(el, prop)
        self.typed(el, prop.type_name)
        if prop.default is not None:
            self.new(el, "defaultValue", "LiteralString", f"{prop.id}.default", value=prop.default)
        self.stereotype(el, prop)

    def operation(self, parent: etree._Element, op: Operation) -> None:
        el = self.new(parent, "ownedOperation", "Operation", op.id, name=op.name)
        self.comments(el, op)
        for param in op.parameters:
            direction = param.direction if param.direction != "in" else None
            p = self.new(
                el, "ownedParameter", "Parameter", param.id, name=param.name, direction=direction
            )
            self.typed(p, param.type_name)

    def dependency(self, parent: etree._Element, dep) -> None:
        self.new(
            parent,
            "packagedElement",
            "Dependency",
            dep.id,
            name=dep.name,
            client=" ".join(dep.clients),
            supplier=" ".join(dep.suppliers),
        )


def _metaclass(element: Element) -> str:
    return "Property" if isinstance(element, Property) else "Class"


def _as_class(port: Property) -> Classifier:
    """A port of the text as the class BOUML models it with, same id, name and comments."""
    cls = Classifier(port.id, "Class", port.name, port.line, port.owner)
    cls.comments = port.comments
    return cls
