"""The Papyrus profile is shipped *defined*, and a Papyrus-shaped model applying it validates.

Two independent checks of the definition: pyecore (an EMF implementation) loads it as an Ecore
package, and a structural check written from Eclipse UML2's profile-definition mapping compares it
with the UML part of the same file (read with lxml, not with the exporter): one EClass per
stereotype, annotated with the stereotype's id; ``base_<Metaclass>`` references typed by the UML
metaclass, mandatory when the UML end is; one attribute per tag with the tag's type and default;
one EEnum per enumeration with its literals in order. The sample's stereotype applications are then
instantiated with pyecore from the loaded definition: every tag a feature, every value a literal.
"""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree
from pyecore.ecore import EClass, EDataType, EEnum, EPackage
from pyecore.resources import URI, ResourceSet

from acordcs.profile.declaration import PROFILE_NAME, PROFILE_URI
from acordcs.profile.papyrus import eclipse_profile
from acordcs.profile.papyrus_definition import EPACKAGE_ID
from tests.support.toolchain import ROOT, run_main

SAMPLE = ROOT / "samples" / "papyrus" / "thermostat.uml"
XMI = "http://www.omg.org/spec/XMI/20131001"
UML = "http://www.eclipse.org/uml2/5.0.0/UML"
NS = {"xmi": XMI, "uml": UML}
UML2 = "http://www.eclipse.org/uml2/2.0.0/UML"
UML_ECORE = "http://www.eclipse.org/uml2/5.0.0/UML#//"
UML_TYPES = "http://www.eclipse.org/uml2/5.0.0/Types#//"
TYPE = f"{{{XMI}}}type"
ID = f"{{{XMI}}}id"


def _profile() -> etree._Element:
    root = etree.fromstring(eclipse_profile())
    (prof,) = root.xpath("uml:Profile", namespaces=NS)
    return prof


def _definition(prof: etree._Element) -> etree._Element:
    (ann,) = prof.xpath(f"eAnnotations[@source='{UML2}']", namespaces=NS)
    assert prof[0] is ann, "Papyrus writes the definition first"
    (package,) = ann.xpath("contents[@xmi:type='ecore:EPackage']", namespaces=NS)
    return package


def test_the_definition_names_the_profile_namespace():
    package = _definition(_profile())
    assert package.get(ID) == EPACKAGE_ID
    assert (package.get("name"), package.get("nsPrefix")) == (PROFILE_NAME, PROFILE_NAME)
    assert package.get("nsURI") == PROFILE_URI  # what stereotype applications are read by


def test_the_definition_mirrors_the_uml_profile():
    prof = _profile()
    package = _definition(prof)
    by_id = {el.get(ID): el for el in prof.iter() if el.get(ID)}
    classes = package.xpath("eClassifiers[@xmi:type='ecore:EClass']", namespaces=NS)
    stereotypes = prof.xpath("packagedElement[@xmi:type='uml:Stereotype']", namespaces=NS)
    assert len(classes) == len(stereotypes)
    for eclass in classes:
        (ann,) = eclass.xpath(f"eAnnotations[@source='{UML2}']", namespaces=NS)
        stereotype = by_id[ann.get("references")]
        assert stereotype.get(TYPE) == "uml:Stereotype"
        assert stereotype.get("name") == eclass.get("name")
        features = {f.get("name"): f for f in eclass.xpath("eStructuralFeatures")}
        props = stereotype.xpath("ownedAttribute")
        assert [p.get("name") for p in props] == list(features)
        for prop in props:
            feature = features[prop.get("name")]
            where = f"{eclass.get('name')}.{prop.get('name')}"
            assert feature.get("ordered") == "false", where
            # UML's default lower bound is 1: mandatory unless the property says lower 0
            lower = prop.xpath("lowerValue")
            mandatory = not lower or lower[0].get("value") not in (None, "0")
            assert feature.get("lowerBound") == ("1" if mandatory else None), where
            if prop.get("name").startswith("base_"):
                assert feature.get(TYPE) == "ecore:EReference", where
                metaclass = prop.xpath("type/@href")[0].split("#")[1]
                assert feature.xpath("eType/@href") == [UML_ECORE + metaclass], where
                continue
            assert feature.get(TYPE) == "ecore:EAttribute", where
            default = prop.xpath("defaultValue")
            if prop.get("type"):  # an enumeration of the profile
                enum = by_id[prop.get("type")]
                eenum = package.xpath(
                    "eClassifiers[@xmi:id=$i]", namespaces=NS, i=feature.get("eType")
                )
                assert eenum and eenum[0].get("name") == enum.get("name"), where
                expected = by_id[default[0].get("instance")].get("name") if default else None
            else:
                primitive = prop.xpath("type/@href")[0].split("#")[1]
                assert feature.xpath("eType/@href") == [UML_TYPES + primitive], where
                expected = default[0].get("value") if default else None
            assert feature.get("defaultValueLiteral") == expected, where
    for enum in prof.xpath("packagedElement[@xmi:type='uml:Enumeration']", namespaces=NS):
        (eenum,) = package.xpath("eClassifiers[@name=$n]", n=enum.get("name"))
        assert eenum.get(TYPE) == "ecore:EEnum"
        assert eenum.xpath(f"eAnnotations[@source='{UML2}']/@references") == [enum.get(ID)]
        literals = eenum.xpath("eLiterals")
        assert [lit.get("name") for lit in literals] == enum.xpath("ownedLiteral/@name")
        assert [int(lit.get("value", "0")) for lit in literals] == list(range(len(literals)))


def _load_with_pyecore(tmp_path: Path) -> EPackage:
    """The definition as a standalone .ecore, loaded by pyecore with the UML metaclasses and
    primitive types it refers to registered under their Eclipse nsURIs."""
    package = _definition(_profile())
    root = etree.Element(
        "{http://www.eclipse.org/emf/2002/Ecore}EPackage",
        nsmap={"xmi": XMI, "ecore": "http://www.eclipse.org/emf/2002/Ecore"},
    )
    for key, value in package.attrib.items():
        if key != TYPE:
            root.set(key, value)
    for ann in package.iter("eAnnotations"):
        ann.attrib.pop("references", None)  # into the UML part: checked above
    root.extend(list(package))
    path = tmp_path / "ACORDCS.ecore"
    path.write_bytes(etree.tostring(root))
    rset = ResourceSet()
    uml = EPackage("uml", nsURI=UML, nsPrefix="uml")
    uml.eClassifiers.extend(
        EClass(m) for m in ("Class", "Component", "Port", "Property", "AssociationClass")
    )
    types = EPackage("types", nsURI=UML_TYPES[:-3], nsPrefix="types")
    types.eClassifiers.extend(EDataType(t, str) for t in ("String", "Real", "Integer", "Boolean"))
    rset.metamodel_registry[uml.nsURI] = uml
    rset.metamodel_registry[types.nsURI] = types
    return rset.get_resource(URI(str(path))).contents[0]


def test_pyecore_loads_the_definition(tmp_path):
    loaded = _load_with_pyecore(tmp_path)
    assert loaded.nsURI == PROFILE_URI
    policy_set = loaded.getEClassifier("CtxPolicySet")
    engine = policy_set.findEStructuralFeature("engine")
    assert isinstance(engine.eType, EEnum)
    assert [lit.name for lit in engine.eType.eLiterals] == ["fuzzy", "clips"]
    assert policy_set.findEStructuralFeature("base_Class").eType.name == "Class"
    assert policy_set.findEStructuralFeature("base_Class").lowerBound == 1


def test_the_papyrus_sample_validates_clean():
    result = run_main(["validate", "--fail-on", "warning", str(SAMPLE)])
    assert (result.code, result.out) == (0, f"{SAMPLE}: 0 errors, 0 warnings, 0 infos\n")


def test_the_papyrus_sample_applies_the_defined_profile(tmp_path):
    root = etree.parse(str(SAMPLE)).getroot()
    schema = root.get("{http://www.w3.org/2001/XMLSchema-instance}schemaLocation").split()
    assert schema == [PROFILE_URI, f"ACORDCS.profile.uml#{EPACKAGE_ID}"]
    (application,) = root.xpath("uml:Model/profileApplication", namespaces=NS)
    assert application.xpath("eAnnotations/references/@href") == [
        f"ACORDCS.profile.uml#{EPACKAGE_ID}"
    ]
    assert application.xpath("appliedProfile/@href") == [f"ACORDCS.profile.uml#_{PROFILE_NAME}"]
    # Every application is an instance of the loaded definition: tags are features, enumeration
    # values literals, numbers numbers, bases ids of the model.
    loaded = _load_with_pyecore(tmp_path)
    ids = {el.get(ID) for el in root.iter() if el.get(ID)}
    applications = [el for el in root if etree.QName(el).namespace == PROFILE_URI]
    assert len(applications) == 11
    for app in applications:
        eclass = loaded.getEClassifier(etree.QName(app).localname)
        instance = eclass()
        for key, value in app.attrib.items():
            if key == ID:
                continue
            feature = eclass.findEStructuralFeature(key)
            assert feature is not None, f"{eclass.name} has no feature {key}"
            if key.startswith("base_"):
                assert value in ids
            elif isinstance(feature.eType, EEnum):
                instance.eSet(feature, feature.eType.getEEnumLiteral(value))
                assert instance.eGet(feature).name == value
            elif feature.eType.name == "Real":
                float(value)


def test_the_sample_s_copy_of_the_profile_is_what_export_writes():
    assert (SAMPLE.parent / "ACORDCS.profile.uml").read_bytes() == eclipse_profile()


@pytest.mark.parametrize("tool", [None, "bouml", "papyrus"])
def test_profile_export_writes_the_files(tmp_path, tool):
    target = tmp_path / "new" / "profiles"
    args = ["profile", "export", str(target)] + (["--tool", tool] if tool else [])
    result = run_main(args)
    assert result.code == 0, result.both
    expected = {None: {"ACORDCS.xmi", "ACORDCS.profile.uml"}, "bouml": {"ACORDCS.xmi"}}.get(
        tool, {"ACORDCS.profile.uml"}
    )
    assert {p.name for p in target.iterdir()} == expected
    assert all(line.startswith("wrote ") for line in result.out.splitlines())
    again = run_main(args)
    assert again.code == 0
    assert all(line.startswith("up to date ") for line in again.out.splitlines())
    if "ACORDCS.profile.uml" in expected:
        assert (target / "ACORDCS.profile.uml").read_bytes() == eclipse_profile()


def test_profile_export_into_a_file_or_an_unwritable_place_exits_2(tmp_path):
    a_file = tmp_path / "model.xmi"
    a_file.write_text("x", encoding="utf-8")
    result = run_main(["profile", "export", str(a_file)])
    assert result.code == 2 and "is a file" in result.err and "Traceback" not in result.err
    assert "give a directory" in result.err
    result = run_main(["profile", "export", str(a_file / "sub")])
    assert result.code == 2 and "cannot write the profile files" in result.err
    assert run_main(["profile", "export", "--tool", "rational", str(tmp_path)]).code == 2
