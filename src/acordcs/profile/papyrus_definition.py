"""The Ecore definition of the Papyrus profile: what Papyrus writes when a user *defines* a profile
(Eclipse UML2's ``Profile.define()``), so that the profile can be applied as shipped.

Eclipse UML2 keeps a profile's definition in an ``eAnnotations`` of the profile with source
``http://www.eclipse.org/uml2/2.0.0/UML`` whose ``contents`` is an ``ecore:EPackage``: one
``EClass`` per stereotype (an annotation ``references`` its stereotype; ``base_<Metaclass>``
``EReference`` typed by the UML metaclass; one ``EAttribute`` per tag typed by a UML primitive type
or an ``EEnum``) and one ``EEnum`` per enumeration. A model applying the profile points at that
``EPackage`` from its profile application and its ``xsi:schemaLocation``; stereotype applications
are instances of its classes in the namespace ``nsURI``. Shape and attribute names are those of
profiles Papyrus defined (``ordered="false"``, ``lowerBound="1"`` for a mandatory end, eType hrefs
into ``http://www.eclipse.org/uml2/5.0.0/UML`` and ``.../Types``).
"""

from __future__ import annotations

from collections.abc import Sequence

from lxml import etree

from acordcs import __version__
from acordcs.profile.declaration import PROFILE_NAME, PROFILE_URI, Stereotype
from acordcs.profile.writing import enumerations

UML2_ANNOTATION = "http://www.eclipse.org/uml2/2.0.0/UML"
UML_TYPES = "http://www.eclipse.org/uml2/5.0.0/Types"
UML_ECORE = "http://www.eclipse.org/uml2/5.0.0/UML"
# The id of the definition's EPackage: a model's profile application and schemaLocation name it.
EPACKAGE_ID = f"_{PROFILE_NAME}.definition.EPackage"


def add_definition(
    prof: etree._Element, stereotypes: Sequence[Stereotype], t: str, i: str, optional: set[str]
) -> None:
    """Insert the definition as the first child of ``prof`` (where Papyrus writes it).

    ``optional`` holds the ids of the stereotypes' ``base_*`` properties whose lower bound is 0
    (a stereotype extending several metaclasses); the others are mandatory (``lowerBound="1"``).
    """
    ann = etree.Element("eAnnotations", {t: "ecore:EAnnotation", i: f"_{PROFILE_NAME}.definition"})
    ann.set("source", UML2_ANNOTATION)
    prof.insert(0, ann)
    package = etree.SubElement(
        ann,
        "contents",
        {
            t: "ecore:EPackage",
            i: EPACKAGE_ID,
            "name": PROFILE_NAME,
            "nsURI": PROFILE_URI,
            "nsPrefix": PROFILE_NAME,
        },
    )
    version = etree.SubElement(
        package,
        "eAnnotations",
        {t: "ecore:EAnnotation", i: f"{EPACKAGE_ID}.version", "source": "PapyrusVersion"},
    )
    etree.SubElement(
        version,
        "details",
        {
            t: "ecore:EStringToStringMapEntry",
            i: f"{EPACKAGE_ID}.version.Version",
            "key": "Version",
            "value": __version__,
        },
    )
    for st in stereotypes:
        _eclass(package, st, t, i, optional)
    for name, literals in enumerations(stereotypes).items():
        enum = etree.SubElement(
            package, "eClassifiers", {t: "ecore:EEnum", i: f"_E.{name}", "name": name}
        )
        _references(enum, f"_{name}", t, i)
        for n, literal in enumerate(literals):
            attrs = {t: "ecore:EEnumLiteral", i: f"_E.{name}.{literal}", "name": literal}
            if n:
                attrs["value"] = str(n)
            etree.SubElement(enum, "eLiterals", attrs)


def _references(parent: etree._Element, target: str, t: str, i: str) -> None:
    etree.SubElement(
        parent,
        "eAnnotations",
        {
            t: "ecore:EAnnotation",
            i: f"{parent.get(i)}.uml",
            "source": UML2_ANNOTATION,
            "references": target,
        },
    )


def _eclass(package: etree._Element, st: Stereotype, t: str, i: str, optional: set[str]) -> None:
    eclass = etree.SubElement(
        package, "eClassifiers", {t: "ecore:EClass", i: f"_E.{st.name}", "name": st.name}
    )
    _references(eclass, f"_{st.name}", t, i)
    for m in st.metaclasses:
        attrs = {t: "ecore:EReference", i: f"_E.{st.name}.base_{m}", "name": f"base_{m}"}
        attrs["ordered"] = "false"
        if f"_{st.name}.base_{m}" not in optional:
            attrs["lowerBound"] = "1"
        ref = etree.SubElement(eclass, "eStructuralFeatures", attrs)
        etree.SubElement(ref, "eType", {t: "ecore:EClass", "href": f"{UML_ECORE}#//{m}"})
    for tag in st.tags:
        attrs = {t: "ecore:EAttribute", i: f"_E.{st.name}.{tag.name}", "name": tag.name}
        attrs["ordered"] = "false"
        if tag.values:
            attrs["eType"] = f"_E.{tag.type}"
        if tag.default is not None:
            attrs["defaultValueLiteral"] = tag.default
        feature = etree.SubElement(eclass, "eStructuralFeatures", attrs)
        if not tag.values:
            etree.SubElement(
                feature, "eType", {t: "ecore:EDataType", "href": f"{UML_TYPES}#//{tag.type}"}
            )
