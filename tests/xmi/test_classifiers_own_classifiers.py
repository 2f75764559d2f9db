"""What a classifier owns in UML 2.5 is read wherever it is nested: use cases owned by a class
(``ownedUseCase``, as Papyrus writes a SysML 1.6 model's), behaviours (``ownedBehavior``), nested
classifiers, a node's nodes, and a class's ports written apart (``ownedPort``, Enterprise Architect)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from lxml import etree

from tests.support.toolchain import no_crash, run_main

# A Papyrus model in the form of the SysML 1.6 export of issue 23: six use cases owned by a block,
# each with a generalization and an activity, and one use case in the package.
PAPYRUS_OWNED_USE_CASES = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="20131001" xmlns:xmi="http://www.omg.org/spec/XMI/20131001" xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML">
 <uml:Model xmi:id="m" name="Drone">
  <packagedElement xmi:type="uml:UseCase" xmi:id="fly" name="Fly"/>
  <packagedElement xmi:type="uml:Class" xmi:id="drone" name="DroneSystem">
{use_cases}
   <nestedClassifier xmi:type="uml:Class" xmi:id="battery" name="Battery">
    <ownedUseCase xmi:id="charge" name="Charge"/>
   </nestedClassifier>
  </packagedElement>
  <packagedElement xmi:type="uml:Node" xmi:id="n" name="Board">
   <nestedNode xmi:id="n2" name="Cpu"/>
  </packagedElement>
 </uml:Model>
</xmi:XMI>
"""
USE_CASE = """   <ownedUseCase xmi:id="uc{n}" name="Mission{n}">
    <generalization xmi:id="g{n}" general="fly"/>
    <ownedBehavior xmi:type="uml:Activity" xmi:id="act{n}" name="Mission{n}Flow"/>
   </ownedUseCase>"""


def _model(tmp_path: Path) -> Path:
    text = PAPYRUS_OWNED_USE_CASES.format(
        use_cases="\n".join(USE_CASE.format(n=n) for n in range(1, 6))
    )
    path = tmp_path / "drone.uml"
    path.write_text(text, encoding="utf-8")
    return path


def test_use_cases_owned_by_classes_are_read_with_what_they_own(tmp_path: Path) -> None:
    path = _model(tmp_path)
    result = run_main(["inspect", "--format", "json", str(path)])
    no_crash(result)
    data = json.loads(result.out)
    root = etree.parse(str(path)).getroot()
    assert data["classifiers"]["UseCase"] == 7 == len(root.xpath("//ownedUseCase")) + 1
    assert data["classifiers"]["Activity"] == 5 and data["generalizations"] == 5
    assert data["classifiers"]["Class"] == 2 and data["classifiers"]["Node"] == 2
    validated = run_main(["validate", str(path)])
    assert validated.code == 0 and ": R2" not in validated.out, validated.out


def test_owned_use_cases_know_their_owner(tmp_path: Path) -> None:
    from acordcs.xmi.readers import read_uml

    uml = read_uml(str(_model(tmp_path)))
    charge = next(c for c in uml.classifiers if c.name == "Charge")
    assert charge.qualified_name() == "DroneSystem::Battery::Charge"
    mission = next(c for c in uml.classifiers if c.name == "Mission3")
    assert mission.generals == ["fly"] and [c.name for c in mission.nested] == ["Mission3Flow"]


@pytest.mark.parametrize(
    ("exporter", "port"),
    [
        # Enterprise Architect writes a class's ports apart from its attributes
        ("Enterprise Architect", '<ownedPort xmi:type="uml:Port" xmi:id="p" name="power"/>'),
        # as Papyrus, BOUML and MagicDraw write them: owned attributes of type uml:Port
        ("Bouml", '<ownedAttribute xmi:type="uml:Port" xmi:id="p" name="power"/>'),
        # an ownedPort is a port whatever its xmi:type says
        ("Enterprise Architect", '<ownedPort xmi:id="p" name="power"/>'),
    ],
)
def test_ports_are_read_as_ports_never_as_attributes(
    tmp_path: Path, exporter: str, port: str
) -> None:
    text = f"""<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">
 <xmi:Documentation exporter="{exporter}" exporterVersion="6.5"/>
 <uml:Model xmi:type="uml:Model" name="EA_Model">
  <packagedElement xmi:type="uml:Class" xmi:id="c" name="Lamp">
   <ownedAttribute xmi:type="uml:Property" xmi:id="a" name="level"/>
   {port}
  </packagedElement>
 </uml:Model>
</xmi:XMI>
"""
    path = tmp_path / "ea.xmi"
    path.write_text(text, encoding="utf-8")
    from acordcs.xmi.readers import read_uml

    uml = read_uml(str(path))
    (lamp,) = uml.classifiers
    assert [(a.name, a.kind) for a in lamp.attributes] == [("level", "Property")]
    assert [(p.name, p.kind, p.owner) for p in lamp.ports] == [("power", "Port", lamp)]
    assert uml.elements["p"] is lamp.ports[0]
    assert (uml.counts()["attributes"], uml.counts()["ports"]) == (1, 1)
    assert not uml.diagnostics
