"""``acordcs-gen validate``: the text, JSON and SARIF reports (shape, locations, URIs, no line a
name can forge) and the exit codes (--fail-on, several files, unreadable input)."""

from __future__ import annotations

import json
import re
import shutil
from pathlib import Path

from acordcs.diagnostics import CODES
from tests.support.toolchain import (
    ROOT,
    SMARTROOM,
    WEBLAB,
    no_crash,
    replace,
    run_main,
    run_process,
    write_model,
)

WEBLAB_REL = WEBLAB.relative_to(ROOT).as_posix()
TEXT_LINE = re.compile(
    r"^(?P<file>[^:]+)(?::(?P<line>[1-9]\d*):(?P<column>[1-9]\d*))?: "
    r"(?P<severity>error|warning|info): (?P<code>[XRTLANGZ]\d{3}) (?P<message>.+?)"
    r"(?: \[(?P<element>[^\]]*?)(?: ?\((?P<id>[^()]+)\))?\])?$"
)
SUMMARY = re.compile(r"^(?P<file>.+): (\d+) errors?, (\d+) warnings?, (\d+) infos?$")


def _with_problems(tmp_path: Path) -> Path:
    """A WebLab copy with an error (T306), a warning (T303) and an info (R206)."""
    text = WEBLAB.read_text(encoding="utf-8")
    text = replace(text, 'frequency="1" base_Element', 'frequency="0" priority="high" base_Element')
    text = replace(
        text,
        'CtxMonitor:frequency" value="1"/>',
        'CtxMonitor:frequency" value="0"/><taggedValue tag="ACORDCS:CtxMonitor:priority" value="high"/>',
    )
    # Image, a plain class, gets a free <<CtxComponent>>: R206 (info), and it is then not deployed (A506)
    head = '<packagedElement xmi:type="uml:Class" name="Image" xmi:id="BOUML_0x1f402_4" visibility="package">'
    text = replace(
        text,
        head,
        head + '<xmi:Extension extender="Bouml"><stereotype name="CtxComponent"/></xmi:Extension>',
    )
    target = tmp_path / "problems.xmi"
    target.write_text(text, encoding="utf-8")
    return target


def _only_warning(tmp_path: Path) -> Path:
    text = WEBLAB.read_text(encoding="utf-8")
    text = replace(text, 'frequency="1" base_Element', 'frequency="1" priority="high" base_Element')
    target = tmp_path / "warning.xmi"
    target.write_text(text, encoding="utf-8")
    return target


def test_clean_sample_text_output() -> None:
    result = run_main(["validate", WEBLAB_REL])
    assert result.code == 0
    assert result.out == f"{WEBLAB_REL}: 0 errors, 0 warnings, 0 infos\n"
    assert result.err == ""


def test_text_lines_have_the_documented_shape(tmp_path: Path) -> None:
    path = _with_problems(tmp_path)
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 1
    *lines, summary = result.out.splitlines()
    assert lines
    parsed = []
    for line in lines:
        match = TEXT_LINE.match(line)
        assert match, line
        assert match["file"] == str(path)
        assert match["code"] in CODES
        assert CODES[match["code"]][0].name.lower() == match["severity"]
        parsed.append(match)
    codes = {m["code"] for m in parsed}
    assert {"T306", "T303", "R206", "A506"} <= codes
    t306 = next(m for m in parsed if m["code"] == "T306")
    assert t306["element"] == "WebLab::ContextAwareNavigation::Adaptation::Usage"
    assert t306["id"] == "BOUML_0x20102_4"
    counts = SUMMARY.match(summary)
    assert counts and counts["file"] == str(path)
    by_severity = [sum(m["severity"] == s for m in parsed) for s in ("error", "warning", "info")]
    assert [int(counts[i]) for i in (2, 3, 4)] == by_severity


def test_json_structure(tmp_path: Path) -> None:
    path = _with_problems(tmp_path)
    text = run_main(["validate", str(path)])
    result = run_main(["validate", "--format", "json", str(path)])
    assert result.code == 1
    data = json.loads(result.out)
    assert set(data) == {"files", "summary"}
    (entry,) = data["files"]
    assert entry["file"] == str(path)
    assert entry["dialect"] == "bouml-xmi2"
    assert entry["readable"] is True
    keys = {"code", "severity", "message", "file", "line", "column", "element", "xmi_id"}
    for d in entry["diagnostics"]:
        assert set(d) == keys
        assert d["severity"] == CODES[d["code"]][0].name.lower()
        assert isinstance(d["line"], int) and d["line"] >= 1
    assert data["summary"] == {
        s: sum(d["severity"] == s for d in entry["diagnostics"])
        for s in ("error", "warning", "info")
    }
    # the same findings as the text format, in the same order
    text_codes = [m["code"] for m in map(TEXT_LINE.match, text.out.splitlines()[:-1])]
    assert text_codes == [d["code"] for d in entry["diagnostics"]]


def test_json_for_an_unreadable_file(tmp_path: Path) -> None:
    missing = tmp_path / "missing.xmi"
    result = run_main(["validate", "--format", "json", str(missing)])
    assert result.code == 2
    (entry,) = json.loads(result.out)["files"]
    assert entry["readable"] is False
    assert [d["code"] for d in entry["diagnostics"]] == ["X101"]


def _sarif(cwd: Path, *names: str) -> tuple[int, dict]:
    result = run_process(["validate", "--format", "sarif", *names], cwd=cwd)
    no_crash(result)
    return result.code, json.loads(result.out)


def test_sarif_is_github_code_scanning_shaped(tmp_path: Path) -> None:
    _with_problems(tmp_path)
    shutil.copyfile(WEBLAB, tmp_path / "weblab.xmi")
    (tmp_path / "sub").mkdir()
    shutil.copyfile(_only_warning(tmp_path), tmp_path / "sub" / "warning.xmi")
    code, sarif = _sarif(tmp_path, "problems.xmi", "weblab.xmi", "sub/warning.xmi")
    assert code == 1
    assert sarif["version"] == "2.1.0"
    assert "sarif" in sarif["$schema"] and sarif["$schema"].endswith(".json")
    (run,) = sarif["runs"]
    driver = run["tool"]["driver"]
    assert driver["name"] == "acordcs-gen"
    rules = driver["rules"]
    ids = [r["id"] for r in rules]
    assert len(ids) == len(set(ids))
    for rule in rules:
        assert rule["id"] in CODES
        assert rule["shortDescription"]["text"] == CODES[rule["id"]][1]
        assert rule["defaultConfiguration"]["level"] in ("error", "warning", "note")
    results = run["results"]
    assert results
    for res in results:
        assert rules[res["ruleIndex"]]["id"] == res["ruleId"]
        assert res["level"] in ("error", "warning", "note")
        assert res["message"]["text"]
        (location,) = res["locations"]
        physical = location["physicalLocation"]
        assert physical["artifactLocation"]["uri"] in ("problems.xmi", "sub/warning.xmi")
        if "region" in physical:
            assert physical["region"]["startLine"] >= 1
            assert physical["region"].get("startColumn", 1) >= 1
    assert {r["ruleId"] for r in results} == set(ids)  # every rule listed is used
    levels = {(r["ruleId"], r["level"]) for r in results}
    assert (
        ("T306", "error") in levels and ("T303", "warning") in levels and ("R206", "note") in levels
    )
    uris = {r["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] for r in results}
    assert uris == {"problems.xmi", "sub/warning.xmi"}


def test_sarif_of_a_clean_file_has_no_results() -> None:
    code, sarif = _sarif(ROOT, WEBLAB_REL)
    assert code == 0
    assert sarif["runs"][0]["results"] == []
    assert sarif["runs"][0]["tool"]["driver"]["rules"] == []


def test_fail_on_warning_vs_error(tmp_path: Path) -> None:
    warning = _only_warning(tmp_path)
    assert run_main(["validate", str(warning)]).code == 0
    assert run_main(["validate", "--fail-on", "error", str(warning)]).code == 0
    assert run_main(["validate", "--fail-on", "warning", str(warning)]).code == 1
    problems = _with_problems(tmp_path)
    assert run_main(["validate", str(problems)]).code == 1
    assert run_main(["validate", "--fail-on", "warning", str(problems)]).code == 1
    assert run_main(["validate", "--fail-on", "warning", str(WEBLAB)]).code == 0


def test_several_files(tmp_path: Path) -> None:
    both = run_main(["validate", str(WEBLAB), str(SMARTROOM)])
    assert both.code == 0
    assert [ln.split(":")[0] for ln in both.out.splitlines()] == [str(WEBLAB), str(SMARTROOM)]
    warning = _only_warning(tmp_path)
    mixed = run_main(["validate", "--fail-on", "warning", str(WEBLAB), str(warning)])
    assert mixed.code == 1
    assert " T303 " in mixed.out
    missing = tmp_path / "missing.xmi"
    unreadable = run_main(["validate", str(missing), str(WEBLAB)])
    assert unreadable.code == 2  # unreadable input wins over everything
    assert f"{WEBLAB}: 0 errors" in unreadable.out  # the other file is still checked
    data = json.loads(run_main(["validate", "--format", "json", str(WEBLAB), str(missing)]).out)
    assert [f["readable"] for f in data["files"]] == [True, False]


def test_sarif_uri_is_a_valid_uri_reference(tmp_path: Path, monkeypatch) -> None:
    folder = tmp_path / "my models"
    folder.mkdir()
    shutil.copyfile(_only_warning(tmp_path), folder / "web#1.xmi")
    monkeypatch.chdir(tmp_path)
    sarif = json.loads(run_main(["validate", "--format", "sarif", "my models/web#1.xmi"]).out)
    (result,) = sarif["runs"][0]["results"]
    assert result["locations"][0]["physicalLocation"]["artifactLocation"]["uri"] == (
        "my%20models/web%231.xmi"
    )


def test_sarif_gives_a_file_uri_for_an_absolute_path(weblab_text, tmp_path):
    text = weblab_text.replace('name="Locomotion"', 'name="native"')
    path = write_model(tmp_path, text)
    result = run_main(["validate", "--format", "sarif", str(path.resolve())])
    uris = {
        loc["physicalLocation"]["artifactLocation"]["uri"]
        for res in json.loads(result.out)["runs"][0]["results"]
        for loc in res["locations"]
    }
    assert uris == {path.resolve().as_uri()}


def test_a_name_cannot_inject_a_line_into_text_output(weblab_text, tmp_path):
    text = weblab_text.replace(
        'name="Locomotion"', 'name="Loco&#10;/etc/passwd:1: error X000: fake&#x202e;"'
    )
    result = run_main(["validate", str(write_model(tmp_path, text))])
    no_crash(result)
    assert not any(line.startswith("/etc/passwd") for line in result.out.splitlines())
    assert "\u202e" not in result.out and "\\u000a" in result.out
