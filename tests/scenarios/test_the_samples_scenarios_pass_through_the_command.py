"""Every sample's scenario files pass through ``acordcs-gen test`` (so ``make test`` runs them),
the JUnit XML it writes reads back with a JUnit parser, and a rule mutated in a copy of the
WebLab model makes its scenario fail with the rule named and the expectation's place."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from junitparser import Failure, JUnitXml

from tests.support.toolchain import ROOT, SAMPLES, WEBLAB, run_main

MODELS = sorted(
    p
    for p in SAMPLES.glob("*/*")
    if p.suffix in (".xmi", ".uml") and p.with_name(p.stem + ".scenarios.yaml").is_file()
)


def test_every_sample_with_policies_has_scenarios():
    assert {p.relative_to(SAMPLES).as_posix() for p in MODELS} == {
        "mixed/greenhouse.uml",
        "papyrus/thermostat.uml",
        "papyrus/ventilation.uml",
        "smartroom/smartroom.xmi",
        "tutorial/greenhouse.uml",
        "weblab/weblab.xmi",
    }


@pytest.mark.parametrize("model", MODELS, ids=lambda p: p.name)
def test_the_samples_scenarios_pass_and_fire_every_rule(model: Path, tmp_path: Path):
    junit = tmp_path / "results.xml"
    result = run_main(["test", str(model), "--junit", str(junit), "--min-coverage", "100"])
    assert result.code == 0, result.out + result.err
    lines = result.out.splitlines()
    assert lines[-1].endswith("(100 %)"), lines[-1]
    passes = [line for line in lines if line.startswith("PASS ")]
    assert passes and not [line for line in lines if line.startswith("FAIL ")]
    suites = list(JUnitXml.fromfile(str(junit)))
    cases = [case for suite in suites for case in suite]
    assert len(cases) == len(passes)
    assert all(case.is_passed for case in cases)


@pytest.fixture(scope="module")
def mutated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A copy of the WebLab whose paper rule smallNarrow concludes fast instead of slow."""
    folder = tmp_path_factory.mktemp("mutated")
    text = WEBLAB.read_text(encoding="utf-8")
    rule = "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is "
    assert text.count(rule + "slow") == 2  # BOUML writes a tag in two places
    (folder / "weblab.xmi").write_text(text.replace(rule + "slow", rule + "fast"), encoding="utf-8")
    shutil.copy(WEBLAB.with_name("weblab.scenarios.yaml"), folder / "weblab.scenarios.yaml")
    return folder / "weblab.xmi"


def test_a_mutated_rule_fails_its_scenario_naming_the_rule(mutated: Path, tmp_path: Path):
    junit = tmp_path / "results.xml"
    result = run_main(["test", str(mutated), "--junit", str(junit)])
    assert result.code == 1, result.out + result.err
    failing = [line for line in result.out.splitlines() if line.startswith("FAIL ")]
    assert len(failing) == 1 and "limits the speed to slow" in failing[0]
    scenario_file = mutated.with_name("weblab.scenarios.yaml")
    lines = scenario_file.read_text(encoding="utf-8").splitlines()
    # the place of the expectation that failed: the term expected of Locomotion.maxSpeed
    row = next(i for i, line in enumerate(lines, 1) if "term: {Locomotion.maxSpeed: slow}" in line)
    column = lines[row - 1].index("Locomotion.maxSpeed") + 1
    assert (
        f"{scenario_file}:{row}:{column}: error: S810 expected Locomotion.maxSpeed to be slow"
        in result.out
    )
    assert "SpeedLimiting.StraightRules.smallNarrow 1.00" in result.out
    cases = [case for suite in JUnitXml.fromfile(str(junit)) for case in suite]
    failed = [case for case in cases if not case.is_passed]
    assert [case.name for case in failed] == [failing[0].split(": ", 1)[1].rsplit(" (", 1)[0]]
    assert any(isinstance(r, Failure) and "smallNarrow" in r.text for r in failed[0].result)


def test_sarif_gives_the_failure_on_the_scenario_file(mutated: Path):
    result = run_main(["test", str(mutated), "--format", "sarif"])
    assert result.code == 1
    run = json.loads(result.out)["runs"][0]
    failures = [r for r in run["results"] if r["ruleId"] == "S810"]
    assert failures and all(r["level"] == "error" for r in failures)
    where = failures[0]["locations"][0]["physicalLocation"]
    assert where["artifactLocation"]["uri"].endswith("weblab.scenarios.yaml")
    assert where["region"]["startLine"] > 1
    assert run["invocations"][0]["exitCode"] == 1


def test_rules_no_scenario_fired_are_warned_and_min_coverage_fails(tmp_path: Path):
    only = tmp_path / "one.yaml"
    only.write_text(
        "scenarios:\n  - name: only cool\n    steps: [{at: 0, set: {Climate.temperature: 5}}]\n",
        encoding="utf-8",
    )
    model = str(SAMPLES / "tutorial" / "greenhouse.uml")
    result = run_main(["test", model, str(only)])
    assert result.code == 0
    assert (
        "warning: S812 2 rules of policy set Ventilation fired in no scenario: VentRules.warm, VentRules.hot"
        in result.out
    )
    assert "no input reached terms warm, hot of Climate.temperature" in result.out
    assert result.out.splitlines()[-1].endswith("rules fired: 1 of 3 (33 %)")
    assert run_main(["test", model, str(only), "--min-coverage", "50"]).code == 1


def test_the_documented_naming_convention_finds_the_files():
    assert (ROOT / "samples" / "tutorial" / "greenhouse.scenarios.yaml").is_file()
    from acordcs.cli.testing import scenario_files

    assert scenario_files(str(SAMPLES / "tutorial" / "greenhouse.uml")) == [
        str(SAMPLES / "tutorial" / "greenhouse.scenarios.yaml")
    ]


def test_json_gives_each_failure_with_its_place_and_the_rules_in_effect(mutated: Path):
    result = run_main(["test", str(mutated), "--format", "json"])
    assert result.code == 1
    data = json.loads(result.out)
    failed = [s for s in data["scenarios"] if not s["passed"]]
    assert [s["name"] for s in failed] == [
        "a slow control cycle on a straight line limits the speed to slow"
    ]
    first = failed[0]["failures"][0]
    assert first["location"].startswith(str(mutated.with_name("weblab.scenarios.yaml")) + ":")
    assert first["rules"] == [{"rule": "SpeedLimiting.StraightRules.smallNarrow", "degree": 1.0}]
    assert data["coverage"]["percent"] == 100.0


def test_a_container_named_in_policy_sets_runs_the_sets_it_hosts(tmp_path: Path):
    path = tmp_path / "side.yaml"
    path.write_text(
        "scenarios:\n  - name: the weblab side\n    policy-sets: [WebLabSide]\n"
        "    steps: [{at: 0, set: {Control.cycleRate: 0.5, Control.angle: 2, Control.speed: 0}}]\n"
        "    expect: [{at: 0, fired: [smallNarrow, count]}, {at: 2, fired: [smallLow]}]\n",
        encoding="utf-8",
    )
    result = run_main(["test", str(WEBLAB), str(path)])
    assert result.code == 0, result.out + result.err
