"""Scenario files are hostile input: what the reader refuses, it refuses with file:line:col and
what to do (exit 2, nothing run); names the model lacks get a "did you mean"; values outside a
variable's range are refused with the range; a model that does not validate runs nothing."""

from __future__ import annotations

from pathlib import Path

import pytest

from tests.support.toolchain import SAMPLES, run_main

GREENHOUSE = str(SAMPLES / "tutorial" / "greenhouse.uml")


def scenario(steps: str = "[{at: 0, set: {Climate.temperature: 20}}]", extra: str = "") -> str:
    return f"scenarios:\n  - name: s\n    steps: {steps}\n{extra}"


CASES = [
    # (file text, line, what the column points at, code, words of the message)
    ("scenarios:\n  - &a {name: s, steps: []}\n  - *a\n", 2, "&a", "S802", "anchors and aliases"),
    (
        "scenarios:\n  - name: !!python/object/apply:os.system ['true']\n    steps: []\n",
        2,
        "!!python",
        "S802",
        "tags",
    ),
    (scenario(extra="    expct: []\n"), 4, "expct", "S803", "did you mean 'expect'"),
    (
        scenario("[{at: 0, set: {Climate.temprature: 20}}]"),
        3,
        "Climate.temprature",
        "S804",
        "no attribute 'Climate.temprature' (did you mean 'Climate.temperature'?)",
    ),
    (
        scenario("[{at: 0, set: {Climate.temperature: .nan}}]"),
        3,
        ".nan",
        "S805",
        "not a finite number",
    ),
    (
        scenario("[{at: 0, set: {Climate.temperature: 60}}]"),
        3,
        "60",
        "S805",
        "Climate.temperature = 60 is outside its range 0..50",
    ),
    (
        scenario("[{at: 5, set: {Vent.opening: 1}}, {at: 1, set: {Vent.opening: 2}}]"),
        3,
        "1, set",
        "S805",
        "give the steps in time order",
    ),
    (
        scenario(extra="    expect: [{at: 0, fired: [col]}]\n"),
        4,
        "col]",
        "S804",
        "no rule 'col' in the scenario's policy sets (did you mean 'cool'?)",
    ),
    (
        scenario(extra="    expect: [{at: 0, term: {Vent.opening: wid}}]\n"),
        4,
        "wid}",
        "S804",
        "no term of Vent.opening 'wid' (did you mean 'wide'?)",
    ),
    ("scenarios: [\n", 2, "", "S802", "not valid YAML"),
    (
        scenario(extra="    expect: [{at: 0, term: {Vent.opening: off}}]\n"),
        4,
        "off}",
        "S803",
        "not the boolean false: YAML reads yes, no, on, off, true and false unquoted as booleans",
    ),
]


@pytest.mark.parametrize(("text", "line", "marker", "code", "words"), CASES)
def test_a_bad_scenario_file_is_refused_at_its_place(
    tmp_path: Path, text: str, line: int, marker: str, code: str, words: str
):
    rows = [*text.splitlines(), ""]
    column = rows[line - 1].index(marker) + 1
    path = tmp_path / "bad.yaml"
    path.write_text(text, encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(path)])
    assert result.code == 2, result.out + result.err
    assert result.out == ""  # nothing was run
    first = result.err.splitlines()[0]
    assert first.startswith(f"{path}:{line}:{column}: error: {code} "), first
    assert words in first, first
    assert "no scenario was run" in result.err


def test_a_file_over_the_size_limit_is_refused_unread(tmp_path: Path):
    path = tmp_path / "huge.yaml"
    path.write_bytes(b"# " + b"x" * (1 << 20) + b"\n")
    result = run_main(["test", GREENHOUSE, str(path)])
    assert result.code == 2
    assert f"{path}: error: S801 scenario file is " in result.err


def test_too_deep_a_document_is_refused(tmp_path: Path):
    path = tmp_path / "deep.yaml"
    path.write_text("a: " + "[" * 40 + "]" * 40 + "\n", encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(path)])
    assert result.code == 2 and "S806 nested deeper than 32 levels" in result.err


def test_a_model_that_does_not_validate_runs_nothing(tmp_path: Path):
    path = tmp_path / "any.yaml"
    path.write_text(scenario(), encoding="utf-8")
    result = run_main(["test", str(SAMPLES / "mistakes" / "broken-weblab.xmi"), str(path)])
    assert result.code == 2 and result.out == ""
    assert "the model does not validate" in result.err.splitlines()[-1]


def test_no_scenario_file_is_a_usage_error_naming_the_convention(tmp_path: Path):
    model = tmp_path / "greenhouse.uml"
    model.write_bytes(Path(GREENHOUSE).read_bytes())
    result = run_main(["test", str(model)])
    assert result.code == 2
    assert "greenhouse.scenarios.yaml" in result.err and "greenhouse.scenarios/" in result.err


def test_a_context_document_the_provider_refuses_fails_the_scenario_at_its_step(tmp_path: Path):
    path = tmp_path / "entities.yaml"
    path.write_text(
        "scenarios:\n"
        "  - name: a bomb\n"
        "    policy-sets: [Recovering]\n"
        "    steps:\n"
        "      - at: 0\n"
        "        context:\n"
        "          publisher: Locomotion\n"
        "          document: '<!DOCTYPE t [<!ENTITY a \"aaaa\">]><telemetry>&a;</telemetry>'\n",
        encoding="utf-8",
    )
    result = run_main(["test", str(SAMPLES / "weblab" / "weblab.xmi"), str(path)])
    assert result.code == 1
    assert f"  {path}:8:21: error: S811 the document of Locomotion was refused: " in result.out
    assert "entit" in result.out.lower()


def test_a_periodic_set_run_for_too_long_is_refused_before_it_runs(tmp_path: Path):
    path = tmp_path / "long.yaml"
    path.write_text(
        "scenarios:\n  - name: a year\n    policy-sets: [BandwidthLimiting]\n"
        "    steps: [{at: 0, set: {Usage.numUsers: 1}}, {at: 31536000, set: {Usage.numUsers: 2}}]\n",
        encoding="utf-8",
    )
    result = run_main(["test", str(SAMPLES / "weblab" / "weblab.xmi"), str(path)])
    assert result.code == 2 and result.out == ""
    column = path.read_text(encoding="utf-8").splitlines()[3].index("31536000") + 1
    assert (
        f"{path}:4:{column}: error: S806 policy set BandwidthLimiting fires at 0.5 Hz: 3.1536e+07 s"
        in result.err
    )


def test_a_name_with_control_characters_stays_on_its_line_and_in_valid_junit(tmp_path: Path):
    from junitparser import JUnitXml

    path = tmp_path / "names.yaml"
    path.write_text(
        'scenarios:\n  - name: "hot\\nPASS forged\\u0001"\n'
        "    steps: [{at: 0, set: {Climate.temperature: 40}}]\n"
        "    expect: [{at: 0, term: {Vent.opening: closed}}]\n",
        encoding="utf-8",
    )
    junit = tmp_path / "results.xml"
    result = run_main(["test", GREENHOUSE, str(path), "--junit", str(junit)])
    assert result.code == 1
    assert not [line for line in result.out.splitlines() if line.startswith("PASS")]
    (case,) = [case for suite in JUnitXml.fromfile(str(junit)) for case in suite]
    assert case.name == "hot\nPASS forged\\u0001" and not case.is_passed


def test_sarif_gives_a_refused_file_and_an_unwritable_junit_is_exit_2(tmp_path: Path):
    import json

    path = tmp_path / "bad.yaml"
    path.write_text(scenario("[{at: 0, set: {Climate.temprature: 20}}]"), encoding="utf-8")
    result = run_main(["test", GREENHOUSE, str(path), "--format", "sarif"])
    assert result.code == 2
    run = json.loads(result.out)["runs"][0]
    assert [r["ruleId"] for r in run["results"]] == ["S804"]
    assert run["invocations"][0] == {"executionSuccessful": False, "exitCode": 2}
    good = tmp_path / "good.yaml"
    good.write_text(scenario(), encoding="utf-8")
    unwritable = tmp_path / "no" / "such" / "dir" / "results.xml"
    result = run_main(["test", GREENHOUSE, str(good), "--junit", str(unwritable)])
    assert result.code == 2 and "cannot write it" in result.err
