"""Real exports of Enterprise Architect, MagicDraw, Modelio, Visual Paradigm, Umbrello and Rational Rose,
read in place from ``../shared/reference/xmi-other-tools`` (skipped without it, failing with CI=true).

Each file is checked twice: against the counts its ``SOURCES.md`` states (made independently of the
project), and against an XPath count over the raw file written here from the XMI forms (content outside
``xmi:Extension`` / ``XMI.extension``, which hold diagrams and tool data).
"""

from __future__ import annotations

import json

import pytest
from lxml import etree

from tests.support.toolchain import XMI_OTHER_TOOLS, codes_in, no_crash, run_main, xmi_sample

UMBRELLO = "umbrello__class_all-elements.xmi"
MAGICDRAW = "marklogic-uml2es__DHFEmployeeSample_md18.5.xml"
EA = "staruml-xmi__EA_XMI21.xmi"
MODELIO = "portaless__test5_modelio-objing3.0.0.xmi"
VP = "staruml-xmi__VP7.0.0_XMI12.xmi"
ROSE = "argouml-tests__issue4919-Rose-uml13-xmi11.xmi"

MEMBERS = "//*[self::packagedElement or self::nestedClassifier or self::ownedMember]"
PARSER = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)


def _inspect(name: str) -> dict:
    result = run_main(["inspect", "--format", "json", str(xmi_sample(name, XMI_OTHER_TOOLS))])
    no_crash(result)
    assert result.code == 0, result.both
    return json.loads(result.out)


def _validate(name: str) -> str:
    result = run_main(["validate", str(xmi_sample(name, XMI_OTHER_TOOLS))])
    no_crash(result)
    assert result.code == 0, result.out
    return result.out


def _clean(out: str) -> bool:
    """Nothing found but T313 (these files apply no ACORDCS stereotype, which T313 says) and
    R211 (elements of UML metaclasses the reader does not read, named)."""
    return codes_in(out) <= {"T313", "R211"} and " 0 errors," in out


def _tree(name: str) -> etree._Element:
    return etree.parse(str(xmi_sample(name, XMI_OTHER_TOOLS)), PARSER).getroot()


def _outside_extensions(root: etree._Element, xpath: str, ns: dict) -> list[etree._Element]:
    return [
        el
        for el in root.xpath(xpath, namespaces=ns)
        if not any(
            isinstance(a.tag, str) and a.tag.rpartition("}")[2] in ("Extension", "XMI.extension")
            for a in el.iterancestors()
        )
    ]


def _applications(parent: etree._Element) -> int:
    """Children of ``parent`` that are stereotype applications: a profile's element with base_*."""
    return sum(
        1
        for el in parent
        if isinstance(el.tag, str) and any(k.startswith("base_") for k in el.attrib)
    )


# ------------------------------------------------------------------------------ XMI 2.x / UML 2
def test_enterprise_architect_applications_inside_the_model() -> None:
    data = _inspect(EA)
    root = _tree(EA)
    ns = {"xmi": "http://schema.omg.org/spec/XMI/2.1", "uml": "http://schema.omg.org/spec/UML/2.1"}
    # members only: EA types template parameters uml:Class too (ownedParameteredElement)
    classes = _outside_extensions(root, MEMBERS + "[@xmi:type='uml:Class']", ns)
    operations = _outside_extensions(root, "//ownedOperation", ns)
    generalizations = _outside_extensions(root, "//generalization", ns)
    applications = _applications(root.find("uml:Model", ns))
    assert (len(classes), len(operations), len(generalizations), applications) == (25, 5, 2, 11)
    assert data["classifiers"]["Class"] == 25
    assert (data["operations"], data["generalizations"]) == (5, 2)
    assert sum(data["stereotype_applications"].values()) == 11
    # the profile's name comes from EA's namespace URI, not the prefix
    assert set(data["stereotype_applications"]) >= {"thecustomprofile:role_binding"}
    assert data["exporter"] == "Enterprise Architect 6.5" and data["dialect"] == "omg-xmi2"


def test_enterprise_architect_extension_ids_are_not_duplicates() -> None:
    out = _validate(EA)  # EA's xmi:Extension restates every element's id
    assert ": R203 " not in out and ": R204 " not in out


def test_magicdraw_applications_at_the_root_and_its_own_profiles_not_content() -> None:
    data = _inspect(MAGICDRAW)
    root = _tree(MAGICDRAW)
    ns = {"xmi": "http://www.omg.org/spec/XMI/20131001"}
    classes = _outside_extensions(root, MEMBERS + "[@xmi:type='uml:Class']", ns)
    assert len(classes) == 6 and data["classifiers"] == {"Class": 6}
    assert _applications(root) == 40
    assert sum(data["stereotype_applications"].values()) == 40
    apps = data["stereotype_applications"]
    assert apps["MarkLogic_Entity_Services_Profile:exclude"] == 8
    assert data["exporter"] == "MagicDraw UML 18.5" and data["model"] == "HR"
    # the profiles copied into xmi:Extension blocks are not read as model content
    assert "Stereotype" not in data["classifiers"] and data["packages"] == 0


def test_magicdraw_validates_clean() -> None:
    out = _validate(MAGICDRAW)
    assert _clean(out), out


def test_modelio_eclipse_uml2_with_its_default_profile() -> None:
    data = _inspect(MODELIO)
    root = _tree(MODELIO)
    ns = {"xmi": "http://schema.omg.org/spec/XMI/2.1"}
    dependencies = root.xpath("//packagedElement[@xmi:type='uml:Dependency']", namespaces=ns)
    classes = root.xpath("//packagedElement[@xmi:type='uml:Class']", namespaces=ns)
    assert data["dependencies"] == len(dependencies) == 9
    assert data["classifiers"]["Class"] == len(classes) == 2
    assert data["stereotype_applications"] == {"default:trace": _applications(root)}
    assert data["exporter"] == "Objing 3.0.0" and data["dialect"] == "eclipse-uml2"
    # its 4 instance specifications are the one thing not read, and said so once
    instances = root.xpath(
        "//packagedElement[@xmi:type='uml:InstanceSpecification']", namespaces=ns
    )
    (note,) = [ln for ln in _validate(MODELIO).splitlines() if ": R211 " in ln]
    assert f"R211 {len(instances)} uml:InstanceSpecification elements skipped" in note
    assert data["diagnostics"] == 1


# ------------------------------------------------------------------------------ XMI 1.x / UML 1.x
def test_umbrello_uml13_namespace_and_diagram_ids() -> None:
    data = _inspect(UMBRELLO)
    root = _tree(UMBRELLO)
    ns = {"UML": "http://schema.omg.org/spec/UML/1.3"}
    classes = _outside_extensions(root, "//UML:Class", ns)
    operations = _outside_extensions(root, "//UML:Operation", ns)
    assert (len(classes), len(operations)) == (2, 2)
    assert data["classifiers"]["Class"] == 2 and data["operations"] == 2
    # stereotypes as attributes: free UML 1.x stereotypes, no profile
    assert all(":" not in key for key in data["stereotype_applications"])
    assert data["stereotype_applications"]["interface"] == 3
    assert data["exporter"].startswith("umbrello uml modeller") and data["exporter"].endswith(
        "1.6.1"
    )
    out = _validate(UMBRELLO)  # its diagram widgets reuse the classes' ids: no R203
    assert _clean(out), out


def test_visual_paradigm_xmi12() -> None:
    data = _inspect(VP)
    root = _tree(VP)
    ns = {"UML": "org.omg/UML/1.4"}
    assert len(_outside_extensions(root, "//UML:Class", ns)) == 2
    assert data["classifiers"]["Class"] == 2 and data["operations"] == 2
    assert data["exporter"] == "Visual Paradigm 7.0.0" and data["dialect"] == "xmi1.2"
    assert _clean(_validate(VP))


def test_rational_rose_xmi11_with_doctype_is_read_as_the_empty_model_it_is() -> None:
    data = _inspect(ROSE)
    assert data["model"] == "AAA_5.1.1_K2" and data["classifiers"] == {}
    assert data["exporter"] == "Unisys.JCR.1 1.3.6" and data["dialect"] == "xmi1.1"
    out = _validate(ROSE)
    assert ": X102 " not in out and ": R208 " not in out


@pytest.mark.parametrize(
    ("name", "line"),
    [
        (EA, "omg-xmi2 (Enterprise Architect 6.5), model 'EA_Model'"),
        (MAGICDRAW, "omg-xmi2 (MagicDraw UML 18.5), model 'HR'"),
        (MODELIO, "eclipse-uml2 (Objing 3.0.0), model 'test'"),
        (VP, "xmi1.2 (Visual Paradigm 7.0.0), model 'VP_XMI_TestModel'"),
        (ROSE, "xmi1.1 (Unisys.JCR.1 1.3.6), model 'AAA_5.1.1_K2'"),
    ],
)
def test_inspect_names_the_exporter_and_version(name: str, line: str) -> None:
    result = run_main(["inspect", str(xmi_sample(name, XMI_OTHER_TOOLS))])
    assert result.out.splitlines()[0].endswith(line), result.out


def test_every_file_of_the_folder_is_checked_here() -> None:
    folder = xmi_sample(UMBRELLO, XMI_OTHER_TOOLS).parent
    present = {p.name for p in folder.iterdir() if p.name != "SOURCES.md"}
    assert present == {UMBRELLO, MAGICDRAW, EA, MODELIO, VP, ROSE}


@pytest.mark.parametrize("name", [MAGICDRAW, MODELIO, EA])
def test_every_count_matches_the_xmi2_oracle(name: str, tmp_path) -> None:
    """The full XPath oracle of ``test_readers`` (every count ``inspect`` reports). EA's root
    ``xmi:Extension`` (its own types and profile, restated elements) is removed for the oracle: not
    model content; its applications, inside ``uml:Model``, are compared on their own above."""
    from tests.xmi.test_readers import oracle

    root = _tree(name)
    for ext in [c for c in root if isinstance(c.tag, str) and c.tag.endswith("}Extension")]:
        root.remove(ext)
    stripped = tmp_path / name
    stripped.write_bytes(etree.tostring(root.getroottree(), encoding="UTF-8"))
    expected = oracle(stripped)
    data = _inspect(name)
    if name == EA:
        expected.pop("stereotype_applications")
    assert {k: data[k] for k in expected} == expected
