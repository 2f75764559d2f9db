"""What a reader does not read is said once per type (R211, an info), never as an error in the user's
model; a type that is not UML at all is R201, a warning naming what was skipped, and an error only
when the element holds or relates an ACORD-CS element (it is then lost to ACORD-CS).

The files are small, in the forms the tools write (issue 23 lists the real exports they come from):
BOUML 1.13's sequence-diagram events (``uml:ExecutionEvent``, ``uml:SendOperationEvent``: UML 2.0 to
2.3 metaclasses), ArgoUML's actions (``UML:DestroyAction``, ...: UML 1.4), Enterprise Architect's
``UML:DiagramElement`` (Diagram Interchange), Visual Paradigm's ``uml:TaggedValue`` (UML 1.x) and its
own ``activitySwimlane2``.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from acordcs.xmi.readers import read_uml
from acordcs.xmi.readers.skipped import metamodel_of, uml_metaclasses
from tests.support.toolchain import codes_in, no_crash, run_main


def _xmi2(exporter: str, members: str) -> str:
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">
 <xmi:Documentation exporter="{exporter}" exporterVersion="1.13"/>
 <uml:Model xmi:type="uml:Model" xmi:id="themodel" name="m">
  <packagedElement xmi:type="uml:Class" xmi:id="c1" name="Camera"/>
{members}
 </uml:Model>
</xmi:XMI>
"""


BOUML_EVENTS = _xmi2(
    "Bouml",
    """  <packagedElement xmi:type="uml:ExecutionEvent" xmi:id="ev1" name="ExecutionEvent0"/>
  <packagedElement xmi:type="uml:SendOperationEvent" xmi:id="ev2" name="SendOperationEvent0"/>
  <packagedElement xmi:type="uml:ExecutionEvent" xmi:id="ev3" name="ExecutionEvent1"/>""",
)

ARGO_ACTIONS = """<?xml version="1.0" encoding="UTF-8"?>
<XMI xmi.version="1.2" xmlns:UML="org.omg.xmi.namespace.UML">
 <XMI.header><XMI.documentation><XMI.exporter>ArgoUML (using Netbeans XMI Writer version 1.0)</XMI.exporter>
 <XMI.exporterVersion>0.34</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model xmi.id="m" name="m"><UML:Namespace.ownedElement>
   <UML:Class xmi.id="c1" name="Camera"/>
   <UML:DestroyAction xmi.id="a1" name=""/>
   <UML:CreateAction xmi.id="a2" name=""/>
   <UML:ReturnAction xmi.id="a3" name=""/>
   <UML:CreateAction xmi.id="a4" name=""/>
  </UML:Namespace.ownedElement></UML:Model>
 </XMI.content>
</XMI>
"""

EA_DIAGRAM_ELEMENTS = """<?xml version="1.0" encoding="windows-1252"?>
<XMI xmi.version="1.1" xmlns:UML="omg.org/UML1.3">
 <XMI.header><XMI.documentation><XMI.exporter>Enterprise Architect</XMI.exporter>
 <XMI.exporterVersion>2.5</XMI.exporterVersion></XMI.documentation></XMI.header>
 <XMI.content>
  <UML:Model name="EA Model" xmi.id="MX_EAID_1"><UML:Namespace.ownedElement>
   <UML:Class name="Camera" xmi.id="EAID_2"/>
   <UML:DiagramElement geometry="Left=586;Top=50;Right=676;Bottom=405;" subject="EAID_2" seqno="1"/>
  </UML:Namespace.ownedElement></UML:Model>
 </XMI.content>
</XMI>
"""

VP_OWN_TYPES = _xmi2(
    "Visual Paradigm",
    """  <packagedElement xmi:type="uml:TaggedValue" xmi:id="tv1" name="author"/>
  <ownedMember xmi:type="uml:activitySwimlane2" xmi:id="sw1" name="Lanes"/>""",
)

ACORDCS_NS = 'xmlns:ACORDCS="http:///schemas/ACORDCS/1"'


def _with_acordcs(members: str, applications: str) -> str:
    text = _xmi2("Bouml", members).replace("<xmi:XMI ", f"<xmi:XMI {ACORDCS_NS} ", 1)
    return text.replace("</xmi:XMI>", f"{applications}\n</xmi:XMI>")


MISSPELT_CLASS = _xmi2("Bouml", '  <packagedElement xmi:type="uml:Clas" xmi:id="c2" name="Lamp"/>')
# The same class as a component: what ACORD-CS reads of it is lost (docs/diagnostics.md, R201)
MISSPELT_COMPONENT = _with_acordcs(
    '  <packagedElement xmi:type="uml:Clas" xmi:id="c2" name="Lamp"/>',
    ' <ACORDCS:CtxComponent xmi:id="s2" base_Class="c2"/>',
)


def _notes(out: str) -> list[str]:
    return [line for line in out.splitlines() if ": R211 " in line]


def _validate(tmp_path: Path, text: str, encoding: str = "utf-8") -> tuple[int, str]:
    path = tmp_path / "model.xmi"
    path.write_bytes(text.encode(encoding))
    result = run_main(["validate", str(path)])
    no_crash(result)
    return result.code, result.out


def test_uml2_events_of_older_uml_versions_are_an_info_per_metaclass(tmp_path: Path) -> None:
    code, out = _validate(tmp_path, BOUML_EVENTS)
    assert code == 0 and codes_in(out) == {"R211", "T313"}, out
    execution, send = _notes(out)
    # once per metaclass, with the count and the first element's line and id
    assert execution.endswith(
        "model.xmi:6:1: info: R211 2 uml:ExecutionEvent elements skipped, the first at this line: "
        "a UML 2.0-2.3 metaclass this reader does not read; what they hold is not checked [(ev1)]"
    )
    assert ":7:1: info: R211 1 uml:SendOperationEvent element skipped: a UML 2.0-2.3" in send
    assert "did you mean" not in out


def test_uml14_actions_of_argouml_are_an_info_per_metaclass(tmp_path: Path) -> None:
    code, out = _validate(tmp_path, ARGO_ACTIONS)
    assert code == 0 and codes_in(out) == {"R211", "T313"}, out
    notes = _notes(out)
    assert [re.search(r"R211 (\d+ UML:\w+)", n).group(1) for n in notes] == [
        "1 UML:DestroyAction",
        "2 UML:CreateAction",
        "1 UML:ReturnAction",
    ]
    assert all("a UML 1.4 metaclass" in n for n in notes) and "did you mean" not in out


def test_diagram_interchange_elements_in_the_uml_namespace_are_an_info(tmp_path: Path) -> None:
    code, out = _validate(tmp_path, EA_DIAGRAM_ELEMENTS, "cp1252")
    assert code == 0 and codes_in(out) == {"R211", "T313"}, out
    (note,) = _notes(out)
    assert "1 UML:DiagramElement element skipped: a Diagram Interchange 1.0 metaclass" in note


def test_a_known_tools_own_types_are_an_info_and_a_uml1_name_in_xmi2_too(tmp_path: Path) -> None:
    code, out = _validate(tmp_path, VP_OWN_TYPES)
    assert code == 0 and codes_in(out) == {"R211", "T313"}, out
    tagged, lanes = _notes(out)
    assert "1 uml:TaggedValue element skipped: a UML 1.4 metaclass" in tagged
    assert "no UML version defines it (the exporting tool's own type)" in lanes
    assert "did you mean" not in out  # activitySwimlane2 resembles no metaclass


def test_the_same_type_from_an_unknown_tool_is_a_warning_naming_it(tmp_path: Path) -> None:
    code, out = _validate(tmp_path, VP_OWN_TYPES.replace("Visual Paradigm", "NoSuchModeller"))
    assert code == 0 and {"R201", "R211", "R210"} <= codes_in(out), out
    assert (
        "model.xmi:7:1: warning: R201 unknown xmi:type uml:activitySwimlane2 on 'Lanes'; the "
        "element is skipped: it holds no ACORD-CS element and relates none, so nothing ACORD-CS "
        "reads is lost: correct the type if it matters to you [Lanes (sw1)]"
    ) in out
    assert ": R211 1 uml:TaggedValue element skipped" in out  # UML all the same
    # what was skipped makes the unknown exporter's reading doubtful: a warning, not R209's info
    assert ": warning: R210 exporter 'NoSuchModeller 1.13'" in out


@pytest.mark.parametrize("exporter", ["Bouml", "Visual Paradigm", "NoSuchModeller"])
def test_a_misspelt_metaclass_is_named_whoever_wrote_it(tmp_path: Path, exporter: str) -> None:
    text = _xmi2(exporter, '  <packagedElement xmi:type="uml:Clas" xmi:id="c2" name="Lamp"/>')
    code, out = _validate(tmp_path, text)
    assert code == 0, out
    assert ": warning: R201 unknown xmi:type uml:Clas (did you mean uml:Class?) on 'Lamp'" in out
    assert not _notes(out)


def test_several_of_one_unknown_type_are_one_warning(tmp_path: Path) -> None:
    """An exporter's lowercase ``uml:collaborationOccurrence``, three times: one warning with the
    count and the first, the closest metaclass suggested."""
    members = "\n".join(
        f'  <packagedElement xmi:type="uml:collaborationOccurrence" xmi:id="o{n}" name="Use{n}"/>'
        for n in range(3)
    )
    code, out = _validate(tmp_path, _xmi2("Bouml", members))
    assert code == 0, out
    (line,) = [ln for ln in out.splitlines() if ": R201 " in ln]
    assert line.endswith(
        "model.xmi:6:1: warning: R201 unknown xmi:type uml:collaborationOccurrence (did you mean "
        "uml:CollaborationOccurrence?); 3 elements skipped, the first ('Use0') at this line: they "
        "hold no ACORD-CS element and relate none, so nothing ACORD-CS reads is lost: correct the "
        "type if it matters to you [Use0 (o0)]"
    ), line


def test_uml14_association_links_of_an_unknown_writer_are_a_warning(tmp_path: Path) -> None:
    """UML 1.4's metamodel associations written as elements (``UML:A_context_raisedSignal``, as
    the NetBeans MDR writer does) by a tool the reader does not know."""
    text = ARGO_ACTIONS.replace(
        "ArgoUML (using Netbeans XMI Writer version 1.0)", "Netbeans XMI Writer"
    )
    text = text.replace(
        '<UML:DestroyAction xmi.id="a1" name=""/>',
        '<UML:A_context_raisedSignal><UML:Signal xmi.idref="c1"/></UML:A_context_raisedSignal>',
    )
    code, out = _validate(tmp_path, text)
    assert code == 0, out
    (line,) = [ln for ln in out.splitlines() if ": R201 " in ln]
    assert (
        ": warning: R201 unknown element UML:A_context_raisedSignal (a UML 1.4 metamodel " in line
    )
    assert "nothing ACORD-CS reads is lost" in line


@pytest.mark.parametrize(
    ("members", "applications", "said"),
    [
        (  # the misspelt element has a stereotype
            '  <packagedElement xmi:type="uml:Clas" xmi:id="c2" name="Lamp"/>',
            ' <ACORDCS:CtxComponent xmi:id="s2" base_Class="c2"/>',
            "unknown xmi:type uml:Clas (did you mean uml:Class?) on 'Lamp'; the element is skipped, "
            "and it holds <<CtxComponent>> 'Lamp', which ACORD-CS reads",
        ),
        (  # an element inside it has one
            '  <packagedElement xmi:type="uml:Pakage" xmi:id="p2" name="Devices">\n'
            '   <packagedElement xmi:type="uml:Class" xmi:id="c2" name="Lamp"/>\n'
            "  </packagedElement>",
            ' <ACORDCS:CtxComponent xmi:id="s2" base_Class="c2"/>',
            "unknown xmi:type uml:Pakage (did you mean uml:Package?) on 'Devices'; the element is "
            "skipped, and it holds <<CtxComponent>> 'Lamp', which ACORD-CS reads",
        ),
        (  # it relates two ACORD-CS elements: a misspelt dependency (a deployment)
            '  <packagedElement xmi:type="uml:Class" xmi:id="c2" name="Lamp"/>\n'
            '  <packagedElement xmi:type="uml:Dependancy" xmi:id="d1" client="c1" supplier="c2"/>',
            ' <ACORDCS:CtxContainer xmi:id="s1" base_Class="c1"/>\n'
            ' <ACORDCS:CtxComponent xmi:id="s2" base_Class="c2"/>',
            "unknown xmi:type uml:Dependancy (did you mean uml:Dependency?); the element is "
            "skipped, and it relates <<CtxContainer>> 'Camera' and <<CtxComponent>> 'Lamp', which "
            "ACORD-CS reads",
        ),
    ],
    ids=["stereotyped", "holds-a-stereotyped-element", "relates-stereotyped-elements"],
)
def test_an_unknown_type_touching_acordcs_is_an_error_saying_what(
    tmp_path: Path, members: str, applications: str, said: str
) -> None:
    code, out = _validate(tmp_path, _with_acordcs(members, applications))
    assert code == 1, out
    (line,) = [ln for ln in out.splitlines() if ": R201 " in ln]
    assert ": error: R201 " in line and said in line, line
    # the stereotype is not on the wrong metaclass: the type is unknown, which R201 says
    assert "T301" not in codes_in(out), out


def test_an_unknown_type_naming_one_acordcs_element_is_a_warning(tmp_path: Path) -> None:
    """A misspelt constraint on a component: ACORD-CS reads no constraint, nothing is lost."""
    members = (
        '  <packagedElement xmi:type="uml:Class" xmi:id="c2" name="Lamp"/>\n'
        '  <packagedElement xmi:type="uml:Constrant" xmi:id="k1" name="bright" '
        'constrainedElement="c2"/>'
    )
    text = _with_acordcs(members, ' <ACORDCS:CtxComponent xmi:id="s2" base_Class="c2"/>')
    _, out = _validate(tmp_path, text)
    (line,) = [ln for ln in out.splitlines() if ": R201 " in ln]
    assert (
        ": warning: R201 unknown xmi:type uml:Constrant (did you mean uml:Constraint?) on " in line
    )


def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch) -> None:
    """docs/diagnostics.md's R201 examples: the warning is a transcript on ``lamp.xmi``
    (:data:`MISSPELT_CLASS`, run by tests/docs), the error a line of output on
    :data:`MISSPELT_COMPONENT`, checked here."""
    page = (Path(__file__).parents[2] / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = page.split("{#r201}", 1)[1].split("\n### ", 1)[0]
    assert "$ acordcs-gen validate lamp.xmi" in section
    (shown,) = re.findall(r"^lamp-component\.xmi:\d+:1: error: R201 .*$", section, flags=re.M)
    monkeypatch.chdir(tmp_path)
    Path("lamp-component.xmi").write_text(MISSPELT_COMPONENT, encoding="utf-8")
    result = run_main(["validate", "lamp-component.xmi"])
    assert result.code == 1 and shown in result.out.splitlines(), result.out


def test_children_the_walk_does_not_read_are_named_not_dropped(tmp_path: Path) -> None:
    text = _xmi2(
        "Bouml",
        """  <packagedElement xmi:type="uml:Class" xmi:id="c2" name="Lamp">
   <ownedRule xmi:type="uml:Constraint" xmi:id="r1" name="positive"/>
   <ownedConnector xmi:id="k1" name="wire"/>
  </packagedElement>""",
    )
    code, out = _validate(tmp_path, text)
    assert code == 0, out
    constraint, connector = _notes(out)
    assert "R211 1 uml:Constraint element skipped" in constraint
    assert "R211 1 <ownedConnector> element skipped: written without xmi:type" in connector


def test_a_profiles_extensions_and_imports_are_not_noted(tmp_path: Path) -> None:
    text = _xmi2(
        "Bouml",
        """  <packageImport xmi:id="pi" importedPackage="x"/>
  <packagedElement xmi:type="uml:Profile" xmi:id="p" name="P">
   <packagedElement xmi:type="uml:Stereotype" xmi:id="s" name="S"/>
   <packagedElement xmi:type="uml:Extension" xmi:id="e" name="E" memberEnd="s"/>
  </packagedElement>""",
    )
    uml = read_uml(str(_write(tmp_path, text)))
    assert [d.code for d in uml.diagnostics] == [], uml.diagnostics


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "model.xmi"
    path.write_text(text, encoding="utf-8")
    return path


def test_the_metaclass_list_knows_every_version_and_no_enumeration() -> None:
    names = uml_metaclasses()
    assert metamodel_of("Class") == "UML 2.5" and metamodel_of("ExecutionEvent") == "UML 2.0-2.3"
    assert metamodel_of("CreateAction") == "UML 1.4" and metamodel_of("Structure") == "UML 1.3"
    assert metamodel_of("GraphNode") == "Diagram Interchange 1.0"
    assert metamodel_of("VisibilityKind") is None and metamodel_of("activitySwimlane2") is None
    # every name the readers read is UML
    from acordcs.xmi.uml import CLASSIFIER_KINDS

    assert set(names) >= CLASSIFIER_KINDS
