"""The ACORDCS profile as files a modeller imports, produced from the one declaration.

Two dialects, both from :func:`acordcs.profile.declaration.profile`:

* :func:`bouml_xmi` -- BOUML's XMI 2.1 (UML 2.1), shaped as BOUML's own exporter writes an
  in-model profile, so that BOUML's XMI 2.1 import plug-out reads it back as a profile: a
  ``uml:Profile`` with ``uml:Stereotype`` children whose tags are ``ownedAttribute`` elements
  (type, ``defaultValue``) and whose ``base_<Metaclass>`` attributes name the extended
  metaclasses, plus BOUML's ``xmi:Extension`` blocks.
* :func:`eclipse_profile` -- an Eclipse UML2 ``.profile.uml`` for Papyrus, shaped like a real
  Papyrus-made profile: metaclass ``elementImport`` elements, ``uml:Extension`` elements with an
  ``uml:ExtensionEnd``, enumerations, primitive types from ``UMLPrimitiveTypes.library.uml``.

Ids are derived from names, never random or counted per run, so the output is byte-identical for
the same declaration and a model that applied an earlier version of the profile keeps resolving.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from pathlib import Path

from lxml import etree

from acordcs.profile.declaration import PROFILE_NAME, PROFILE_URI, Stereotype, Tag, profile

BOUML_FILE = "ACORDCS.xmi"
ECLIPSE_FILE = "ACORDCS.profile.uml"

PRIMITIVE_TYPES = ("String", "Real", "Integer", "Boolean")

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

_XML_DECLARATION = b'<?xml version="1.0" encoding="UTF-8"?>\n'


class ProfileExportError(ValueError):
    """The declaration cannot be written as a UML profile."""


def _check(stereotypes: Sequence[Stereotype]) -> None:
    enums: dict[str, tuple[str, ...]] = {}
    for st in stereotypes:
        if not st.metaclasses:
            raise ProfileExportError(
                f"stereotype {st.name!r} extends no UML metaclass: give its EClass a 'metaclasses' "
                "detail in the http://acordcs.org/profile annotation of acordcs.ecore"
            )
        for tag in st.tags:
            if tag.values:
                seen = enums.setdefault(tag.type, tag.values)
                if seen != tag.values:
                    raise ProfileExportError(
                        f"enumeration {tag.type!r} (tag {st.name}.{tag.name}) has values "
                        f"{tag.values} here and {seen} elsewhere: one enumeration needs one list "
                        "of literals"
                    )
                if tag.default is not None and tag.default not in tag.values:
                    raise ProfileExportError(
                        f"tag {st.name}.{tag.name}: default {tag.default!r} is not one of "
                        f"{', '.join(tag.values)}: fix the default in acordcs.ecore"
                    )
            elif tag.type not in PRIMITIVE_TYPES:
                raise ProfileExportError(
                    f"tag {st.name}.{tag.name} has type {tag.type!r}, which is neither a UML "
                    f"primitive type ({', '.join(PRIMITIVE_TYPES)}) nor an enumeration with "
                    "literals: map its EDataType in acordcs.profile.declaration"
                )


def _enumerations(stereotypes: Sequence[Stereotype]) -> dict[str, tuple[str, ...]]:
    """Enumeration name -> literals, in the order tags first use them."""
    out: dict[str, tuple[str, ...]] = {}
    for st in stereotypes:
        for tag in st.tags:
            if tag.values:
                out.setdefault(tag.type, tag.values)
    return out


def _tag_doc(tag: Tag) -> str:
    doc = tag.doc
    # The metamodel's documentation may already say so; say it once.
    if tag.prefix and "starts with" not in doc:
        extra = f"Any other tag whose name starts with '{tag.name}' also holds these values."
        doc = f"{doc} {extra}".strip()
    return doc


def _serialize(root: etree._Element, indent: str) -> bytes:
    etree.indent(root, space=indent)
    # The declaration is written by hand only to get the double quotes both tools write.
    return _XML_DECLARATION + etree.tostring(root, encoding="UTF-8", xml_declaration=False) + b"\n"


# --- BOUML ---------------------------------------------------------------------------------------


def bouml_xmi(stereotypes: Sequence[Stereotype] | None = None) -> bytes:
    """The profile as BOUML's XMI 2.1 exporter writes an in-model profile (UTF-8 bytes)."""
    stereotypes = profile() if stereotypes is None else tuple(stereotypes)
    _check(stereotypes)
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
    for name, literals in _enumerations(stereotypes).items():
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
    return _serialize(root, "\t")


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
        doc = _tag_doc(tag)
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


# --- Eclipse UML2 / Papyrus ----------------------------------------------------------------------


def eclipse_profile(stereotypes: Sequence[Stereotype] | None = None) -> bytes:
    """The profile as an Eclipse UML2 ``.profile.uml`` for Papyrus (UTF-8 bytes)."""
    stereotypes = profile() if stereotypes is None else tuple(stereotypes)
    _check(stereotypes)
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
            doc = _tag_doc(tag)
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
    for name, literals in _enumerations(stereotypes).items():
        enum = etree.SubElement(
            prof, "packagedElement", {t: "uml:Enumeration", i: f"_{name}", "name": name}
        )
        for lit in literals:
            etree.SubElement(
                enum,
                "ownedLiteral",
                {t: "uml:EnumerationLiteral", i: f"_{name}.{lit}", "name": lit},
            )

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
    return _serialize(root, "  ")


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


# --- files ---------------------------------------------------------------------------------------

OUTPUTS: dict[str, Callable[[], bytes]] = {BOUML_FILE: bouml_xmi, ECLIPSE_FILE: eclipse_profile}


def default_directory() -> Path:
    """Where the shipped profile files live (next to this module)."""
    return Path(__file__).resolve().parent


def write_profiles(directory: Path | str | None = None) -> list[Path]:
    """Write both profile files into ``directory`` (default: the package); only files whose
    content changed are rewritten. Returns the paths written."""
    target = default_directory() if directory is None else Path(directory)
    if not target.is_dir():
        raise NotADirectoryError(
            f"cannot write the ACORDCS profile files: {target} is not a directory; create it or "
            "pass an existing one"
        )
    written = []
    for name, produce in OUTPUTS.items():
        path = target / name
        data = produce()
        try:
            current = path.read_bytes()
        except FileNotFoundError:
            current = None
        if current != data:
            tmp = path.with_suffix(path.suffix + ".tmp")
            tmp.write_bytes(data)
            tmp.replace(path)
            written.append(path)
    return written
