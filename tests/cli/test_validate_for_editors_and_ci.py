"""``validate`` for editors and CI: lines VS Code's ``$gcc`` problem matcher makes clickable, real
columns in JSON, stable SARIF fingerprints, an invocation on every SARIF run, a help page per code,
``--quiet``, standard input, long values cut, "did you mean" for stereotypes, tags and values."""

from __future__ import annotations

import json
import re
import subprocess
import tomllib
from pathlib import Path

from acordcs.diagnostics import CODES, MAX_QUOTED, help_uri, shorten
from tests.support.toolchain import (
    ROOT,
    WEBLAB,
    entry_point,
    no_crash,
    replace,
    run_main,
    run_process,
    write_model,
)

# VS Code's built-in $gcc problem matcher (ms-vscode.cpptools, package.json "problemMatchers"),
# copied as it is: file 1, line 2, column 3, severity 4, message 5.
GCC = re.compile(r"^(.*?):(\d+):(\d*):?\s+(?:fatal\s+)?(warning|error):\s+(.*)$")


def _misspelt(weblab_text: str) -> str:
    """The README's example: a misspelt variable and term in StraightRules' first rule."""
    return replace(
        weblab_text,
        "smallNarrow: if cycleRate is small and angle is narrow",
        "smallNarrow: if cycleRat is small and angle is narow",
        count=2,
    )


def test_every_error_and_warning_line_is_matched_by_the_gcc_problem_matcher(weblab_text, tmp_path):
    text = _misspelt(weblab_text)
    text = replace(
        text,
        'trigger="event" frequency="" base_Element="BOUML_0x20182_4"',
        'trigger="event" frequency="" colour="red" base_Element="BOUML_0x20182_4"',
    )
    path = write_model(tmp_path, text)
    result = run_main(["validate", str(path)])
    no_crash(result)
    assert result.code == 1
    *lines, _summary = result.out.splitlines()
    matched = [GCC.match(line) for line in lines]
    assert all(matched), lines
    for m in matched:
        assert m[1] == str(path) and int(m[2]) >= 1 and int(m[3]) >= 1
        code = m[5].split(" ", 1)[0]
        assert str(CODES[code][0]) == m[4]
    assert {m[5].split(" ", 1)[0] for m in matched} >= {"L402", "L404", "T303"}
    l402 = next(m for m in matched if m[5].startswith("L402 "))
    assert (l402[2], l402[3]) == ("729", "1")  # the tag's line; the rule's column is in the text
    assert "column 17" in l402[5]


def test_the_gcc_pattern_is_the_one_vs_code_ships():
    """The pattern itself, on gcc's own output: a copy that matched nothing would prove nothing."""
    assert GCC.match("main.c:3:5: error: expected ';' before 'return'").groups() == (
        "main.c",
        "3",
        "5",
        "error",
        "expected ';' before 'return'",
    )
    assert not GCC.match("main.c:3: error L402: old acordcs format")


def test_json_columns_are_real_and_file_level_findings_have_no_position(weblab_text, tmp_path):
    path = write_model(tmp_path, _misspelt(weblab_text))
    data = json.loads(run_main(["validate", "--format", "json", str(path)]).out)
    for d in data["files"][0]["diagnostics"]:
        assert d["line"] >= 1 and d["column"] >= 1
    missing = json.loads(run_main(["validate", "--format", "json", str(tmp_path / "no.xmi")]).out)
    (d,) = missing["files"][0]["diagnostics"]
    assert d["code"] == "X101" and d["line"] is None and d["column"] is None


def _sarif(path: Path) -> tuple[int, dict]:
    result = run_main(["validate", "--format", "sarif", str(path)])
    no_crash(result)
    return result.code, json.loads(result.out)


def _engine(weblab_text: str, value: str) -> str:
    """SpeedLimiting's engine set to ``value`` in both of BOUML's places."""
    for old in ('engine="fuzzy" semantics', 'tag="ACORDCS:CtxPolicySet:engine" value="fuzzy"'):
        assert old in weblab_text
        weblab_text = weblab_text.replace(old, old.replace("fuzzy", value), 1)
    return weblab_text


def test_sarif_fingerprints_do_not_depend_on_the_message(weblab_text, tmp_path):
    """Two different wrong values of one tag: different messages, the same finding."""
    _, first = _sarif(write_model(tmp_path, _engine(weblab_text, "fuzy")))
    _, second = _sarif(write_model(tmp_path, _engine(weblab_text, "fuzzzzy")))
    (a,) = [r for r in first["runs"][0]["results"] if r["ruleId"] == "T305"]
    (b,) = [r for r in second["runs"][0]["results"] if r["ruleId"] == "T305"]
    assert a["message"]["text"] != b["message"]["text"]
    assert a["partialFingerprints"] == b["partialFingerprints"]
    assert "fuzy" not in json.dumps(a["partialFingerprints"])


def test_sarif_fingerprints_are_unique_within_a_run(weblab_text, tmp_path):
    """One rule naming the same unknown variable twice: two results, two fingerprints."""
    text = replace(
        weblab_text,
        "smallNarrow: if cycleRate is small and angle is narrow",
        "smallNarrow: if cycleRat is small and cycleRat is narrow",
        count=2,
    )
    _, sarif = _sarif(write_model(tmp_path, text))
    found = [r for r in sarif["runs"][0]["results"] if r["ruleId"] == "L402"]
    prints = [json.dumps(r["partialFingerprints"]) for r in found]
    assert len(prints) == 2 and len(set(prints)) == 2


def test_every_sarif_run_says_whether_it_succeeded(weblab_text, tmp_path):
    clean = _sarif(WEBLAB)
    failing = _sarif(write_model(tmp_path, _misspelt(weblab_text)))
    unreadable = _sarif(tmp_path / "missing.xmi")
    for code, sarif in (clean, failing, unreadable):
        (invocation,) = sarif["runs"][0]["invocations"]
        assert invocation["exitCode"] == code
        assert invocation["executionSuccessful"] is (code != 2)
    assert [c for c, _ in (clean, failing, unreadable)] == [0, 1, 2]


def test_sarif_help_uri_points_at_the_code_s_own_section(weblab_text, tmp_path):
    _, sarif = _sarif(write_model(tmp_path, _misspelt(weblab_text)))
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    anchors = set(re.findall(r"^### ([A-Z]\d{3})\b", page, flags=re.M))
    assert anchors == set(CODES)  # one section per code: its anchor is the code in lower case
    declared = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    docs = declared["project"]["urls"]["Documentation"]  # the one place the URL is written
    for rule in sarif["runs"][0]["tool"]["driver"]["rules"]:
        assert rule["helpUri"] == help_uri(rule["id"])
        assert rule["helpUri"] == f"{docs}/diagnostics.md#{rule['id'].lower()}"


def test_sarif_is_structurally_valid_2_1_0(weblab_text, tmp_path):
    """A structural check written from the SARIF 2.1.0 specification (sections 3.13 to 3.27): the
    OASIS JSON schema is not available offline here."""
    _, sarif = _sarif(write_model(tmp_path, _misspelt(weblab_text)))
    assert sarif["version"] == "2.1.0" and isinstance(sarif["runs"], list)
    for run in sarif["runs"]:
        driver = run["tool"]["driver"]
        assert isinstance(driver["name"], str) and driver["name"]
        for rule in driver["rules"]:
            assert re.match(r"^https?://", rule["helpUri"])  # 3.49.12: an absolute URI
        for inv in run["invocations"]:
            assert isinstance(inv["executionSuccessful"], bool)  # required, 3.20.14
        for res in run["results"]:
            assert isinstance(res["message"]["text"], str)
            assert res["level"] in ("none", "note", "warning", "error")
            assert all(isinstance(v, str) for v in res["partialFingerprints"].values())
            region = res["locations"][0]["physicalLocation"].get("region", {})
            assert all(region[k] >= 1 for k in region)


def test_quiet_prints_only_what_fails(weblab_text, tmp_path):
    text = replace(
        weblab_text,
        'trigger="event" frequency="" base_Element="BOUML_0x20182_4"',
        'trigger="event" frequency="" colour="red" base_Element="BOUML_0x20182_4"',
    )
    path = write_model(tmp_path, text)
    assert run_main(["validate", "--quiet", str(WEBLAB)]).out == ""
    warned = run_main(["validate", "--quiet", str(path)])
    assert (warned.code, warned.out) == (0, "")  # a warning does not reach --fail-on error
    failing = run_main(["validate", "-q", "--fail-on", "warning", str(path)])
    assert failing.code == 1
    assert [ln.split(": ")[2].split()[0] for ln in failing.out.splitlines()] == ["T303"]


def test_dash_reads_standard_input(weblab_text, tmp_path):
    done = subprocess.run(
        [*entry_point(), "validate", "-"],
        input=_misspelt(weblab_text),
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert done.returncode == 1, done.stderr
    assert done.stdout.splitlines()[0].startswith("<stdin>:729:1: error: L402 ")
    assert done.stdout.splitlines()[-1].startswith("<stdin>: 2 errors")
    bad = subprocess.run(
        [*entry_point(), "validate", "-"],
        input="not xml",
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    assert bad.returncode == 2 and "<stdin>:1:1: error: X108" in bad.stdout
    twice = run_main(["validate", "-", "-"])
    assert twice.code == 2 and "once" in twice.err


def test_a_long_value_is_cut_with_an_ellipsis(weblab_text, tmp_path):
    """R205 quotes a tag's two values: the whole rule list of StraightRules, twice."""
    text = replace(
        weblab_text, 'Rule="smallNarrow: if cycleRate', 'Rule="smallNarrow: if  cycleRate'
    )
    result = run_main(["validate", str(write_model(tmp_path, text))])
    (line,) = [ln for ln in result.out.splitlines() if ": R205 " in ln]
    assert "\u2026" in line and len(line) < 600
    assert shorten("x " + repr("a" * 500)) == "x '" + "a" * (MAX_QUOTED - 1) + "\u2026'"
    assert shorten("short 'value'") == "short 'value'"


def test_did_you_mean_for_stereotypes_tags_and_values(weblab_text, tmp_path):
    text = replace(
        weblab_text,
        '<ACORDCS:CtxPolicy xmi:id="BOUML_STELT_0x20302_4"',
        '<ACORDCS:CtxPolcy xmi:id="BOUML_STELT_0x20302_4"',
    )
    text = replace(text, 'trigger="periodic" frequency="0.5"', 'triger="periodic" frequency="0.5"')
    text = _engine(text, "fuzy")
    result = run_main(["validate", str(write_model(tmp_path, text))])
    no_crash(result)
    assert "no stereotype 'CtxPolcy' (did you mean 'CtxPolicy'?)" in result.out
    assert "no tag 'triger' (did you mean 'trigger'?)" in result.out
    assert "is 'fuzy' (did you mean 'fuzzy'?)" in result.out


def test_the_installed_command_prints_the_same_lines(weblab_text, tmp_path):
    path = write_model(tmp_path, _misspelt(weblab_text))
    assert run_process(["validate", str(path)]).out == run_main(["validate", str(path)]).out
