"""The dialect rules on the documented forms of each tool, beyond the six real files: small files written
here in each form (UML 1.4 references and tag definitions, UML 1.3 attributes, XMI 2.1 ``ownedMember``,
a ``uml:Model`` root), the exporter's name found in each place a tool writes it, the never-silent
checks (R208, R209, R210) and the DOCTYPE policy."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from acordcs.model.reading import read_model
from acordcs.xmi.readers import read_uml
from tests.support.toolchain import codes_in, no_crash, run_main

UML14_ARGO = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.2" xmlns:UML="org.omg.xmi.namespace.UML">
 <XMI.header><XMI.documentation><XMI.exporter>ArgoUML (using Netbeans XMI Writer version 1.0)</XMI.exporter>
 <XMI.exporterVersion>0.34</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model xmi.id="m" name="argo">
   <UML:Namespace.ownedElement>
    <UML:Class xmi.id="c1" name="Camera">
     <UML:ModelElement.stereotype><UML:Stereotype xmi.idref="st1"/></UML:ModelElement.stereotype>
     <UML:ModelElement.taggedValue>
      <UML:TaggedValue xmi.id="tv1"><UML:TaggedValue.dataValue>5</UML:TaggedValue.dataValue>
       <UML:TaggedValue.type><UML:TagDefinition xmi.idref="td1"/></UML:TaggedValue.type>
      </UML:TaggedValue>
     </UML:ModelElement.taggedValue>
     <UML:Classifier.feature>
      <UML:Operation xmi.id="o1" name="grab">
       <UML:BehavioralFeature.parameter>
        <UML:Parameter xmi.id="p1" name="n" kind="in">
         <UML:Parameter.type><UML:DataType xmi.idref="int"/></UML:Parameter.type>
        </UML:Parameter>
       </UML:BehavioralFeature.parameter>
      </UML:Operation>
     </UML:Classifier.feature>
    </UML:Class>
    <UML:Class xmi.id="c2" name="Base"/>
    <UML:Generalization xmi.id="g1">
     <UML:Generalization.child><UML:Class xmi.idref="c1"/></UML:Generalization.child>
     <UML:Generalization.parent><UML:Class xmi.idref="c2"/></UML:Generalization.parent>
    </UML:Generalization>
    <UML:DataType xmi.id="int" name="int"/>
    <UML:Stereotype xmi.id="st1" name="CtxMonitor"/>
    <UML:TagDefinition xmi.id="td1" name="frequency"/>
   </UML:Namespace.ownedElement>
  </UML:Model>
 </XMI.content>
</XMI>
"""

UML13_UMBRELLO = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.2" xmlns:UML="http://schema.omg.org/spec/UML/1.3">
 <XMI.header><XMI.documentation><XMI.exporter>umbrello uml modeller http://umbrello.kde.org</XMI.exporter>
 <XMI.exporterVersion>2.11</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model xmi.id="m1" name="UML Model">
   <UML:Namespace.ownedElement>
    <UML:Stereotype xmi.id="folder" name="folder"/>
    <UML:Model stereotype="folder" xmi.id="Logical View" name="Logical View">
     <UML:Namespace.ownedElement>
      <UML:DataType xmi.id="dt" name="int"/>
      <UML:Class xmi.id="A" name="A">
       <UML:Classifier.feature>
        <UML:Attribute xmi.id="a1" name="x" type="dt"/>
       </UML:Classifier.feature>
      </UML:Class>
      <UML:Class xmi.id="B" name="B"/>
      <UML:Generalization xmi.id="g" child="A" parent="B"/>
      <UML:Dependency xmi.id="d" client="A" supplier="B"/>
     </UML:Namespace.ownedElement>
     <XMI.extension xmi.extender="umbrello"><diagrams><diagram xmi.id="A"/></diagrams></XMI.extension>
    </UML:Model>
   </UML:Namespace.ownedElement>
  </UML:Model>
 </XMI.content>
</XMI>
"""

XMI21_OWNED_MEMBER = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.0" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">
 <xmi:Documentation exporter="Visual Paradigm" exporterVersion="17.0"/>
 <uml:Model xmi:id="m" name="vp">
  <ownedMember xmi:type="uml:Package" xmi:id="p" name="pkg">
   <ownedMember xmi:type="uml:Class" xmi:id="c" name="Camera">
    <ownedOperation xmi:id="o" name="grab"/>
   </ownedMember>
  </ownedMember>
 </uml:Model>
</xmi:XMI>
"""

GENMYMODEL_ROOT = """<?xml version="1.0" encoding="UTF-8"?>
<uml:Model xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML" xmi:id="m" name="gmm">
 <eAnnotations xmi:id="e" source="genmymodel"><details xmi:id="d" key="exporterVersion" value="1.0"/></eAnnotations>
 <packagedElement xmi:type="uml:Class" xmi:id="c" name="Camera"/>
</uml:Model>
"""

# The same small UML 1.3 model in XMI 1.0 (long names, values as child elements, as the Novosoft UML
# library of early ArgoUML writes it) and in XMI 1.1 (Rose's unqualified form).
XMI10_LONG_NAMES = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.0">
 <XMI.header><XMI.documentation><XMI.exporter>Novosoft UML Library</XMI.exporter>
  <XMI.exporterVersion>0.4.19</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <Model_Management.Model xmi.id="m"><Foundation.Core.ModelElement.name>m</Foundation.Core.ModelElement.name>
   <Foundation.Core.Namespace.ownedElement>
    <Foundation.Core.Class xmi.id="c">
     <Foundation.Core.ModelElement.name>Camera</Foundation.Core.ModelElement.name>
     <Foundation.Core.ModelElement.visibility xmi.value="public"/>
     <Foundation.Core.ModelElement.stereotype><Foundation.Extension_Mechanisms.Stereotype xmi.idref="s"/></Foundation.Core.ModelElement.stereotype>
     <Foundation.Core.ModelElement.taggedValue>
      <Foundation.Extension_Mechanisms.TaggedValue xmi.id="tv">
       <Foundation.Extension_Mechanisms.TaggedValue.tag>frequency</Foundation.Extension_Mechanisms.TaggedValue.tag>
       <Foundation.Extension_Mechanisms.TaggedValue.value>5</Foundation.Extension_Mechanisms.TaggedValue.value>
      </Foundation.Extension_Mechanisms.TaggedValue>
     </Foundation.Core.ModelElement.taggedValue>
     <Foundation.Core.GeneralizableElement.generalization><Foundation.Core.Generalization xmi.idref="g"/></Foundation.Core.GeneralizableElement.generalization>
     <Foundation.Core.Classifier.feature>
      <Foundation.Core.Attribute xmi.id="a">
       <Foundation.Core.ModelElement.name>fps</Foundation.Core.ModelElement.name>
       <Foundation.Core.StructuralFeature.type><Foundation.Core.Classifier xmi.idref="d"/></Foundation.Core.StructuralFeature.type>
       <Foundation.Core.Attribute.initialValue><Foundation.Data_Types.Expression>
        <Foundation.Data_Types.Expression.body>12</Foundation.Data_Types.Expression.body>
       </Foundation.Data_Types.Expression></Foundation.Core.Attribute.initialValue>
      </Foundation.Core.Attribute>
      <Foundation.Core.Operation xmi.id="o">
       <Foundation.Core.ModelElement.name>grab</Foundation.Core.ModelElement.name>
       <Foundation.Core.BehavioralFeature.parameter>
        <Foundation.Core.Parameter xmi.id="p">
         <Foundation.Core.ModelElement.name>n</Foundation.Core.ModelElement.name>
         <Foundation.Core.Parameter.kind xmi.value="in"/>
         <Foundation.Core.Parameter.type><Foundation.Core.Classifier xmi.idref="d"/></Foundation.Core.Parameter.type>
        </Foundation.Core.Parameter>
       </Foundation.Core.BehavioralFeature.parameter>
      </Foundation.Core.Operation>
     </Foundation.Core.Classifier.feature>
    </Foundation.Core.Class>
    <Foundation.Core.Class xmi.id="b"><Foundation.Core.ModelElement.name>Device</Foundation.Core.ModelElement.name></Foundation.Core.Class>
    <Foundation.Core.DataType xmi.id="d"><Foundation.Core.ModelElement.name>int</Foundation.Core.ModelElement.name></Foundation.Core.DataType>
    <Foundation.Core.Generalization xmi.id="g">
     <Foundation.Core.Generalization.child><Foundation.Core.GeneralizableElement xmi.idref="c"/></Foundation.Core.Generalization.child>
     <Foundation.Core.Generalization.parent><Foundation.Core.GeneralizableElement xmi.idref="b"/></Foundation.Core.Generalization.parent>
    </Foundation.Core.Generalization>
    <Foundation.Core.Association xmi.id="as">
     <Foundation.Core.Association.connection>
      <Foundation.Core.AssociationEnd xmi.id="e1">
       <Foundation.Core.AssociationEnd.aggregation xmi.value="composite"/>
       <Foundation.Core.AssociationEnd.type><Foundation.Core.Classifier xmi.idref="b"/></Foundation.Core.AssociationEnd.type>
      </Foundation.Core.AssociationEnd>
      <Foundation.Core.AssociationEnd xmi.id="e2">
       <Foundation.Core.AssociationEnd.isNavigable xmi.value="false"/>
       <Foundation.Core.AssociationEnd.type><Foundation.Core.Classifier xmi.idref="c"/></Foundation.Core.AssociationEnd.type>
      </Foundation.Core.AssociationEnd>
     </Foundation.Core.Association.connection>
    </Foundation.Core.Association>
    <Foundation.Extension_Mechanisms.Stereotype xmi.id="s">
     <Foundation.Core.ModelElement.name>camera</Foundation.Core.ModelElement.name>
     <Foundation.Extension_Mechanisms.Stereotype.extendedElement><Foundation.Core.ModelElement xmi.idref="c"/></Foundation.Extension_Mechanisms.Stereotype.extendedElement>
    </Foundation.Extension_Mechanisms.Stereotype>
   </Foundation.Core.Namespace.ownedElement>
  </Model_Management.Model>
 </XMI.content>
</XMI>
"""
XMI11_SAME = """<?xml version="1.0"?>
<XMI xmi.version="1.1" xmlns:UML="href://org.omg/UML/1.3">
 <XMI.header><XMI.documentation><XMI.exporter>Novosoft UML Library</XMI.exporter>
  <XMI.exporterVersion>0.4.19</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <Model xmi.id="m" name="m"><Namespace.ownedElement>
   <Class xmi.id="c" name="Camera" visibility="public" stereotype="s">
    <ModelElement.taggedValue><TaggedValue xmi.id="tv" tag="frequency" value="5"/></ModelElement.taggedValue>
    <Classifier.feature>
     <Attribute xmi.id="a" name="fps" type="d"><Attribute.initialValue><Expression body="12"/></Attribute.initialValue></Attribute>
     <Operation xmi.id="o" name="grab"><BehavioralFeature.parameter><Parameter xmi.id="p" name="n" kind="in" type="d"/></BehavioralFeature.parameter></Operation>
    </Classifier.feature>
   </Class>
   <Class xmi.id="b" name="Device"/>
   <DataType xmi.id="d" name="int"/>
   <Generalization xmi.id="g" child="c" parent="b"/>
   <Association xmi.id="as"><Association.connection>
    <AssociationEnd xmi.id="e1" aggregation="composite" type="b"/>
    <AssociationEnd xmi.id="e2" isNavigable="false" type="c"/>
   </Association.connection></Association>
   <Stereotype xmi.id="s" name="camera"/>
  </Namespace.ownedElement></Model>
 </XMI.content>
</XMI>
"""
# Classes inside an element the reader does not know: read as none.
CLASSES_IN_AN_UNKNOWN_CONTAINER = """<?xml version="1.0"?>
<XMI xmi.version="1.2" xmlns:UML="org.omg.xmi.namespace.UML">
 <XMI.header><XMI.documentation><XMI.exporter>SomeTool</XMI.exporter></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model xmi.id="m" name="m"><UML:Namespace.ownedElement>
   <UML:Bundle xmi.id="b"><UML:Bundle.content>
    <UML:Class xmi.id="c" name=""/>
    <UML:Class xmi.id="c2" name="Lamp"/>
   </UML:Bundle.content></UML:Bundle>
  </UML:Namespace.ownedElement></UML:Model>
 </XMI.content>
</XMI>
"""

UNKNOWN_TOOL = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">
 <xmi:Documentation exporter="NoSuchModeller" exporterVersion="3.1"/>
 <uml:Model xmi:type="uml:Model" xmi:id="m" name="m">
  <packagedElement xmi:type="uml:Class" xmi:id="c" name="Camera"/>
 </uml:Model>
</xmi:XMI>
"""


def _codes(out: str) -> set[str]:
    """The codes ``validate`` printed, but T313 (these small files apply no ACORDCS stereotype)."""
    return codes_in(out) - {"T313"}


def _write(tmp_path: Path, text: str, name: str = "model.xmi") -> str:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return str(path)


def test_uml14_references_stereotypes_and_tag_definitions(tmp_path: Path) -> None:
    uml = read_uml(_write(tmp_path, UML14_ARGO))
    assert uml.dialect == "xmi1.2" and uml.tool == "argouml"
    camera = next(c for c in uml.classifiers if c.name == "Camera")
    assert [a.key for a in uml.applications_of("c1")] == ["CtxMonitor"]
    assert camera.tagged_values == {"frequency": "5"}
    assert camera.operations[0].parameters[0].type_name == "int"
    assert camera.generals == ["c2"]
    assert not uml.diagnostics, uml.diagnostics


def test_uml13_attribute_references_and_extension_ids(tmp_path: Path) -> None:
    uml = read_uml(_write(tmp_path, UML13_UMBRELLO))
    a = next(c for c in uml.classifiers if c.name == "A")
    assert a.attributes[0].type_name == "int"
    assert a.generals == ["B"]
    assert (uml.dependencies[0].clients, uml.dependencies[0].suppliers) == (["A"], ["B"])
    assert [app.key for app in uml.applications_of("Logical View")] == ["folder"]
    assert not uml.diagnostics, uml.diagnostics  # the diagram's xmi.id="A" is no duplicate


def test_xmi21_owned_member_form(tmp_path: Path) -> None:
    uml = read_uml(_write(tmp_path, XMI21_OWNED_MEMBER))
    assert uml.dialect == "omg-xmi2" and uml.exporter == "Visual Paradigm 17.0"
    assert [c.name for c in uml.classifiers] == ["Camera"]
    assert [p.name for p in uml.packages] == ["pkg"] and len(uml.classifiers[0].operations) == 1
    assert not uml.diagnostics


def test_model_as_root_with_exporter_in_eannotations(tmp_path: Path) -> None:
    uml = read_uml(_write(tmp_path, GENMYMODEL_ROOT))
    assert uml.dialect == "eclipse-uml2" and uml.tool == "genmymodel"
    assert uml.exporter == "genmymodel 1.0" and [c.name for c in uml.classifiers] == ["Camera"]


def _view(uml) -> dict:
    """What a reading holds, by name: classifiers with their features, relations, stereotypes."""
    names = {e.id: e.name for e in uml.elements.values()}
    return {
        "model": uml.name,
        "classifiers": sorted(
            (
                c.kind,
                c.name,
                tuple((a.name, a.type_name, a.default) for a in c.attributes),
                tuple(
                    (o.name, tuple((p.name, p.direction, p.type_name) for p in o.parameters))
                    for o in c.operations
                ),
                tuple(names[g] for g in c.generals),
                tuple(sorted(c.tagged_values.items())),
            )
            for c in uml.classifiers
        ),
        "associations": [
            [
                (names[e], uml.elements[e].aggregation, uml.elements[e].navigable)
                for e in a.member_ends
            ]
            for a in uml.associations
        ],
        "stereotypes": sorted((names[a.base], a.key) for a in uml.applications.values()),
    }


def test_xmi10_long_names_read_as_the_same_model_in_xmi11(tmp_path: Path) -> None:
    xmi10 = read_uml(_write(tmp_path, XMI10_LONG_NAMES))
    xmi11 = read_uml(_write(tmp_path, XMI11_SAME, "same11.xmi"))
    assert xmi10.dialect == "xmi1.0" and xmi10.tool == "argouml"
    assert _view(xmi10) == _view(xmi11)
    camera = next(c for c in xmi10.classifiers if c.name == "Camera")
    assert [(a.name, a.type_name, a.default) for a in camera.attributes] == [("fps", "int", "12")]
    assert camera.line == 8  # lines are the file's: the long names are renamed in place
    assert [d.code for d in xmi10.diagnostics] == []


def test_xmi10_validates_and_inspects_like_any_file(tmp_path: Path) -> None:
    path = _write(tmp_path, XMI10_LONG_NAMES)
    result = run_main(["validate", path])
    assert result.code == 0 and _codes(result.out) == set(), result.out
    data = json.loads(run_main(["inspect", "--format", "json", path]).out)
    assert (data["dialect"], data["classifiers"], data["attributes"], data["operations"]) == (
        "xmi1.0",
        {"Class": 2, "DataType": 1},
        1,
        1,
    )
    assert data["stereotype_applications"] == {"camera": 1} and data["exporter"].startswith("Novo")


def test_class_like_elements_read_as_none_is_an_error_naming_the_exporter(tmp_path: Path) -> None:
    path = _write(tmp_path, CLASSES_IN_AN_UNKNOWN_CONTAINER)
    result = run_main(["validate", path])
    no_crash(result)
    assert result.code == 1 and _codes(result.out) == {"R201", "R208"}, result.out
    line = next(ln for ln in result.out.splitlines() if ": R208 " in ln)
    assert "'SomeTool'" in line and "export" in line
    # the first class has an empty name: named by its id, never as ''
    assert "(the first: Class c (no name), element Class)" in line and "''" not in line
    assert line.startswith(f"{path}:7:")  # the first class


def test_inspect_refuses_what_validate_refuses(tmp_path: Path) -> None:
    path = _write(tmp_path, CLASSES_IN_AN_UNKNOWN_CONTAINER)
    result = run_main(["inspect", path])
    no_crash(result)
    assert result.code == 1 and result.out == "", result.both
    assert ": R208 " in result.err and "Class c (no name)" in result.err


def test_unknown_exporter_read_cleanly_is_an_info(tmp_path: Path) -> None:
    path = _write(tmp_path, UNKNOWN_TOOL)
    result = run_main(["validate", path])
    assert result.code == 0 and _codes(result.out) == {"R209"}, result.out
    assert "'NoSuchModeller 3.1'" in result.out


def test_unknown_exporter_with_errors_is_a_warning(tmp_path: Path) -> None:
    text = UNKNOWN_TOOL.replace(
        'name="Camera"/>',
        'name="Camera"><generalization xmi:id="g" general="nope"/></packagedElement>',
    )
    result = run_main(["validate", _write(tmp_path, text)])
    assert _codes(result.out) == {"R202", "R210"}, result.out


# ------------------------------------------------------------------------------------- DOCTYPE
MINIMAL_XMI11 = """<XMI xmi.version="1.1" xmlns:UML="href://org.omg/UML/1.3">
<XMI.header><XMI.documentation><XMI.exporter>Unisys.JCR.1</XMI.exporter></XMI.documentation></XMI.header>
<XMI.content><Model xmi.id="G.0" name="m"><Namespace.ownedElement>
<Class xmi.id="c" name="&#67;amera"/></Namespace.ownedElement></Model></XMI.content></XMI>
"""


@pytest.mark.parametrize(
    "doctype",
    [
        "<!DOCTYPE XMI SYSTEM '{dtd}'>",
        '<!DOCTYPE XMI PUBLIC "-//OMG//XMI 1.1//EN" "{dtd}">',
        "<!-- <!DOCTYPE XMI SYSTEM 'UML1311.dtd' [<!ENTITY e 'x'>]> -->",
    ],
    ids=["system", "public", "commented-out"],
)
def test_external_doctype_alone_is_accepted_and_never_loaded(doctype: str, tmp_path: Path) -> None:
    dtd = tmp_path / "UML13.dtd"
    # Were the DTD read, its default attribute would rename the class and its entity would be known.
    dtd.write_text(
        '<!ATTLIST Class name CDATA "LOADED"><!ENTITY canary "LOADED">', encoding="utf-8"
    )
    text = (
        f"<?xml version='1.0' encoding='ISO-8859-1'?>\n{doctype.format(dtd=dtd)}\n{MINIMAL_XMI11}"
    )
    result = run_main(["inspect", "--format", "json", _write(tmp_path, text)])
    no_crash(result)
    assert result.code == 0, result.both
    data = json.loads(result.out)
    assert data["classifiers"] == {"Class": 1} and "LOADED" not in result.out


@pytest.mark.parametrize(
    "doctype",
    [
        "<!DOCTYPE XMI SYSTEM 'UML13.dtd' [<!ENTITY e 'x'>]>",
        "<!DOCTYPE XMI [<!ATTLIST Class name CDATA 'x'>]>",
        "<!DOCTYPE XMI SYSTEM 'a.dtd'>\n<!DOCTYPE XMI [<!ENTITY e 'x'>]>",
        "<!DOCTYPE XMI>",
    ],
    ids=["external-and-subset", "subset-only", "second-declaration", "no-identifier"],
)
def test_internal_subset_stays_refused(doctype: str, tmp_path: Path) -> None:
    text = f"<?xml version='1.0'?>\n{doctype}\n{MINIMAL_XMI11}"
    result = run_main(["validate", _write(tmp_path, text)])
    no_crash(result)
    assert result.code == 2 and codes_in(result.out) == {"X102"}, result.out


def test_external_doctype_in_utf16_is_accepted(tmp_path: Path) -> None:
    """The byte scan cannot read UTF-16: libxml2's view of the declaration decides."""
    text = f"<?xml version='1.0' encoding='UTF-16'?>\n<!DOCTYPE XMI SYSTEM 'UML13.dtd'>\n{MINIMAL_XMI11}"
    path = tmp_path / "utf16.xmi"
    path.write_bytes(text.encode("utf-16"))
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 0, result.out
    path.write_bytes(
        text.replace("'UML13.dtd'>", "'UML13.dtd' [<!ENTITY e 'x'>]>").encode("utf-16")
    )
    assert run_main(["validate", str(path)]).code == 2


def test_the_named_dtd_is_never_opened(tmp_path: Path) -> None:
    """libxml2 tries to open a DTD an external identifier names even with ``load_dtd=False``: the
    parser's resolver must answer first. The DTD here is a FIFO nobody writes to: opening it for
    reading would block, and the read below would time out."""
    fifo = tmp_path / "UML13.dtd"
    os.mkfifo(fifo)
    model = tmp_path / "model.xmi"
    model.write_text(f"<?xml version='1.0'?>\n<!DOCTYPE XMI SYSTEM '{fifo}'>\n{MINIMAL_XMI11}")
    code = (
        "import sys; from acordcs.xmi.readers import read_uml; "
        f"uml = read_uml({str(model)!r}); sys.exit(len(uml.diagnostics))"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run([sys.executable, "-c", code], env=env, timeout=60, check=False)
    assert proc.returncode == 0


EA_XMI11 = """<?xml version="1.0" encoding="windows-1252"?>
<XMI xmi.version="1.1" xmlns:UML="omg.org/UML1.3" timestamp="2009-03-02 10:00:00">
 <XMI.header><XMI.documentation><XMI.exporter>Enterprise Architect</XMI.exporter>
 <XMI.exporterVersion>2.5</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model name="EA Model" xmi.id="MX_EAID_1">
   <UML:Namespace.ownedElement>
    <UML:Class name="EARootClass" xmi.id="EAID_11111111_5487_4080_A7F4_41526CB0AA00" isRoot="true"/>
    <UML:Package name="lab" xmi.id="EAPK_1" visibility="public">
     <UML:Namespace.ownedElement>
      <UML:Class name="Light" xmi.id="EAID_2" visibility="public" namespace="EAPK_1">
       <UML:ModelElement.stereotype><UML:Stereotype name="CtxMonitor"/></UML:ModelElement.stereotype>
       <UML:ModelElement.taggedValue>
        <UML:TaggedValue tag="isSpecification" value="false"/>
        <UML:TaggedValue tag="ea_stype" value="Class"/>
        <UML:TaggedValue tag="ea_localid" value="3"/>
        <UML:TaggedValue tag="date_created" value="2009-03-02 10:00:00"/>
        <UML:TaggedValue tag="stereotype" value="CtxMonitor"/>
        <UML:TaggedValue tag="frequency" value="2"/>
        <UML:TaggedValue tag="$ea_xref_property" value="$XREFPROP=$XID={A1}$XID;$NAM=Stereotypes$NAM;$TYP=element property$TYP;$VIS=Public$VIS;$PAR=0$PAR;$DES=@STEREO;Name=CtxMonitor;GUID={B2};FQName=ACORDCS::CtxMonitor;@ENDSTEREO;$DES;$CLT={C3}$CLT;$SUP=&lt;none&gt;$SUP;$ENDXREF;"/>
       </UML:ModelElement.taggedValue>
      </UML:Class>
     </UML:Namespace.ownedElement>
    </UML:Package>
   </UML:Namespace.ownedElement>
  </UML:Model>
 </XMI.content>
</XMI>
"""


def test_enterprise_architect_xmi11_profile_stereotypes_from_the_xref(tmp_path: Path) -> None:
    path = tmp_path / "ea11.xmi"
    path.write_bytes(EA_XMI11.encode("cp1252"))
    reading = read_model(str(path))
    assert reading.uml.dialect == "xmi1.1" and reading.uml.tool == "enterprise-architect"
    assert [a.key for a in reading.uml.applications.values()] == ["ACORDCS:CtxMonitor"]
    light = next(r for r in reading.architecture.roles.values() if r.name == "Light")
    assert light.kind == "CtxMonitor" and light.tag("frequency") == "2"
    codes = {d.code for d in reading.diagnostics}
    assert "T303" not in codes and "R206" not in codes, reading.diagnostics


def test_exporter_in_a_comment_and_in_child_elements(tmp_path: Path) -> None:
    """BOUML's option writes xmi:Documentation inside a comment; MagicDraw writes child elements."""
    commented = UNKNOWN_TOOL.replace(
        '<xmi:Documentation exporter="NoSuchModeller" exporterVersion="3.1"/>',
        '<!-- <xmi:Documentation exporter="Bouml" exporterVersion="1.15.1"/> -->',
    )
    uml = read_uml(_write(tmp_path, commented, "commented.xmi"))
    assert (uml.exporter, uml.tool, uml.dialect) == ("Bouml 1.15.1", "bouml", "bouml-xmi2")
    assert not uml.diagnostics
    children = UNKNOWN_TOOL.replace(
        '<xmi:Documentation exporter="NoSuchModeller" exporterVersion="3.1"/>',
        "<xmi:Documentation><xmi:exporter>Cameo Systems Modeler</xmi:exporter>"
        "<xmi:exporterVersion>2022x</xmi:exporterVersion></xmi:Documentation>",
    )
    uml = read_uml(_write(tmp_path, children, "children.xmi"))
    assert (uml.exporter, uml.tool, uml.dialect) == (
        "Cameo Systems Modeler 2022x",
        "magicdraw",
        "omg-xmi2",
    )


def test_no_exporter_named_is_an_info_unless_eclipse(tmp_path: Path) -> None:
    bare = UNKNOWN_TOOL.replace(
        '<xmi:Documentation exporter="NoSuchModeller" exporterVersion="3.1"/>', ""
    )
    uml = read_uml(_write(tmp_path, bare, "bare.xmi"))
    assert [d.code for d in uml.diagnostics] == ["R209"]
    assert "names itself nowhere" in uml.diagnostics[0].message
    papyrus = GENMYMODEL_ROOT.replace(
        '<eAnnotations xmi:id="e" source="genmymodel"><details xmi:id="d" key="exporterVersion" value="1.0"/></eAnnotations>',
        "",
    )
    uml = read_uml(_write(tmp_path, papyrus, "papyrus.uml"))
    assert uml.exporter is None and not uml.diagnostics
