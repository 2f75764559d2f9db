"""``validate`` never says "clean" about a file it could not judge: Papyrus diagram files are
refused (exit 2), and a model that applies no ACORD-CS stereotype gets T313 saying whether the
profile is there."""

from __future__ import annotations

import json
import shutil

from tests.support.toolchain import ROOT, no_crash, run_main

PAPYRUS = ROOT / "samples" / "papyrus" / "thermostat.uml"

# A .notation file as Papyrus saves one: XMI with the UML namespace, diagrams pointing into the model.
NOTATION = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.0" xmlns:xmi="http://www.omg.org/XMI" xmlns:notation="http://www.eclipse.org/gmf/runtime/1.0.2/notation" xmlns:uml="http://www.eclipse.org/uml2/5.0.0/UML">
  <notation:Diagram xmi:id="_d" type="PapyrusUMLClassDiagram" name="Main" measurementUnit="Pixel">
    <children xmi:type="notation:Shape" xmi:id="_s" type="Class_Shape">
      <element xmi:type="uml:Class" href="thermostat.uml#_Heater"/>
    </children>
    <element xmi:type="uml:Model" href="thermostat.uml#_model"/>
  </notation:Diagram>
</xmi:XMI>
"""
DI = """<?xml version="1.0" encoding="UTF-8"?>
<xmi:XMI xmi:version="2.0" xmlns:xmi="http://www.omg.org/XMI" xmlns:architecture="http://www.eclipse.org/papyrus/infra/core/architecture"/>
"""


def test_a_notation_file_is_refused_with_what_to_do(tmp_path):
    path = tmp_path / "thermostat.notation"
    path.write_text(NOTATION, encoding="utf-8")
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 2
    line = result.out.splitlines()[0]
    assert line.startswith(f"{path}: error: X109 a Papyrus diagram file, not a model")
    assert "thermostat.uml" in line
    assert "0 errors" not in result.out


def test_a_di_file_and_a_renamed_notation_file_are_refused(tmp_path):
    di = tmp_path / "model.di"
    di.write_text(DI, encoding="utf-8")
    renamed = tmp_path / "diagrams.xml"
    renamed.write_text(NOTATION, encoding="utf-8")
    for path in (di, renamed):
        result = run_main(["validate", "--format", "json", str(path)])
        assert result.code == 2
        (entry,) = json.loads(result.out)["files"]
        assert entry["readable"] is False
        assert [d["code"] for d in entry["diagnostics"]] == ["X109"]
    assert run_main(["inspect", str(renamed)]).code == 2


def test_other_non_model_files_exit_2(tmp_path):
    text = tmp_path / "notes.txt"
    text.write_text("meeting notes\n", encoding="utf-8")
    other_xml = tmp_path / "pom.xml"
    other_xml.write_text('<project xmlns="http://maven.apache.org/POM/4.0.0"/>', encoding="utf-8")
    for path in (text, other_xml):
        result = run_main(["validate", str(path)])
        no_crash(result)
        assert result.code == 2, result.out


def test_a_model_without_the_profile_warns_t313(tmp_path):
    text = PAPYRUS.read_text(encoding="utf-8")
    bare = text.split("  <ACORDCS:CtxContainer", 1)[0] + "</xmi:XMI>\n"
    path = tmp_path / "bare.uml"
    path.write_text(bare, encoding="utf-8")
    shutil.copy(PAPYRUS.with_name("ACORDCS.profile.uml"), tmp_path)  # the profile it applies
    result = run_main(["validate", str(path)])
    assert result.code == 0  # a warning: exit 1 only with --fail-on warning
    (line, summary) = result.out.splitlines()
    assert line.startswith(f"{path}:5:1: warning: T313 no element has an ACORD-CS stereotype")
    assert "the profile ACORDCS is not in the file" in line
    assert "acordcs-gen profile export" in line
    assert summary == f"{path}: 0 errors, 1 warning, 0 infos"
    assert run_main(["validate", "--fail-on", "warning", str(path)]).code == 1


def test_t313_says_when_the_profile_is_there_but_unused(tmp_path):
    profile = ROOT / "src" / "acordcs" / "profile" / "ACORDCS.xmi"
    result = run_main(["validate", str(profile)])
    assert "T313" in result.out
    assert "the profile ACORDCS is in the file" in result.out


def test_an_applied_model_has_no_t313():
    assert "T313" not in run_main(["validate", str(PAPYRUS)]).out
