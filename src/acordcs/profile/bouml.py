"""The ACORDCS profile in BOUML's XMI 2.1 (UML 2.1), shaped as BOUML's own exporter writes an
in-model profile, so that BOUML's XMI 2.1 import plug-out reads it back as a profile: a
``uml:Profile`` with ``uml:Stereotype`` children whose tags are ``ownedAttribute`` elements (type,
``defaultValue``) and whose ``base_<Metaclass>`` attributes name the extended metaclasses, plus
BOUML's ``xmi:Extension`` blocks. Ids are derived from names (see :mod:`acordcs.profile.profile_files`).
"""

from __future__ import annotations

from collections.abc import Sequence

from lxml import etree

from acordcs.profile.declaration import PROFILE_NAME, Stereotype, profile
from acordcs.profile.writing import check, enumerations, serialize, tag_doc

# --- BOUML (XMI 2.1, UML 2.1) -------------------------------------------------------------------

BOUML_XMI_NS = "http://schema.omg.org/spec/XMI/2.1"
BOUML_UML_NS = "http://schema.omg.org/spec/UML/2.1"
BOUML_UML_HREF = "http://schema.omg.org/spec/UML/2.1/uml.xml"

# BOUML's exporter writes an OMG href only for the types it maps itself (int, bool, string); any
# other type is a uml:DataType of that name, and BOUML's import turns it back into that type.
_BOUML_PRIMITIVE_HREF = {"String": "String", "Integer": "Integer", "Boolean": "Boolean"}
_BOUML_DATATYPE_NAME = {"Real": "double"}

# BOUML's "apply on" table lists BOUML element kinds, not UML metaclasses; a UML Port or an
# AssociationClass is drawn as a class in BOUML (the README's section on modelling).
_BOUML_APPLY_ON = {
    "Class": "Class",
    "Component": "Component",
    "Port": "Class",
    "AssociationClass": "Class",
    "Property": "Attribute",
    "Operation": "Operation",
    "Package": "Package",
    "Association": "Relation",
    "Dependency": "Relation",
}


def bouml_xmi(stereotypes: Sequence[Stereotype] | None = None) -> bytes:
    """The profile as BOUML's XMI 2.1 exporter writes an in-model profile (UTF-8 bytes)."""
    stereotypes = profile() if stereotypes is None else tuple(stereotypes)
    check(stereotypes)
    xmi = f"{{{BOUML_XMI_NS}}}"
    uml = f"{{{BOUML_UML_NS}}}"
    root = etree.Element(
        f"{xmi}XMI",
        {f"{xmi}version": "2.1"},
        nsmap={"uml": BOUML_UML_NS, "xmi": BOUML_XMI_NS},
    )
    # A fixed version: the package version would make the shipped file stale on every release.
    etree.SubElement(root, f"{xmi}Documentation", exporter="acordcs", exporterVersion="1")
    model = etree.SubElement(
        root,
        f"{uml}Model",
        {f"{xmi}type": "uml:Model", f"{xmi}id": "themodel", "name": f"{PROFILE_NAME} profile"},
    )
    prof_id = f"{PROFILE_NAME}_Profile"
    mmr_id = f"{PROFILE_NAME}_MMR"
    prof = etree.SubElement(
        model,
        "packagedElement",
        {
            f"{xmi}type": "uml:Profile",
            f"{xmi}id": prof_id,
            "name": PROFILE_NAME,
            "metamodelReference": mmr_id,
        },
    )
    ext = _bouml_extension(prof, xmi, "profile")
    _bouml_tagged(ext, "metamodelReference", BOUML_UML_HREF)
    imp = etree.SubElement(
        prof, "packageImport", {f"{xmi}type": "uml:PackageImport", f"{xmi}id": mmr_id}
    )
    etree.SubElement(
        imp, "importedPackage", {f"{xmi}type": "uml:Model", "href": f"{BOUML_UML_HREF}#1"}
    )

    datatypes: dict[str, str] = {}
    for st in stereotypes:
        _bouml_stereotype(prof, xmi, st, datatypes)
    for name, literals in enumerations(stereotypes).items():
        enum = etree.SubElement(
            prof,
            "packagedElement",
            {
                f"{xmi}type": "uml:Enumeration",
                "name": name,
                f"{xmi}id": f"{PROFILE_NAME}_{name}",
                "visibility": "package",
            },
        )
        for lit in literals:
            etree.SubElement(
                enum,
                "ownedLiteral",
                {
                    f"{xmi}type": "uml:EnumerationLiteral",
                    f"{xmi}id": f"{PROFILE_NAME}_{name}_{lit}",
                    "name": lit,
                },
            )
    # BOUML 1.15 and 5.x define the DataTypes of non-primitive attribute types once, at the end
    # of the root package.
    for type_name, dt_id in datatypes.items():
        etree.SubElement(
            prof,
            "packagedElement",
            {f"{xmi}type": "uml:DataType", f"{xmi}id": dt_id, "name": type_name},
        )
    return serialize(root, "\t")


def _bouml_extension(parent: etree._Element, xmi: str, stereotype: str) -> etree._Element:
    ext = etree.SubElement(parent, f"{xmi}Extension", extender="Bouml")
    etree.SubElement(ext, "stereotype", name=stereotype)
    return ext


def _bouml_tagged(ext: etree._Element, tag: str, value: str) -> None:
    etree.SubElement(ext, "taggedValue", tag=tag, value=value)


def _bouml_stereotype(
    prof: etree._Element, xmi: str, st: Stereotype, datatypes: dict[str, str]
) -> None:
    st_id = f"{PROFILE_NAME}_{st.name}"
    el = etree.SubElement(
        prof,
        "packagedElement",
        {
            f"{xmi}type": "uml:Stereotype",
            "name": st.name,
            f"{xmi}id": st_id,
            "visibility": "package",
            "isAbstract": "false",
        },
    )
    if st.doc:
        etree.SubElement(
            el,
            "ownedComment",
            {f"{xmi}type": "uml:Comment", f"{xmi}id": f"COMMENT_{st_id}", "body": st.doc},
        )
    ext = _bouml_extension(el, xmi, "stereotype")
    apply_on = []
    for m in st.metaclasses:
        kind = _BOUML_APPLY_ON.get(m, m)
        if kind not in apply_on:
            apply_on.append(kind)
    _bouml_tagged(ext, "stereotypeApplyOn", " ".join(apply_on))
    # BOUML keeps several extended metaclasses as space-separated hrefs in this one property.
    _bouml_tagged(
        ext, "stereotypeExtension", " ".join(f"{BOUML_UML_HREF}#{m}" for m in st.metaclasses)
    )
    for tag in st.tags:
        attr_id = f"{st_id}_{tag.name}"
        attr = etree.SubElement(
            el,
            "ownedAttribute",
            {
                f"{xmi}type": "uml:Property",
                "name": tag.name,
                f"{xmi}id": attr_id,
                "visibility": "public",
            },
        )
        doc = tag_doc(tag)
        if doc:
            etree.SubElement(
                attr,
                "ownedComment",
                {f"{xmi}type": "uml:Comment", f"{xmi}id": f"COMMENT_{attr_id}", "body": doc},
            )
        if tag.values:
            etree.SubElement(
                attr,
                "type",
                {f"{xmi}type": "uml:Class", f"{xmi}idref": f"{PROFILE_NAME}_{tag.type}"},
            )
        elif tag.type in _BOUML_PRIMITIVE_HREF:
            etree.SubElement(
                attr,
                "type",
                {
                    f"{xmi}type": "uml:PrimitiveType",
                    "href": f"{BOUML_UML_HREF}#{_BOUML_PRIMITIVE_HREF[tag.type]}",
                },
            )
        else:
            dt_name = _BOUML_DATATYPE_NAME[tag.type]
            dt_id = datatypes.setdefault(dt_name, f"BOUML_datatype_{len(datatypes)}")
            etree.SubElement(attr, "type", {f"{xmi}type": "uml:Class", f"{xmi}idref": dt_id})
        if tag.default is not None:
            etree.SubElement(
                attr,
                "defaultValue",
                {
                    f"{xmi}type": "uml:LiteralString",
                    f"{xmi}id": f"BOUML_VALUE_{attr_id}",
                    "value": tag.default,
                },
            )
    for m in st.metaclasses:
        etree_base = etree.SubElement(
            el,
            "ownedAttribute",
            {
                f"{xmi}type": "uml:Property",
                "name": f"base_{m}",
                f"{xmi}id": f"BOUML_BASE_{st_id}_{m}",
                "association": f"BOUML_EXT_{st_id}_{m}",
            },
        )
        etree.SubElement(
            etree_base, "type", {f"{xmi}type": "uml:Class", "href": f"{BOUML_UML_HREF}#{m}"}
        )
    for m in st.metaclasses:
        # Unlike BOUML 4.x (whose memberEnd dangles), both ends resolve here.
        ext_el = etree.SubElement(
            prof,
            "packagedElement",
            {
                f"{xmi}type": "uml:Extension",
                "name": f"A_{m}_{st.name}",
                f"{xmi}id": f"BOUML_EXT_{st_id}_{m}",
                "memberEnd": f"BOUML_EXTEND_{st_id}_{m} BOUML_BASE_{st_id}_{m}",
            },
        )
        etree.SubElement(
            ext_el,
            "ownedEnd",
            {
                f"{xmi}type": "uml:ExtensionEnd",
                "name": f"extension_{st.name}",
                f"{xmi}id": f"BOUML_EXTEND_{st_id}_{m}",
                "type": st_id,
                "aggregation": "composite",
            },
        )
