"""X107 (not well-formed, read in recovery mode) says what to do for the file it is about: BOUML
writes names unescaped, so a '<' in a name of a BOUML export is renamed in BOUML; anywhere else
(a hand-written or another tool's file, a tag's value, a rule's text) the character is written as
XML writes it, ``&lt;`` or ``&amp;``. Each keeps file:line:col, and the other checks still run."""

from __future__ import annotations

import shutil
from pathlib import Path

from tests.support.generator import weblab_variant
from tests.support.toolchain import ROOT, codes_in, no_crash, replace, run_main

VENTILATION = ROOT / "samples" / "papyrus" / "ventilation.uml"
RENAME = "BOUML writes names unescaped: rename the element"


def _ventilation(tmp_path: Path, old: str, new: str) -> Path:
    model = tmp_path / "ventilation.uml"
    model.write_text(replace(VENTILATION.read_text(encoding="utf-8"), old, new), encoding="utf-8")
    shutil.copy(VENTILATION.with_name("ACORDCS.profile.uml"), tmp_path)
    return model


def _x107(model: Path) -> str:
    result = run_main(["validate", str(model)])
    no_crash(result)
    assert "X107" in codes_in(result.out) and result.code == 1, result.out
    (line,) = [line for line in result.out.splitlines() if " X107 " in line]
    return line


def test_a_less_than_in_a_hand_written_rule_is_written_as_lt(tmp_path: Path) -> None:
    model = _ventilation(tmp_path, "Occupancy.people == 0 and", "Occupancy.people < 1 and")
    line = _x107(model)
    where = model.read_text(encoding="utf-8").splitlines()
    row = next(n for n, text in enumerate(where, start=1) if "people < 1" in text)
    column = where[row - 1].index("< 1") + 1
    assert line == (
        f"{model}:{row}:{column}: error: X107 not well-formed XML: Unescaped '<' not allowed in "
        "attributes values; in the value of 'Rule', write '<' as &lt; (a rule's 'a < b' as "
        "'a &lt; b'); the rest was read in recovery mode so that every other check could run, but "
        "what is near this place may be cut short"
    )
    assert "BOUML" not in line


def test_an_ampersand_in_a_hand_written_name_is_written_as_amp(tmp_path: Path) -> None:
    line = _x107(_ventilation(tmp_path, 'name="Fan">', 'name="Fan&Filter">'))
    assert "in the value of 'name', write '&' as &amp;;" in line and RENAME not in line


def test_a_less_than_in_a_bouml_name_is_renamed_in_bouml(tmp_path: Path) -> None:
    line = _x107(weblab_variant(tmp_path, ('name="Image" xmi:id=', 'name="Image<T>" xmi:id=')))
    assert f"({RENAME}, e.g. no '<' or '&', and export again)" in line
    assert "&lt;" not in line


def test_a_less_than_in_a_bouml_tag_value_is_written_as_lt(tmp_path: Path) -> None:
    rule = ("Control.speed == 0 then", "Control.speed < 1 then", 2)  # a rule: a tag's value
    line = _x107(weblab_variant(tmp_path, rule))
    assert "in the value of 'value', write '<' as &lt;" in line and RENAME not in line


def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch) -> None:
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = page.split("{#x107}", 1)[1].split("\n### ", 1)[0]
    (shown,) = [line for line in section.splitlines() if line.startswith("ventilation.uml:")]
    model = _ventilation(tmp_path, "Occupancy.people == 0 and", "Occupancy.people < 1 and")
    monkeypatch.chdir(tmp_path)
    assert run_main(["validate", model.name]).out.splitlines()[0] == shown
