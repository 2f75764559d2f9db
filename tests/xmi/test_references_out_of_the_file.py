"""A reference to an id the file does not hold (R202) is a warning when no ACORD-CS element makes
it or is joined by it (a package exported alone names what it left out: a UML Dependency whose
supplier is in another file); it is an error when ACORD-CS reads it (a container's deployment of a
component that is not there, an attribute of a component typed by a missing class): what the
application is made of is then incomplete. Each says which, with file:line:col and the element."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from tests.support.toolchain import codes_in, no_crash, run_main

HEAD = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" xmlns:ACORDCS="http:///schemas/ACORDCS/1">
 <xmi:Documentation exporter="Bouml" exporterVersion="5.1"/>
 <uml:Model xmi:type="uml:Model" xmi:id="themodel" name="Home">
"""
# A home's container and heater, and two classes of the user's that ACORD-CS does not read.
CLASSES = """  <packagedElement xmi:type="uml:Class" xmi:id="home" name="House"/>
  <packagedElement xmi:type="uml:Class" xmi:id="heater" name="Heater">
   <ownedAttribute xmi:type="uml:Property" xmi:id="power" name="power">
    <type xmi:type="uml:PrimitiveType" href="http://schema.omg.org/spec/UML/2.1/uml.xml#Integer"/>
   </ownedAttribute>
  </packagedElement>
  <packagedElement xmi:type="uml:Dependency" xmi:id="d1" client="home" supplier="heater"/>
  <packagedElement xmi:type="uml:Class" xmi:id="invoice" name="Invoice"/>
"""
TAIL = """ </uml:Model>
 <ACORDCS:CtxContainer xmi:id="s1" base_Class="home"/>
 <ACORDCS:CtxComponent xmi:id="s2" base_Class="heater"/>
</xmi:XMI>
"""

# a dependency of the user's class on an element of another file (the package's own export)
FOREIGN_SUPPLIER = '  <packagedElement xmi:type="uml:Dependency" xmi:id="d2" name="billing" client="invoice" supplier="BOUML_0x2a1_4"/>\n'
# the same from the container: the deployment of something not in the file
FOREIGN_DEPLOYMENT = '  <packagedElement xmi:type="uml:Dependency" xmi:id="d3" name="hostsMeter" client="home" supplier="BOUML_0x2a1_4"/>\n'
# the user's class generalising a class of another file
FOREIGN_GENERAL = '  <packagedElement xmi:type="uml:Class" xmi:id="bill" name="Bill"><generalization xmi:type="uml:Generalization" xmi:id="g1" general="BOUML_0x2a2_4"/></packagedElement>\n'
# the component's attribute typed by a class of another file
FOREIGN_TYPE = (
    'power">\n    <type xmi:type="uml:PrimitiveType" href="http://schema.omg.org/spec/UML/2.1/uml.xml#Integer"/>',
    'power">\n    <type xmi:type="uml:Class" xmi:idref="BOUML_0x2a3_4"/>',
)


def _validate(tmp_path: Path, extra: str = "", name: str = "home.xmi", classes: str = CLASSES):
    path = tmp_path / name
    path.write_text(HEAD + classes + extra + TAIL, encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    return path, result


def _r202(out: str) -> list[str]:
    return [line for line in out.splitlines() if ": R202 " in line]


@pytest.mark.parametrize(
    ("extra", "what", "element", "xmi_id"),
    [
        (FOREIGN_SUPPLIER, "Dependency 'billing'", "billing", "BOUML_0x2a1_4"),
        (FOREIGN_GENERAL, "generalization of 'Bill'", "Bill", "BOUML_0x2a2_4"),
    ],
    ids=["dependency-supplier", "generalization"],
)
def test_a_reference_out_of_the_file_on_a_plain_element_is_a_warning(
    tmp_path: Path, extra: str, what: str, element: str, xmi_id: str
) -> None:
    path, result = _validate(tmp_path, extra)
    assert result.code == 0 and codes_in(result.out) == {"R202"}, result.out
    (line,) = _r202(result.out)
    assert re.match(rf"{re.escape(str(path))}:\d+:1: warning: R202 {what} refers to id ", line)
    assert (
        f"'{xmi_id}', which is not in this file (an element of another file, or one deleted); it "
        "touches no ACORD-CS element, so the reference is only left out: export the whole model, "
        "or restore the element, if it matters"
    ) in line
    assert line.endswith(f"[{element} ({xmi_id})]"), line


def test_a_reference_out_of_the_file_acordcs_reads_is_an_error(tmp_path: Path) -> None:
    path, result = _validate(tmp_path, FOREIGN_DEPLOYMENT)
    assert result.code == 1, result.out
    (line,) = _r202(result.out)
    assert (
        f"{path}:13:1: error: R202 Dependency 'hostsMeter' refers to id 'BOUML_0x2a1_4', which no "
        "element of the file has, and <<CtxContainer>> 'House' needs it (ACORD-CS reads this "
        "reference): restore the element, or export the whole model [hostsMeter (BOUML_0x2a1_4)]"
    ) == line


def test_a_component_s_attribute_typed_by_a_missing_class_is_an_error(tmp_path: Path) -> None:
    old, new = FOREIGN_TYPE
    assert CLASSES.count(old) == 1
    _, result = _validate(tmp_path, classes=CLASSES.replace(old, new))
    assert result.code == 1, result.out
    (line,) = _r202(result.out)
    assert ": error: R202 type of 'power' refers to id 'BOUML_0x2a3_4'" in line
    assert "<<CtxComponent>> 'Heater' needs it" in line and line.endswith(
        "[Heater::power (BOUML_0x2a3_4)]"
    )


def test_xmi_1_x_references_follow_the_same_rule(tmp_path: Path) -> None:
    text = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.2" xmlns:UML="org.omg.xmi.namespace.UML">
<XMI.header><XMI.documentation><XMI.exporter>Bouml</XMI.exporter>
<XMI.exporterVersion>1.4.6</XMI.exporterVersion></XMI.documentation></XMI.header>
<XMI.content>
 <UML:Model name="old" xmi.id="M1"><UML:Namespace.ownedElement>
  <UML:Class name="Hub" xmi.id="C1">
   <UML:ModelElement.stereotype><UML:Stereotype name="CtxContainer"/></UML:ModelElement.stereotype>
  </UML:Class>
  <UML:Class name="Invoice" xmi.id="C2"/>
  <UML:Dependency xmi.id="D1" client="C2" supplier="elsewhere"/>
  <UML:Dependency xmi.id="D2" client="C1" supplier="gone"/>
 </UML:Namespace.ownedElement></UML:Model>
</XMI.content>
</XMI>
"""
    path = tmp_path / "old.xmi"
    path.write_text(text, encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    plain, deployed = sorted(_r202(result.out), key=lambda ln: "gone" in ln)
    assert ": warning: R202 dependency refers to id 'elsewhere'" in plain
    assert ": error: R202 dependency refers to id 'gone'" in deployed
    assert "<<CtxContainer>> 'Hub' needs it" in deployed


def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch) -> None:
    """docs/diagnostics.md's R202 examples are this output."""
    page = (Path(__file__).parents[2] / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = page.split("{#r202}", 1)[1].split("\n### ", 1)[0]
    shown = re.findall(r"^home\.xmi:.*$", section, flags=re.M)
    assert len(shown) == 2, shown
    monkeypatch.chdir(tmp_path)
    Path("home.xmi").write_text(
        HEAD + CLASSES + FOREIGN_SUPPLIER + FOREIGN_DEPLOYMENT + TAIL, encoding="utf-8"
    )
    assert shown == _r202(run_main(["validate", "home.xmi"]).out)
