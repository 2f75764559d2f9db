"""The readers against real third-party exports and the project's samples.

``inspect --format json`` is compared with an independent count made here with lxml XPath over the raw
file, following the definitions of the issue (attributes are owned properties that are not association
ends nor ports; ports are owned ``uml:Port``s; associations are Association and AssociationClass; a
stereotype application counts once per (element, stereotype) whichever of BOUML's two places states
it; BOUML's ``<<profile>>`` keyword on a Profile and ``<<stereotype>>`` on a Stereotype are not
applications).
"""

from __future__ import annotations

import json
import re
from collections import Counter
from pathlib import Path

import pytest
from lxml import etree

from acordcs.diagnostics import Severity
from acordcs.model.architecture import interpret
from acordcs.model.reading import read_model
from acordcs.xmi.readers import read_uml
from acordcs.xmi.uml import Classifier
from tests.support.toolchain import (
    SMARTROOM,
    WEBLAB,
    XMI_SAMPLES,
    codes_in,
    no_crash,
    reference_dir,
    reference_files,
    reference_params,
    replace,
    run_main,
    run_process,
    write_model,
    xmi_sample,
)

# Listed at collection time: a placeholder that skips (fails with CI=true) when the folder is absent.
REAL_FILES = reference_params(XMI_SAMPLES)
ALL_FILES = [*REAL_FILES, WEBLAB, SMARTROOM]

# UML classifier metaclasses (UML 2.5, concrete), associations apart: they are counted on their own.
CLASSIFIERS = {
    "Class",
    "Interface",
    "Enumeration",
    "PrimitiveType",
    "DataType",
    "Actor",
    "AssociationClass",
    "Stereotype",
    "Component",
    "Signal",
    "UseCase",
    "Artifact",
    "Node",
    "Device",
    "ExecutionEnvironment",
    "Collaboration",
    "InformationItem",
    "Activity",
    "StateMachine",
    "ProtocolStateMachine",
    "Interaction",
    "OpaqueBehavior",
    "FunctionBehavior",
}
DEPENDENCIES = {"Dependency", "Realization", "Usage", "Abstraction", "Substitution"}
# Where UML 2.5 has a classifier owned: a package's members, a classifier's nested classifiers,
# use cases and behaviours, a node's nodes, an artifact's artifacts.
MEMBER_TAGS = {
    "packagedElement",
    "ownedMember",
    "ownedElement",
    "ownedStereotype",
    "nestedClassifier",
    "ownedType",
    "ownedUseCase",
    "ownedBehavior",
    "nestedNode",
    "nestedArtifact",
}
PARSER = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)


def test_reference_samples_are_there() -> None:
    assert reference_dir(XMI_SAMPLES).is_dir(), XMI_SAMPLES
    assert len(REAL_FILES) == 5, REAL_FILES


# ------------------------------------------------------------------------------------ the oracle
def _oracle_xmi2(root: etree._Element) -> dict:
    nsmap = {k: v for k, v in root.nsmap.items() if v}
    uml = next(
        v
        for v in nsmap.values()
        if re.search(r"omg\.org/spec/UML/|eclipse\.org/uml2/[\d.]+/UML$", v)
    )
    xmi = next(v for v in nsmap.values() if re.search(r"omg\.org/(spec/)?XMI", v))
    xid, xtype = f"{{{xmi}}}id", f"{{{xmi}}}type"

    def kind(el) -> str | None:
        if el.get(xtype):
            return el.get(xtype).rpartition(":")[2]
        if el.tag.startswith(f"{{{uml}}}"):
            return el.tag.rpartition("}")[2]
        return None

    def is_member(el) -> bool:
        """A model element in a containment position (not a reference like <type xmi:idref>)."""
        local = el.tag.rpartition("}")[2] if isinstance(el.tag, str) else ""
        return el.get(xid) is not None and (local in MEMBER_TAGS or el.tag.startswith(f"{{{uml}}}"))

    members = [el for el in root.iter(etree.Element) if is_member(el)]
    classifiers = [el for el in members if kind(el) in CLASSIFIERS]
    # ids named as association member ends, by attribute or by <memberEnd xmi:idref> child
    member_ends = set()
    for el in root.xpath("//*[@memberEnd]"):
        member_ends.update(el.get("memberEnd").split())
    member_ends.update(root.xpath("//memberEnd/@x:idref", namespaces={"x": xmi}))
    attributes = ports = operations = generalizations = 0
    for cls in classifiers:
        # Enterprise Architect writes a class's ports apart, as ownedPort; the other tools as an
        # ownedAttribute of type uml:Port. A port is no attribute (UML makes it a Property).
        for attr in cls.iterchildren("ownedAttribute", "ownedPort"):
            if attr.get("association") is not None or attr.get(xid) in member_ends:
                continue
            if attr.tag == "ownedPort" or attr.get(xtype) == "uml:Port":
                ports += 1
            else:
                attributes += 1
        operations += len(cls.findall("ownedOperation"))
        generalizations += len(cls.findall("generalization"))
    ids = set(root.xpath("//@x:id", namespaces={"x": xmi}))
    applications = set()
    for el in root:  # 1. root-level applications
        if not isinstance(el.tag, str) or el.tag.startswith((f"{{{uml}}}", f"{{{xmi}}}")):
            continue
        for key, value in el.attrib.items():
            if key.startswith("base_") and value in ids:
                applications.add((value, f"{el.prefix}:{etree.QName(el).localname}"))
    for ext in root.iter(f"{{{xmi}}}Extension"):  # 2. BOUML's xmi:Extension blocks
        if ext.get("extender") != "Bouml":
            continue
        owner = ext.getparent()
        for st in ext.iterchildren("stereotype"):
            name = st.get("name")
            keyword = {"Profile": "profile", "Stereotype": "stereotype"}.get(kind(owner))
            if name == keyword:
                continue
            applications.add((owner.get(xid), name))
    return {
        "classifiers": dict(Counter(kind(c) for c in classifiers)),
        "attributes": attributes,
        "ports": ports,
        "operations": operations,
        "associations": sum(kind(el) in ("Association", "AssociationClass") for el in members),
        "generalizations": generalizations,
        "dependencies": sum(kind(el) in DEPENDENCIES for el in members),
        "packages": sum(kind(el) in ("Package", "Profile") for el in members),
        "stereotype_applications": dict(Counter(key for _, key in applications)),
    }


def _oracle_xmi12(root: etree._Element) -> dict:
    u = "org.omg.xmi.namespace.UML"

    def defined(local: str) -> list:
        return root.xpath(f"//u:{local}[@xmi.id]", namespaces={"u": u})

    classifiers = Counter()
    for local in CLASSIFIERS:
        classifiers[local] += len(defined(local))
    applications = set()
    for st in root.xpath("//u:ModelElement.stereotype/u:Stereotype", namespaces={"u": u}):
        applications.add((st.getparent().getparent(), st.get("name")))
    return {
        "classifiers": {k: n for k, n in classifiers.items() if n},
        "attributes": len(defined("Attribute")),
        "ports": 0,  # UML 1.x has no ports
        "operations": len(defined("Operation")),
        "associations": len(defined("Association")) + len(defined("AssociationClass")),
        "generalizations": len(defined("Generalization")),
        "dependencies": sum(len(defined(k)) for k in ("Dependency", "Abstraction", "Usage")),
        "packages": len(defined("Package")),
        "stereotype_applications": dict(Counter(name for _, name in applications)),
    }


def oracle(path: Path) -> dict:
    root = etree.parse(str(path), PARSER).getroot()
    if root.tag == "XMI":
        return _oracle_xmi12(root)
    return _oracle_xmi2(root)


def inspect_json(path: Path) -> dict:
    result = run_main(["inspect", "--format", "json", str(path)])
    assert result.code == 0, result.both
    return json.loads(result.out)


# ------------------------------------------------------------------------------------ the tests
@pytest.mark.parametrize("path", REAL_FILES, ids=lambda p: p.name)
def test_real_export_loads_without_errors(path: Path) -> None:
    reading = read_model(str(path))
    assert reading.uml.dialect in ("bouml-xmi2", "bouml-xmi12", "eclipse-uml2")
    # They apply no ACORD-CS stereotype: T313 says so, and nothing else is wrong with them.
    assert "T313" in {d.code for d in reading.diagnostics}
    bad = [d for d in reading.diagnostics if d.severity >= Severity.WARNING and d.code != "T313"]
    assert bad == [], "\n".join(d.format_text() for d in bad)


def test_validate_all_real_exports_at_once() -> None:
    real_files = reference_files(XMI_SAMPLES)
    result = run_process(["validate", *map(str, real_files)])
    assert result.code == 0, result.both
    # one warning each: T313, no ACORD-CS stereotype applied
    assert result.out.count(": 0 errors, 1 warning, 0 infos") == len(real_files)


@pytest.mark.parametrize("path", ALL_FILES, ids=lambda p: p.name)
def test_inspect_agrees_with_an_independent_count(path: Path) -> None:
    data = inspect_json(path)
    expected = oracle(path)
    got = {key: data[key] for key in expected}
    assert got == expected
    assert sum(data["classifiers"].values()) > 0


def test_oracle_sees_what_the_samples_contain() -> None:
    """The oracle itself, on facts read off the files by eye."""
    cd = oracle(xmi_sample("SecondStageModels__CDKatalog.xmi"))
    assert cd["classifiers"] == {"Class": 4, "Stereotype": 8}
    assert cd["attributes"] == 16  # 3+2+3+3 class attributes, 5 stereotype tags
    assert cd["stereotype_applications"] == {
        "entity": 2,
        "form": 2,
        "visible": 1,
        "lbDMF:masterdetail_action": 1,
        "lbDMF:pk": 2,
        "lbDMF:relationship": 2,
    }
    football = oracle(xmi_sample("Football-world-cup__bouml.xmi"))
    assert football["classifiers"]["AssociationClass"] == 3
    assert football["generalizations"] == 9
    tpb = oracle(xmi_sample("TPB3D__tpb3d.xmi"))
    assert tpb == {
        "classifiers": {"Class": 6, "DataType": 3},
        "attributes": 4,
        "ports": 0,
        "operations": 0,
        "associations": 1,
        "generalizations": 3,
        "dependencies": 0,
        "packages": 3,
        "stereotype_applications": {"List": 1},
    }


def _by_name(uml, name: str, kind: str | None = None):
    found = [
        e for e in uml.elements.values() if e.name == name and (kind is None or e.kind == kind)
    ]
    assert len(found) == 1, (name, found)
    return found[0]


def _attr(uml, cls: str, attr: str):
    owner = next(c for c in uml.classifiers if c.name == cls)
    return next(a for a in owner.attributes if a.name == attr)


def test_types_resolved_without_network() -> None:
    uml = read_uml(str(WEBLAB))
    assert _attr(uml, "Image", "width").type_name == "int"  # OMG href #Integer
    assert _attr(uml, "Image", "encoding").type_name == "string"  # #String
    assert _attr(uml, "Image", "timestamp").type_name == "double"  # BOUML_datatype_0
    step = next(o for c in uml.classifiers for o in c.operations if o.name == "step")
    assert step.return_type == "bool"  # #Boolean
    find = next(o for c in uml.classifiers for o in c.operations if o.name == "findStripe")
    assert [(p.name, p.type_name) for p in find.inputs] == [("frame", "Image")]
    football = read_uml(str(xmi_sample("Football-world-cup__bouml.xmi")))
    assert _attr(football, "Patrocinador", "nome").type_name == "varchar(20)"
    assert _attr(football, "Comitiva", "sigla").type_name == "varchar(10)"
    tpb = read_uml(str(xmi_sample("TPB3D__tpb3d.xmi")))
    assert _attr(tpb, "Parameter", "Value").type_name == "object"
    codegen = read_uml(str(xmi_sample("pyuml2-codegen__Codegen.profile.uml")))
    assert _attr(codegen, "Project", "projectName").type_name == "string"  # pathmap href


def test_unlimited_natural_is_long(weblab_text: str, tmp_path: Path) -> None:
    """BOUML writes its `long` as UnlimitedNatural."""
    old = (
        '<ownedAttribute xmi:type="uml:Property" name="width" xmi:id="BOUML_0x1f402_1" visibility="private">\n'
        '\t\t\t\t\t\t\t<type xmi:type="uml:PrimitiveType" href="http://schema.omg.org/spec/UML/2.1/uml.xml#Integer"/>'
    )
    target = tmp_path / "long.xmi"
    target.write_text(replace(weblab_text, old, old.replace("#Integer", "#UnlimitedNatural")))
    assert _attr(read_uml(str(target)), "Image", "width").type_name == "long"


def test_eclipse_references_and_comments() -> None:
    uml = read_uml(str(xmi_sample("pyuml2-codegen__Codegen.profile.uml")))
    assert uml.dialect == "eclipse-uml2"
    # references are attributes holding ids
    assert _attr(uml, "Project", "generationMode").type_name == "GenerationModeKind"
    assert _attr(uml, "GeneratorHint", "language").type_name == "Language"
    assert _attr(uml, "MavenProject", "dependencies").type_name == "MavenDependency"
    # ends of uml:Extension (base_Class, base_Package, ...) are not attributes
    names = {a.name for c in uml.classifiers for a in c.attributes}
    assert not any(n.startswith("base_") for n in names)
    # generalization by attribute
    maven = next(c for c in uml.classifiers if c.name == "MavenProject")
    assert [uml.elements[g].name for g in maven.generals] == ["Project"]
    # comments: a <body> child, attached through annotatedElement
    project = _by_name(uml, "Project", "Stereotype")
    assert len(project.comments) == 1
    assert project.comments[0].startswith("Control how code is generated:\n- name of project")
    language = _by_name(uml, "Language", "Stereotype")
    assert language.comments[0].startswith("<p>Indicate programming language.")
    profile = _by_name(uml, "Codegen", "Profile")
    assert profile.comments == []  # the owner of an annotating comment is not its subject
    # the Ecore stereotype application carries its tags as XML attributes
    (app,) = uml.applications_of(profile.id)
    assert app.key == "Ecore:EPackage"
    assert app.tags == {
        "packageName": "Codegen",
        "nsPrefix": "Codegen",
        "nsURI": "http://www.eclipse.org/papyrus/Codegen/1",
        "prefix": "Codegen",
    }
    model = read_uml(str(xmi_sample("pyuml2-codegen__testModel.uml")))
    (app,) = model.applications.values()
    assert (model.elements[app.base].name, app.key) == ("Class4", "Codegen:ArcheType")


def test_bouml_comments() -> None:
    uml = read_uml(str(WEBLAB))
    assert _by_name(uml, "Image", "Class").comments == [
        "A frame of the on-board camera as the vision service returns it."
    ]
    (navigator,) = _by_name(uml, "Navigator", "Class").comments
    assert "stripe is found.\nThe only element" in navigator  # &#10; is a newline


def test_bouml_free_stereotypes_and_tags() -> None:
    uml = read_uml(str(xmi_sample("SecondStageModels__CDKatalog.xmi")))
    entities = [
        c for c in uml.classifiers if any(a.key == "entity" for a in uml.applications_of(c.id))
    ]
    assert sorted(c.qualified_name() for c in entities) == [
        "CDKatalog::DMFToUML::CDKatalog_Entities::CD",
        "CDKatalog::DMFToUML::CDKatalog_Entities::Musiker",
    ]
    free = [a for a in uml.applications.values() if a.profile is None]
    assert sorted(a.name for a in free) == ["entity", "entity", "form", "form", "visible"]
    # a two-part tag is a plain tagged value of the element, not a stereotype tag
    form_cd = next(c for c in uml.classifiers if c.id == "BOUML_0x1f402_4")
    assert form_cd.tagged_values == {"lbDMF:toolbarimagefile": "cookie.png"}
    # profile stereotype: tags from both places, merged and equal
    (rel,) = [a for a in uml.applications_of("BOUML_0x1f982_0") if a.name == "relationship"]
    assert rel.tags == {"order": "1", "table": "Musiker", "sourcecolumn": "ID"}
    assert rel.places == {"root", "extension"}
    # BOUML's own export options are not tags
    root_pkg = uml.elements["BOUML_0x81_22"]
    assert not any(k.startswith("gxmi") for k in root_pkg.tagged_values)
    # the profile's <<profile>> and its stereotypes' <<stereotype>> are keywords, not applications
    assert all(a.name not in ("profile", "stereotype") for a in uml.applications.values())


def _usage_role(path: Path):
    reading = read_model(str(path))
    role = next(r for r in reading.architecture.roles.values() if r.name == "Usage")
    return reading, role


def test_tag_from_either_place(weblab_text: str, tmp_path: Path) -> None:
    """A tag written only at the root, or only in xmi:Extension, is read the same."""
    ext_tag = '<taggedValue tag="ACORDCS:CtxMonitor:frequency" value="1"/>'
    only_root = tmp_path / "root.xmi"
    only_root.write_text(replace(weblab_text, ext_tag, ""))
    only_ext = tmp_path / "ext.xmi"
    only_ext.write_text(
        replace(
            weblab_text,
            'frequency="1" base_Element="BOUML_0x20102_4"',
            'base_Element="BOUML_0x20102_4"',
        )
    )
    for path in (only_root, only_ext):
        reading, role = _usage_role(path)
        assert role.tag("frequency") == "1", path.name
        assert reading.diagnostics == [], path.name


def test_a_second_root_application_that_disagrees_gives_r205(
    weblab_text: str, tmp_path: Path
) -> None:
    first = (
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20102_4" acquisition="poll" xpath="" '
        'operation="countUsers" frequency="1" base_Element="BOUML_0x20102_4"/>'
    )
    second = first.replace('frequency="1"', 'frequency="5"').replace("STELT_", "STELT2_")
    target = tmp_path / "twice.xmi"
    target.write_text(replace(weblab_text, first, first + "\n" + second))
    reading, role = _usage_role(target)
    found = [d for d in reading.diagnostics if d.severity >= Severity.WARNING]
    assert [d.code for d in found] == ["R205"]
    assert "stated twice, '1' then '5'; using '1'" in found[0].message
    assert role.tag("frequency") == "1"
    # Stated twice with the same value: nothing to say.
    same = tmp_path / "same.xmi"
    same.write_text(replace(weblab_text, first, first + "\n" + first.replace("STELT_", "STELT2_")))
    assert _usage_role(same)[0].diagnostics == []


def test_disagreeing_tag_places_give_r205(weblab_text: str, tmp_path: Path) -> None:
    target = tmp_path / "r205.xmi"
    target.write_text(
        replace(
            weblab_text,
            'frequency="1" base_Element="BOUML_0x20102_4"',
            'frequency="2" base_Element="BOUML_0x20102_4"',
        )
    )
    reading, role = _usage_role(target)
    found = [d for d in reading.diagnostics if d.severity >= Severity.WARNING]
    assert [d.code for d in found] == ["R205"]
    message = found[0].message
    assert "'frequency'" in message and "'1'" in message and "'2'" in message
    used = re.search(r"using '([^']*)'", message).group(1)
    assert role.tag("frequency") == used  # the value said to be used is the one used


def test_the_profile_is_known_by_its_namespace_not_its_prefix(weblab_text, tmp_path):
    text = weblab_text.replace("xmlns:ACORDCS=", "xmlns:acs=").replace("<ACORDCS:", "<acs:")
    text = re.sub(r'\s*<stereotype name="ACORDCS:[^"]*"/>', "", text)  # root-level copies only
    result = run_main(["inspect", "--format", "json", str(write_model(tmp_path, text))])
    no_crash(result)
    assert '"CtxComponent": [' in result.out.replace("\n", "").replace("  ", "")
    assert '"acs:' not in result.out
    assert run_main(["validate", str(tmp_path / "model.xmi")]).code == 0


def test_an_application_to_a_missing_element_fails_validation(weblab_text, tmp_path):
    text = weblab_text.replace(
        "</xmi:XMI>", '<ACORDCS:CtxComponent xmi:id="APPX" base_Element="NOPE"/></xmi:XMI>'
    )
    result = run_main(["validate", str(write_model(tmp_path, text))])
    assert codes_in(result.out) == {"R204"} and result.code == 1


def test_keyword_markers_are_not_applications() -> None:
    """The WebLab embeds the ACORDCS profile: its Profile and 8 Stereotypes carry BOUML's keywords."""
    uml = read_uml(str(WEBLAB))
    stereotypes = [c for c in uml.classifiers if c.kind == "Stereotype"]
    assert len(stereotypes) == 8
    for element in [*stereotypes, *[p for p in uml.packages if p.kind == "Profile"]]:
        assert uml.applications_of(element.id) == [], element.name


def test_xmi12_reading() -> None:
    uml = read_uml(str(xmi_sample("TPB3D__tpb3d.xmi")))
    assert uml.dialect == "bouml-xmi12"
    assert uml.exporter == "Bouml 1.4.6"
    generals = {
        c.name: sorted(uml.elements[g].name for g in c.generals)
        for c in uml.classifiers
        if c.generals
    }
    assert generals == {"Container": ["Control"], "Panel": ["Container"], "Button": ["Control"]}
    (app,) = uml.applications.values()
    end = uml.elements[app.base]
    assert (app.key, app.profile, end.kind, end.name) == ("List", None, "Property", "Parameters")
    assert uml.elements[end.type_ref].name == "Parameter"
    assert _attr(uml, "Parameter", "Name").type_name == "string"


XMI12_ACORDCS = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.2" xmlns:UML="org.omg.xmi.namespace.UML">
<XMI.header><XMI.documentation><XMI.exporter>Bouml</XMI.exporter>
<XMI.exporterVersion>1.4.6</XMI.exporterVersion></XMI.documentation></XMI.header>
<XMI.content>
 <UML:Model name="old" xmi.id="M1"><UML:Namespace.ownedElement>
  <UML:Class name="Hub" xmi.id="C1" visibility="public">
   <UML:ModelElement.stereotype><UML:Stereotype name="CtxComponent"/></UML:ModelElement.stereotype>
   <UML:ModelElement.taggedValue>
    <UML:TaggedValue tag="stereotype" value="CtxComponent"/>
    <UML:TaggedValue tag="language" value="java"/>
   </UML:ModelElement.taggedValue>
  </UML:Class>
 </UML:Namespace.ownedElement></UML:Model>
</XMI.content>
</XMI>
"""


def test_an_unknown_uml_element_in_xmi_1_2_is_reported(tmp_path):
    """A warning naming it when it holds nothing ACORD-CS reads (TPB3D applies no ACORD-CS
    stereotype): the model validates; an error when it has an ACORD-CS stereotype."""
    text = xmi_sample("TPB3D__tpb3d.xmi").read_text(encoding="utf-8")
    start = text.index('<UML:Class name="Panel"')
    end = text.index("</UML:Class>", start)
    text = text[:start] + "<UML:Klass" + text[start + 10 : end] + "</UML:Klass>" + text[end + 12 :]
    result = run_main(["validate", str(write_model(tmp_path, text))])
    no_crash(result)
    (line,) = [ln for ln in result.out.splitlines() if ": R201 " in ln]
    assert ": warning: R201 unknown element UML:Klass (did you mean UML:Class?) on 'Panel'" in line
    assert "nothing ACORD-CS reads is lost" in line
    assert result.code == 0, result.out
    hub = replace(XMI12_ACORDCS, '<UML:Class name="Hub"', '<UML:Klass name="Hub"')
    hub = replace(hub, "</UML:Class>", "</UML:Klass>")
    target = tmp_path / "hub.xmi"
    target.write_text(hub)
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 1, result.out
    (line,) = [ln for ln in result.out.splitlines() if ": R201 " in ln]
    assert f"{target}:7:1: error: R201 unknown element UML:Klass (did you mean UML:Class?) " in line
    assert (
        "on 'Hub'; it is skipped, and it has the stereotype <<CtxComponent>>, which ACORD-CS reads"
        in line
    )


def test_xmi12_free_stereotype_named_like_ours_is_read_as_acordcs(tmp_path: Path) -> None:
    target = tmp_path / "old.xmi"
    target.write_text(XMI12_ACORDCS)
    uml = read_uml(str(target))
    arch = interpret(uml)
    (role,) = arch.roles.values()
    assert (role.kind, role.name, role.tag("language")) == ("CtxComponent", "Hub", "java")
    assert [d.code for d in uml.diagnostics] == ["R206"]
    assert uml.diagnostics[0].severity is Severity.INFO


def test_bouml_free_stereotype_named_like_ours(weblab_text: str, tmp_path: Path) -> None:
    """``<stereotype name="CtxComponent"/>`` without the profile prefix: R206, and a role."""
    text = replace(
        weblab_text,
        '<ACORDCS:CtxComponent xmi:id="BOUML_STELT_0x1f502_4" language="python" persistent="false" base_Element="BOUML_0x1f502_4"/>\n',
        "",
    )
    start = text.index('name="Vision" xmi:id="BOUML_0x1f502_4"')
    end = text.index("</xmi:Extension>", start)
    block = text[start:end]
    free = (
        block.replace('name="ACORDCS:CtxComponent"', 'name="CtxComponent"')
        .replace('tag="ACORDCS:CtxComponent:language"', 'tag="language"')
        .replace('tag="ACORDCS:CtxComponent:persistent"', 'tag="persistent"')
    )
    target = tmp_path / "free.xmi"
    target.write_text(text[:start] + free + text[end:])
    reading = read_model(str(target))
    assert [d.code for d in reading.diagnostics] == ["R206"]
    role = next(r for r in reading.architecture.roles.values() if r.name == "Vision")
    assert (role.kind, role.tag("language")) == ("CtxComponent", "python")


def _no_model(text: str) -> str:
    """BOUML's "no model" option: no uml:Model, its content directly under xmi:XMI."""
    text = re.sub(r"\n\t<uml:Model [^>]*>", "", text, count=1)
    return replace(text, "\n\t</uml:Model>", "")


def test_no_model_variant_reads_like_the_sample(weblab_text: str, tmp_path: Path) -> None:
    target = tmp_path / "nomodel.xmi"
    target.write_text(_no_model(weblab_text))
    assert "<uml:Model" not in target.read_text()
    with_model = inspect_json(WEBLAB)
    without = inspect_json(target)
    for key in ("classifiers", "attributes", "operations", "associations", "packages"):
        assert without[key] == with_model[key], key
    assert without["stereotype_applications"] == with_model["stereotype_applications"]
    assert without["acordcs"] == with_model["acordcs"]
    assert read_model(str(target)).diagnostics == []


def test_iso_8859_1_export_reads_with_correct_names(tmp_path: Path) -> None:
    source = xmi_sample("SecondStageModels__CDKatalog.xmi")
    text = source.read_text(encoding="utf-8")
    text = replace(text, 'encoding="UTF-8"', 'encoding="ISO-8859-1"')
    text = replace(text, 'name="Laenge"', 'name="Länge"', count=2)
    text = replace(
        text,
        'name="Musiker" xmi:id="BOUML_0x1f482_4"',
        'name="Musikerßäöü" xmi:id="BOUML_0x1f482_4"',
    )
    target = tmp_path / "latin1.xmi"
    target.write_bytes(text.encode("iso-8859-1"))
    assert "Länge".encode("iso-8859-1") in target.read_bytes()  # really single-byte encoded
    reading = read_model(str(target))
    assert [d.code for d in reading.diagnostics] == ["T313"]  # no ACORD-CS stereotype
    uml = reading.uml
    assert [a.name for c in uml.classifiers for a in c.attributes].count("Länge") == 2
    assert "Musikerßäöü" in {c.name for c in uml.classifiers}
    comment = uml.elements["BOUML_0x1f602_4"].comments[0]  # ´ (U+00B4) is in ISO-8859-1
    assert "´master form opens a detail form´" in comment
    assert inspect_json(target) | {"file": None} == inspect_json(source) | {
        "file": None,
    }


def test_utf8_bytes_declared_iso_8859_1_are_reported_not_garbled_silently(tmp_path: Path) -> None:
    source = xmi_sample("SecondStageModels__CDKatalog.xmi")
    text = source.read_text(encoding="utf-8")
    text = replace(text, 'encoding="UTF-8"', 'encoding="ISO-8859-1"')
    text = replace(text, 'name="Laenge"', 'name="Länge"', count=2)
    target = tmp_path / "mojibake.xmi"
    target.write_bytes(text.encode("utf-8"))  # the declaration lies: the bytes are UTF-8
    reading = read_model(str(target))
    assert [d.code for d in reading.diagnostics] == ["X110", "T313"]
    warning = reading.diagnostics[0]
    assert warning.line == 1 and warning.severity.name == "WARNING"
    data = text.encode("utf-8")
    line = data.count(b"\n", 0, data.index("Länge".encode())) + 1
    assert f"first at line {line}:" in warning.message
    assert "'ä' would read as 'Ã¤'" in warning.message
    # The model is still read (as the declaration says), and the exit code is 0 at --fail-on error
    assert "LÃ¤nge" in {a.name for c in reading.uml.classifiers for a in c.attributes}
    result = run_main(["validate", str(target)])
    no_crash(result)
    assert result.code == 0 and " X110 " in result.out


def test_classifier_members_by_kind() -> None:
    """Association classes are classifiers and associations; their memberEnd children are ends."""
    uml = read_uml(str(xmi_sample("Football-world-cup__bouml.xmi")))
    assoc_classes = [c for c in uml.classifiers if c.kind == "AssociationClass"]
    assert len(assoc_classes) == 3
    assert all(c in uml.associations for c in assoc_classes)
    estat = next(c for c in assoc_classes if c.name == "Estat_Jogador")
    assert [a.name for a in estat.attributes] == [
        "num_golos",
        "num_assistencias",
        "jogos_sem_sofrer_golos",
    ]
    assert estat.member_ends == ["BOUML_0x1f402_0", "BOUML_0x1f482_0"]
    assert all(isinstance(uml.elements[e].owner, Classifier) for e in estat.member_ends)


def test_eclipse_namespace_declaration_order_does_not_matter(tmp_path: Path) -> None:
    source = xmi_sample("pyuml2-codegen__Codegen.profile.uml")
    text = source.read_text(encoding="utf-8")
    uml_decl = ' xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML"'
    text = replace(text, uml_decl, "")
    text = replace(
        text,
        'xmlns:xmi="http://www.omg.org/spec/XMI/20131001"',
        'xmlns:xmi="http://www.omg.org/spec/XMI/20131001"' + uml_decl,
    )
    target = tmp_path / "reordered.profile.uml"
    target.write_text(text, encoding="utf-8")
    assert inspect_json(target) | {"file": None} == inspect_json(source) | {"file": None}


def test_utf8_bom_and_windows_1252(weblab_text: str, tmp_path: Path) -> None:
    bom = tmp_path / "bom.xmi"
    bom.write_bytes(b"\xef\xbb\xbf" + weblab_text.encode("utf-8"))
    assert read_model(str(bom)).diagnostics == []
    text = replace(weblab_text, 'encoding="UTF-8"', 'encoding="windows-1252"')
    text = replace(text, 'body="The user\'s computer."', 'body="The user\'s computer: 5 € “max”."')
    cp1252 = tmp_path / "cp1252.xmi"
    cp1252.write_bytes(text.encode("cp1252"))
    reading = read_model(str(cp1252))
    assert reading.diagnostics == []
    user_side = next(c for c in reading.uml.classifiers if c.name == "UserSide")
    assert user_side.comments == ["The user's computer: 5 € “max”."]
