"""Regressions for what a review of the toolchain found (each test failed before its fix)."""

from __future__ import annotations

import re
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.model.checks.tags import shape_problem
from acordcs.rules import Name, TermDef
from acordcs.runtime.fuzzy.membership import make_membership
from acordcs.runtime.rule_engine import RuleError
from tests.support.toolchain import WEBLAB, no_crash, replace, run_main

TEXT = WEBLAB.read_text(encoding="utf-8")


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "model.xmi"
    path.write_text(text, encoding="utf-8")
    return path


def _codes(out: str) -> set[str]:
    return set(re.findall(r": (?:error|warning|info) ([A-Z]\d{3}):", out))


def test_the_profile_is_known_by_its_namespace_not_its_prefix(tmp_path):
    text = TEXT.replace("xmlns:ACORDCS=", "xmlns:acs=").replace("<ACORDCS:", "<acs:")
    text = re.sub(r'\s*<stereotype name="ACORDCS:[^"]*"/>', "", text)  # root-level copies only
    result = run_main(["inspect", "--format", "json", str(_write(tmp_path, text))])
    no_crash(result)
    assert '"CtxComponent": [' in result.out.replace("\n", "").replace("  ", "")
    assert '"acs:' not in result.out
    assert run_main(["validate", str(tmp_path / "model.xmi")]).code == 0


def test_a_number_too_long_for_int_is_a_syntax_error_and_the_other_rules_are_still_checked(
    tmp_path,
):
    text = replace(
        TEXT, "Control.speed == 0 then", "Control.speed == " + "9" * 5000 + " then", count=2
    )
    text = replace(
        text,
        "if cycleRate is small and angle is narrow",
        "if cycleRat is small and angle is narrow",
        count=2,
    )
    result = run_main(["validate", str(_write(tmp_path, text))])
    no_crash(result)
    assert _codes(result.out) == {"L401", "L402"}, result.out
    assert "Z901" not in result.out


def test_a_name_cannot_inject_a_line_into_text_output(tmp_path):
    text = TEXT.replace(
        'name="Locomotion"', 'name="Loco&#10;/etc/passwd:1: error X000: fake&#x202e;"'
    )
    result = run_main(["validate", str(_write(tmp_path, text))])
    no_crash(result)
    assert not any(line.startswith("/etc/passwd") for line in result.out.splitlines())
    assert "\u202e" not in result.out and "\\u000a" in result.out


def test_an_unknown_plain_tag_on_an_acordcs_element_is_reported(tmp_path):
    text = TEXT.replace(
        '<stereotype name="ACORDCS:CtxMonitor"/>',
        '<stereotype name="ACORDCS:CtxMonitor"/><taggedValue tag="frequncy" value="-5"/>',
        1,  # the first monitor only
    )
    result = run_main(["validate", "--fail-on", "warning", str(_write(tmp_path, text))])
    assert "T303" in _codes(result.out) and "'frequncy'" in result.out
    assert result.code == 1


def test_an_application_to_a_missing_element_fails_validation(tmp_path):
    text = TEXT.replace(
        "</xmi:XMI>", '<ACORDCS:CtxComponent xmi:id="APPX" base_Element="NOPE"/></xmi:XMI>'
    )
    result = run_main(["validate", str(_write(tmp_path, text))])
    assert _codes(result.out) == {"R204"} and result.code == 1


def test_a_missing_end_tag_is_refused_not_recovered(tmp_path):
    text = TEXT.replace("</packagedElement>", "", 1)
    result = run_main(["validate", str(_write(tmp_path, text))])
    no_crash(result)
    assert _codes(result.out) == {"X108"} and result.code == 2, result.out


def test_a_control_character_is_not_called_an_encoding_problem(tmp_path):
    text = TEXT.replace('name="Locomotion"', 'name="Loco\x01motion"', 1)
    result = run_main(["validate", str(_write(tmp_path, text))])
    assert _codes(result.out) == {"X108"} and "control character" in result.out


def test_tag_numbers_use_the_xsd_lexical_form(tmp_path):
    text = TEXT.replace('frequency="1" base_Element', 'frequency="1_0" base_Element')
    text = text.replace('CtxMonitor:frequency" value="1"', 'CtxMonitor:frequency" value="1_0"')
    result = run_main(["validate", str(_write(tmp_path, text))])
    assert "T304" in _codes(result.out), result.out


def test_inspect_keeps_two_containers_of_the_same_name(tmp_path):
    text = TEXT.replace('name="WebLabSide"', 'name="UserSide"')
    result = run_main(["inspect", str(_write(tmp_path, text))])
    assert result.out.count("container UserSide") == 2, result.out


NUMBERS = st.one_of(
    st.floats(min_value=-100, max_value=100, allow_nan=False),
    st.sampled_from([0.0, 1.0, float("inf"), float("nan")]),
)
SHAPES = {"trapezoid": 4, "triangle": 3, "gaussian": 2, "bell": 3, "sigmoid": 2, "singleton": 1}


@st.composite
def term_defs(draw):
    shape = draw(st.sampled_from([*SHAPES, "points"]))
    if shape == "points":
        xs = sorted(draw(st.lists(st.sampled_from([0.0, 1.0, 2.0, 3.0]), min_size=2, max_size=5)))
        ys = draw(
            st.lists(st.sampled_from([0.0, 0.5, 1.0, 1.5]), min_size=len(xs), max_size=len(xs))
        )
        params = tuple(v for pair in zip(xs, ys, strict=True) for v in pair)
    else:
        params = tuple(draw(st.lists(NUMBERS, min_size=SHAPES[shape], max_size=SHAPES[shape])))
    return TermDef(Name("t", 1), shape, params)


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(term_defs())
def test_the_validator_accepts_exactly_the_terms_the_fuzzy_engine_accepts(term):
    try:
        make_membership(term.shape, term.parameters)
        engine_ok = True
    except RuleError:
        engine_ok = False
    assert (shape_problem(term) is None) == engine_ok, (term, shape_problem(term))


def test_an_unknown_uml_element_in_xmi_1_2_is_reported(tmp_path):
    from tests.support.toolchain import XMI_SAMPLES

    text = (XMI_SAMPLES / "TPB3D__tpb3d.xmi").read_text(encoding="utf-8")
    start = text.index('<UML:Class name="Panel"')
    end = text.index("</UML:Class>", start)
    text = text[:start] + "<UML:Klass" + text[start + 10 : end] + "</UML:Klass>" + text[end + 12 :]
    result = run_main(["validate", str(_write(tmp_path, text))])
    no_crash(result)
    assert "R201" in _codes(result.out) and "did you mean UML:Class?" in result.out
    assert result.code == 1


def test_sarif_gives_a_file_uri_for_an_absolute_path(tmp_path):
    import json

    text = TEXT.replace('name="Locomotion"', 'name="native"')
    path = _write(tmp_path, text)
    result = run_main(["validate", "--format", "sarif", str(path.resolve())])
    uris = {
        loc["physicalLocation"]["artifactLocation"]["uri"]
        for res in json.loads(result.out)["runs"][0]["results"]
        for loc in res["locations"]
    }
    assert uris == {path.resolve().as_uri()}
