"""Root causes first (issue 21): findings in source order with the cause of others before them, a
misspelt stereotype reported once rather than through every rule naming its element, a misspelt
tag an error that says what it meant, and a Papyrus model whose applied profile file is missing
told so."""

from __future__ import annotations

import shutil
from pathlib import Path

from tests.support.toolchain import SAMPLES, WEBLAB, codes_in, run_main

PAPYRUS = SAMPLES / "papyrus" / "thermostat.uml"


def _edited(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def _misspelt_monitor(text: str) -> str:
    """The WebLab model with monitor Control's stereotype misspelt in both places BOUML writes it."""
    start = text.index('name="Control" xmi:id="BOUML_0x20002_4"')
    end = text.index("</xmi:Extension>", start)
    text = (
        text[:start]
        + text[start:end].replace("ACORDCS:CtxMonitor", "ACORDCS:CtxMonitr")
        + text[end:]
    )
    return text.replace(
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20002_4"',
        '<ACORDCS:CtxMonitr xmi:id="BOUML_STELT_0x20002_4"',
    )


def test_a_misspelt_stereotype_is_reported_once_not_through_every_rule(tmp_path):
    model = _edited(tmp_path, "monitr.xmi", _misspelt_monitor(WEBLAB.read_text(encoding="utf-8")))
    result = run_main(["validate", str(model)])
    # 38 L402s followed from the one typo (every rule naming cycleRate, angle or Control.speed):
    # the cause counts them and names what they are about
    assert result.out.count(": error: ") == 1, result.out
    assert "T302 ACORDCS has no stereotype 'CtxMonitr' (did you mean 'CtxMonitor'?)" in result.out
    assert (
        "; 38 findings (L402) about 'cycleRate', 'angle', 'Control.speed' are checked once this "
        "is fixed [" in result.out
    )
    assert result.code == 1


def test_a_name_no_misspelt_element_has_is_still_reported(tmp_path):
    text = _misspelt_monitor(WEBLAB.read_text(encoding="utf-8"))
    text = text.replace(
        "then Locomotion.maxSpeed is slow&#10;smallMedium",
        "then Locomotion.maxSped is slow&#10;smallMedium",
    )
    result = run_main(["validate", str(_edited(tmp_path, "both.xmi", text))])
    assert codes_in(result.out) == {"T302", "L402"}
    (l402,) = [line for line in result.out.splitlines() if " L402 " in line]
    assert "'Locomotion.maxSped'" in l402 and "'cycleRate'" not in l402


def test_a_misspelt_tag_comes_before_what_it_leaves_unset(tmp_path):
    text = WEBLAB.read_text(encoding="utf-8")
    text = text.replace(
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20102_4" acquisition="poll"',
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20102_4" acquisiton="poll"',
    ).replace('CtxMonitor:acquisition" value="poll"', 'CtxMonitor:acquisiton" value="poll"')
    result = run_main(["validate", str(_edited(tmp_path, "acq.xmi", text))])
    lines = [
        line for line in result.out.splitlines() if ": error: " in line or ": warning: " in line
    ]
    codes = [line.split(": ")[2].split()[0] for line in lines]
    assert codes == ["T320", "A515"], result.out  # the cause, then its consequence
    assert "has no tag 'acquisiton' (did you mean 'acquisition'?)" in lines[0]
    assert result.code == 1


def test_a_cause_further_down_the_file_is_still_printed_first(tmp_path):
    # The only acquisition tag is in the root-level application, near the file's end, after the
    # monitor itself (where A515 is reported): grouped by element, the cause leads.
    text = WEBLAB.read_text(encoding="utf-8")
    start = text.index('name="Usage" xmi:id="BOUML_0x20102_4"')
    end = text.index("</xmi:Extension>", start)
    block = text[start:end].replace(
        '<taggedValue tag="ACORDCS:CtxMonitor:acquisition" value="poll"/>', ""
    )
    text = text[:start] + block + text[end:]
    text = text.replace(
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20102_4" acquisition="poll"',
        '<ACORDCS:CtxMonitor xmi:id="BOUML_STELT_0x20102_4" acquisiton="poll"',
    )
    result = run_main(["validate", str(_edited(tmp_path, "late.xmi", text))])
    found = [
        line for line in result.out.splitlines() if ": error: " in line or ": warning: " in line
    ]
    assert [line.split(": ")[2].split()[0] for line in found] == ["T320", "A515"], result.out
    first, second = (int(line.split(":")[1]) for line in found)
    assert first > second  # printed first although it is further down


def test_a_papyrus_model_whose_profile_file_is_missing_is_told_so(tmp_path):
    model = tmp_path / "thermostat.uml"
    shutil.copy(PAPYRUS, model)
    result = run_main(["validate", str(model)])
    assert codes_in(result.out) == {"T321"}
    assert "applies the profile in 'ACORDCS.profile.uml', which is not there" in result.out
    assert "acordcs-gen profile export DIR --tool papyrus" in result.out
    (line,) = [line for line in result.out.splitlines() if "T321" in line]
    assert str(tmp_path) not in line.split("T321", 1)[1]  # no path of this machine in it
    assert result.code == 0  # a warning: the model itself is whole
    shutil.copy(PAPYRUS.with_name("ACORDCS.profile.uml"), tmp_path)
    assert run_main(["validate", "--fail-on", "warning", str(model)]).code == 0
