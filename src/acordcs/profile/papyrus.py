"""The ACORDCS profile as an Eclipse UML2 ``.profile.uml`` for Papyrus, shaped like a real
Papyrus-made profile: metaclass ``elementImport`` elements, ``uml:Extension`` elements with an
``uml:ExtensionEnd``, enumerations, primitive types from ``UMLPrimitiveTypes.library.uml``, and
already *defined* (its Ecore definition, :mod:`acordcs.profile.papyrus_definition`), so Papyrus
applies it as shipped. Ids are derived from names (see :mod:`acordcs.profile.profile_files`).
"""

from __future__ import annotations

from collections.abc import Sequence

from lxml import etree

from acordcs.profile.declaration import PROFILE_NAME, PROFILE_URI, Stereotype, Tag, profile
from acordcs.profile.papyrus_definition import add_definition
from acordcs.profile.writing import check, enumerations, serialize, tag_doc

# --- Eclipse UML2 / Papyrus ----------------------------------------------------------------------

ECLIPSE_XMI_NS = "http://www.omg.org/spec/XMI/20131001"
ECLIPSE_UML_NS = "http://www.eclipse.org/uml2/5.0.0/UML"
XSI_NS = "http://www.w3.org/2001/XMLSchema-instance"
ECORE_NS = "http://www.eclipse.org/emf/2002/Ecore"
ECORE_PROFILE_NS = "http://www.eclipse.org/uml2/schemas/Ecore/5"
UML_METAMODEL = "pathmap://UML_METAMODELS/UML.metamodel.uml"
UML_PRIMITIVES = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml"
# The Ecore profile shipped with UML2, as the real Codegen.profile.uml applies it; its stereotype
# EPackage records the nsURI and prefix the profile's Ecore definition should use.
ECORE_PROFILE = "pathmap://UML_PROFILES/Ecore.profile.uml"
ECORE_PROFILE_EPACKAGE_ID = "_z1OFcHjqEdy8S4Cr8Rc_NA"


def eclipse_profile(stereotypes: Sequence[Stereotype] | None = None) -> bytes:
    """The profile as an Eclipse UML2 ``.profile.uml`` for Papyrus (UTF-8 bytes)."""
    stereotypes = profile() if stereotypes is None else tuple(stereotypes)
    check(stereotypes)
    xmi = f"{{{ECLIPSE_XMI_NS}}}"
    uml = f"{{{ECLIPSE_UML_NS}}}"
    xsi = f"{{{XSI_NS}}}"
    t = f"{xmi}type"
    i = f"{xmi}id"
    root = etree.Element(
        f"{xmi}XMI",
        {
            f"{xmi}version": "20131001",
            f"{xsi}schemaLocation": (
                f"{ECORE_PROFILE_NS} {ECORE_PROFILE}#{ECORE_PROFILE_EPACKAGE_ID}"
            ),
        },
        nsmap={
            "xmi": ECLIPSE_XMI_NS,
            "xsi": XSI_NS,
            "Ecore": ECORE_PROFILE_NS,
            "ecore": ECORE_NS,
            "uml": ECLIPSE_UML_NS,
        },
    )
    prof_id = f"_{PROFILE_NAME}"
    metaclasses: list[str] = []
    for st in stereotypes:
        for m in st.metaclasses:
            if m not in metaclasses:
                metaclasses.append(m)
    prof = etree.SubElement(
        root,
        f"{uml}Profile",
        {
            i: prof_id,
            "name": PROFILE_NAME,
            "metaclassReference": " ".join(f"_import.{m}" for m in metaclasses),
        },
    )

    for st in stereotypes:
        if st.doc:
            _eclipse_comment(prof, t, i, f"_{st.name}", st.doc)
        for tag in st.tags:
            doc = tag_doc(tag)
            if doc:
                _eclipse_comment(prof, t, i, f"_{st.name}.{tag.name}", doc)
    for m in metaclasses:
        imp = etree.SubElement(
            prof, "elementImport", {t: "uml:ElementImport", i: f"_import.{m}", "alias": m}
        )
        etree.SubElement(imp, "importedElement", {t: "uml:Class", "href": f"{UML_METAMODEL}#{m}"})
    pimp = etree.SubElement(
        prof, "packageImport", {t: "uml:PackageImport", i: "_import.UMLPrimitiveTypes"}
    )
    etree.SubElement(pimp, "importedPackage", {t: "uml:Model", "href": f"{UML_PRIMITIVES}#_0"})

    for st in stereotypes:
        _eclipse_stereotype(prof, t, i, st)
    for name, literals in enumerations(stereotypes).items():
        enum = etree.SubElement(
            prof, "packagedElement", {t: "uml:Enumeration", i: f"_{name}", "name": name}
        )
        for lit in literals:
            etree.SubElement(
                enum,
                "ownedLiteral",
                {t: "uml:EnumerationLiteral", i: f"_{name}.{lit}", "name": lit},
            )

    optional = {
        f"_{st.name}.base_{m}"
        for st in stereotypes
        if len(st.metaclasses) > 1
        for m in st.metaclasses
    }
    add_definition(prof, stereotypes, t, i, optional)
    appl = etree.SubElement(
        prof, "profileApplication", {t: "uml:ProfileApplication", i: "_apply.Ecore"}
    )
    ann = etree.SubElement(
        appl,
        "eAnnotations",
        {t: "ecore:EAnnotation", i: "_apply.Ecore.annotation"},
        source="http://www.eclipse.org/uml2/2.0.0/UML",
    )
    etree.SubElement(
        ann,
        "references",
        {t: "ecore:EPackage", "href": f"{ECORE_PROFILE}#{ECORE_PROFILE_EPACKAGE_ID}"},
    )
    etree.SubElement(appl, "appliedProfile", {t: "uml:Profile", "href": f"{ECORE_PROFILE}#_0"})
    etree.SubElement(
        root,
        f"{{{ECORE_PROFILE_NS}}}EPackage",
        {
            i: "_apply.Ecore.EPackage",
            "base_Package": prof_id,
            "packageName": PROFILE_NAME,
            "nsPrefix": PROFILE_NAME,
            "nsURI": PROFILE_URI,
            "prefix": PROFILE_NAME,
        },
    )
    return serialize(root, "  ")


def _eclipse_comment(prof: etree._Element, t: str, i: str, target: str, doc: str) -> None:
    comment = etree.SubElement(
        prof, "ownedComment", {t: "uml:Comment", i: f"{target}.comment", "annotatedElement": target}
    )
    etree.SubElement(comment, "body").text = doc


def _eclipse_literal(parent: etree._Element, t: str, i: str, tag: Tag, owner_id: str) -> None:
    value_id = f"{owner_id}.default"
    if tag.values:
        etree.SubElement(
            parent,
            "defaultValue",
            {
                t: "uml:InstanceValue",
                i: value_id,
                "type": f"_{tag.type}",
                "instance": f"_{tag.type}.{tag.default}",
            },
        )
        return
    literal_type = {
        "String": "uml:LiteralString",
        "Real": "uml:LiteralReal",
        "Integer": "uml:LiteralInteger",
        "Boolean": "uml:LiteralBoolean",
    }[tag.type]
    el = etree.SubElement(
        parent, "defaultValue", {t: literal_type, i: value_id, "value": tag.default or ""}
    )
    # Papyrus writes the type of a primitive default as a pathmap href child.
    etree.SubElement(el, "type", {t: "uml:PrimitiveType", "href": f"{UML_PRIMITIVES}#{tag.type}"})


def _eclipse_stereotype(prof: etree._Element, t: str, i: str, st: Stereotype) -> None:
    st_id = f"_{st.name}"
    el = etree.SubElement(prof, "packagedElement", {t: "uml:Stereotype", i: st_id, "name": st.name})
    several = len(st.metaclasses) > 1
    for m in st.metaclasses:
        base = etree.SubElement(
            el,
            "ownedAttribute",
            {
                t: "uml:Property",
                i: f"{st_id}.base_{m}",
                "name": f"base_{m}",
                "association": f"_E_{st.name}_{m}",
            },
        )
        etree.SubElement(base, "type", {t: "uml:Class", "href": f"{UML_METAMODEL}#{m}"})
        if several:
            # A stereotype applied to a Class has no Port: each base_* must be optional.
            etree.SubElement(
                base, "lowerValue", {t: "uml:LiteralInteger", i: f"{base.get(i)}.lower"}
            )
    for tag in st.tags:
        prop_id = f"{st_id}.{tag.name}"
        attrs = {t: "uml:Property", i: prop_id, "name": tag.name, "visibility": "public"}
        if tag.values:
            attrs["type"] = f"_{tag.type}"
        prop = etree.SubElement(el, "ownedAttribute", attrs)
        if not tag.values:
            etree.SubElement(
                prop, "type", {t: "uml:PrimitiveType", "href": f"{UML_PRIMITIVES}#{tag.type}"}
            )
        # Tags are optional on an application: [0..1].
        etree.SubElement(prop, "lowerValue", {t: "uml:LiteralInteger", i: f"{prop_id}.lower"})
        etree.SubElement(
            prop,
            "upperValue",
            {t: "uml:LiteralUnlimitedNatural", i: f"{prop_id}.upper", "value": "1"},
        )
        if tag.default is not None:
            _eclipse_literal(prop, t, i, tag, prop_id)
    for m in st.metaclasses:
        ext_id = f"_E_{st.name}_{m}"
        end_id = f"{ext_id}.extension_{st.name}"
        ext = etree.SubElement(
            prof,
            "packagedElement",
            {
                t: "uml:Extension",
                i: ext_id,
                "name": f"E_{st.name}_{m}1",
                "memberEnd": f"{end_id} {st_id}.base_{m}",
            },
        )
        etree.SubElement(
            ext,
            "ownedEnd",
            {
                t: "uml:ExtensionEnd",
                i: end_id,
                "name": f"extension_{st.name}",
                "type": st_id,
                "aggregation": "composite",
                "association": ext_id,
            },
        )
