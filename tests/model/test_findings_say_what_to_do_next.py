"""Every finding says what to do next, in words that fit (issue 30): an L402 with no close name
says where to add the attribute (the monitor a rule reads from, the element a rule writes to, the
element the name is qualified with), an L406 where to add the operation; an L405 is said once per
output that feeds back, counting the rules that conclude it; articles agree with what follows
("an asynchronous port", "an Integer")."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from tests.support.generator import weblab_variant
from tests.support.toolchain import ROOT, codes_in, no_crash, replace, run_main

VENTILATION = ROOT / "samples" / "papyrus" / "ventilation.uml"
AIR_RULE = "fresh: if co2 is low and humidity is not humid then Fan.speed is slow"
UPKEEP_RULE = "idle: if Occupancy.people == 0 and Fan.speed > 10 then Fan.setSpeed(10)"


def _ventilation(tmp_path: Path, *edits: tuple[str, str]) -> Path:
    text = VENTILATION.read_text(encoding="utf-8")
    for old, new in edits:
        text = replace(text, old, new)
    model = tmp_path / "ventilation.uml"
    model.write_text(text, encoding="utf-8")
    shutil.copy(VENTILATION.with_name("ACORDCS.profile.uml"), tmp_path)
    return model


def _findings(model: Path) -> list[str]:
    result = run_main(["validate", str(model)])
    no_crash(result)
    return [line for line in result.out.splitlines() if ": error: " in line]


def test_a_name_read_by_a_rule_is_added_to_the_monitor_feeding_the_set(tmp_path: Path) -> None:
    (line,) = _findings(
        _ventilation(tmp_path, (AIR_RULE, AIR_RULE.replace("humidity is", "temperature is")))
    )
    assert (
        "L402 rule 3 of tag 'Rule' of policy 'AirRules', column 26: variable 'temperature': no "
        "element in the scope of policy set 'Airflow' has attribute 'temperature'; add attribute "
        "'temperature' to AirSensor (the monitor feeding policy set 'Airflow'); scope: AirSensor, "
        "Fan, FanPort [Adaptation::AirRules (_AirRules)]"
    ) in line


def test_a_name_a_rule_concludes_is_added_to_what_the_set_adapts(tmp_path: Path) -> None:
    edit = (AIR_RULE, AIR_RULE.replace("then Fan.speed is slow", "then airflow is slow"))
    (line,) = _findings(_ventilation(tmp_path, edit))
    assert (
        "no element in the scope of policy set 'Airflow' has attribute 'airflow'; add attribute "
        "'airflow' to Fan (what policy set 'Airflow' adapts); scope: "
    ) in line


def test_a_qualified_name_is_added_to_the_element_it_names(tmp_path: Path) -> None:
    edit = (UPKEEP_RULE, UPKEEP_RULE.replace("Occupancy.people", "Occupancy.visitors"))
    (line,) = _findings(_ventilation(tmp_path, edit))
    assert line.endswith(
        "variable 'Occupancy.visitors': Occupancy has no attribute 'visitors'; add attribute "
        "'visitors' to Occupancy, or use one of its attributes: people "
        "[Adaptation::UpkeepRules (_UpkeepRules)]"
    ), line


def test_a_missing_operation_is_added_to_the_element_it_names(tmp_path: Path) -> None:
    edit = (UPKEEP_RULE, UPKEEP_RULE.replace("Fan.setSpeed(10)", "Fan.slowDown(10)"))
    (line,) = _findings(_ventilation(tmp_path, edit))
    assert (
        "L406 rule 1 of tag 'Rule' of policy 'UpkeepRules', column 56: operation 'Fan.slowDown': "
        "Fan has no operation 'slowDown'; add operation 'slowDown' to Fan, or use one of its "
        "operations: setSpeed, purge"
    ) in line


def test_a_name_of_an_element_out_of_the_scope_says_to_relate_it(tmp_path: Path) -> None:
    edit = (AIR_RULE, AIR_RULE.replace("humidity is", "people is"))
    (line,) = _findings(_ventilation(tmp_path, edit))
    assert (
        "no element in the scope of policy set 'Airflow' has attribute 'people'; Occupancy has it "
        "but is not in the scope (relate it: a monitor feeding the set, or an element the set "
        "adapts); scope: AirSensor, Fan, FanPort"
    ) in line


def test_a_close_name_is_still_suggested_instead(tmp_path: Path) -> None:
    (line,) = _findings(
        _ventilation(tmp_path, (AIR_RULE, AIR_RULE.replace("humidity is", "humdity is")))
    )
    assert "has attribute 'humdity' (did you mean 'humidity'?); scope: " in line
    assert "add attribute" not in line


FIRST_RULE = (
    "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"
)


def test_an_output_read_as_an_input_is_said_once_counting_the_rules(tmp_path: Path) -> None:
    # before: 12 x L405, one per rule concluding Locomotion.maxSpeed
    edit = (FIRST_RULE, FIRST_RULE.replace("angle is narrow", "Locomotion.maxSpeed is slow"), 2)
    result = run_main(["validate", str(weblab_variant(tmp_path, edit))])
    assert codes_in(result.out) == {"L405"}, result.out
    (line,) = [line for line in result.out.splitlines() if " L405 " in line]
    assert (
        "L405 'Locomotion.maxSpeed' is an output of 12 rules (rules 1-6 of tag 'Rule' of policy "
        "'StraightRules'; rules 1-6 of tag 'Rule' of policy 'TurnRules') and an input of rule 1 "
        "of tag 'Rule' of policy 'StraightRules' in policy set 'SpeedLimiting': a fuzzy rule "
        "block must not feed back into itself; read it in another policy set, or conclude "
        "another attribute [WebLab::ContextAwareNavigation::Adaptation::StraightRules "
        "(BOUML_0x20302_4)]"
    ) in line


def test_an_output_read_as_an_input_in_papyrus_names_the_rule_reading_it(tmp_path: Path) -> None:
    edit = (
        "muggy: if co2 is fair and humidity is humid",
        "muggy: if co2 is fair and Fan.speed is slow",
    )
    (line,) = _findings(_ventilation(tmp_path, edit))
    assert (
        "L405 'Fan.speed' is an output of 3 rules (rules 1-3 of tag 'Rule' of policy 'AirRules') "
        "and an input of rule 2 of tag 'Rule' of policy 'AirRules' in policy set 'Airflow'"
    ) in line


def test_ports_of_two_kinds_read_with_the_right_article(tmp_path: Path) -> None:
    text = (ROOT / "samples" / "weblab" / "weblab.xmi").read_text(encoding="utf-8")
    start = text.index('name="NavVisionPort"')
    end = text.index("</xmi:Extension>", start)
    text = (
        text[:start]
        + replace(text[start:end], ':kind" value="synchronous"', ':kind" value="asynchronous"')
        + text[end:]
    )
    text = replace(
        text,
        'kind="synchronous" role="required" base_Element="BOUML_0x1fa02_4"',
        'kind="asynchronous" role="required" base_Element="BOUML_0x1fa02_4"',
    )
    model = tmp_path / "weblab.xmi"
    model.write_text(text, encoding="utf-8")
    (line,) = _findings(model)
    assert (
        "A502 port connection 'VisionLink' joins a synchronous port ('VisionPort') and an "
        "asynchronous port ('NavVisionPort'); both must be of the same kind: set the tag kind of "
        "one to the other's"
    ) in line


def test_a_tag_of_the_wrong_type_reads_with_the_right_article(tmp_path: Path) -> None:
    (line,) = _findings(_ventilation(tmp_path, ('port="9101"', 'port="ninety"')))
    assert "T304 tag 'port' must be an Integer, not 'ninety'" in line


def _shown(code: str) -> list[str]:
    """The ``ventilation.uml:`` lines docs/diagnostics.md shows in the section of ``code``."""
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    section = page.split(f"{{#{code}}}", 1)[1].split("\n### ", 1)[0]
    return [line for line in section.splitlines() if line.startswith("ventilation.uml:")]


@pytest.mark.parametrize(
    ("code", "edit"),
    [
        ("l402", (AIR_RULE, AIR_RULE.replace("humidity is", "temperature is"))),
        (
            "l405",
            (
                "muggy: if co2 is fair and humidity is humid",
                "muggy: if co2 is fair and Fan.speed is slow",
            ),
        ),
    ],
)
def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch, code, edit) -> None:
    model = _ventilation(tmp_path, edit)
    monkeypatch.chdir(tmp_path)
    (shown,) = _shown(code)
    assert [shown] == run_main(["validate", model.name]).out.splitlines()[:-1]
