"""Causes first, consequences once (issue 30): a finding another reported finding explains (a
stereotype not read, a reference to an id the file lacks) is not printed on its own; the cause
says how many findings it stands for and what they are about, in the BOUML form (a copy of the
WebLab model) and in the Papyrus form (a copy of samples/papyrus/ventilation.uml), and a guess of
the misspelt id is told. What no reported cause explains is printed as before."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from acordcs.diagnostics import Severity, diagnostic
from acordcs.model.causes import settled
from tests.support.generator import weblab_variant
from tests.support.toolchain import ROOT, codes_in, no_crash, replace, run_main

VENTILATION = ROOT / "samples" / "papyrus" / "ventilation.uml"
PROFILE = VENTILATION.parent / "ACORDCS.profile.uml"


def _ventilation(tmp_path: Path, *edits: tuple[str, str]) -> Path:
    text = VENTILATION.read_text(encoding="utf-8")
    for old, new in edits:
        text = replace(text, old, new)
    model = tmp_path / "ventilation.uml"
    model.write_text(text, encoding="utf-8")
    shutil.copy(PROFILE, tmp_path / PROFILE.name)
    return model


def _validate(model: Path):
    result = run_main(["validate", str(model)])
    no_crash(result)
    found = [line for line in result.out.splitlines() if re.search(r": (error|warning): ", line)]
    return result, found


# The WebLab's <<CtxVariable>> of Control.cycleRate applied to the class Control instead, in both
# of BOUML's places (the root-level application and the element's extension).
_CYCLE_RATE_EXTENSION = (
    '\n\t\t\t\t\t\t\t<xmi:Extension extender="Bouml">\n'
    '\t\t\t\t\t\t\t\t<stereotype name="ACORDCS:CtxVariable"/>\n'
    '\t\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxVariable:min" value="0"/>\n'
    '\t\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxVariable:max" value="3"/>\n'
    '\t\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxVariable:terms" value="small := trape 0 0 0.8 '
    '1.2; medium := trian 0.9 1.4 1.9; large := trape 1.5 2 3 3"/>\n'
    "\t\t\t\t\t\t\t</xmi:Extension>"
)
_CYCLE_RATE = (
    '<ownedAttribute xmi:type="uml:Property" name="cycleRate" xmi:id="BOUML_0x20502_1" '
    'visibility="private">\n\t\t\t\t\t\t\t<type xmi:type="uml:Class" xmi:idref="BOUML_datatype_0"/>'
)
_CONTROL_MONITOR = '<stereotype name="ACORDCS:CtxMonitor"/>\n\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxMonitor:acquisition" value="intercept"/>'
VARIABLE_ON_THE_CLASS = (
    ('base_Element="BOUML_0x20502_1"/>', 'base_Element="BOUML_0x20002_4"/>'),
    (_CYCLE_RATE + _CYCLE_RATE_EXTENSION, _CYCLE_RATE),
    (
        _CONTROL_MONITOR,
        '<stereotype name="ACORDCS:CtxVariable"/>\n\t\t\t\t\t\t\t'
        '<taggedValue tag="ACORDCS:CtxVariable:min" value="0"/>\n\t\t\t\t\t\t\t' + _CONTROL_MONITOR,
    ),
)


def test_a_variable_stereotype_on_the_class_stands_for_the_rules_using_its_attribute_bouml(
    tmp_path: Path,
) -> None:
    # before: 21 x L408 ('cycleRate' is not a linguistic variable) at the rules, then the T301 at
    # the stereotype application near the file's end
    result, found = _validate(weblab_variant(tmp_path, *VARIABLE_ON_THE_CLASS))
    assert result.code == 1 and codes_in(result.out) == {"T301"}, result.out
    (line,) = found
    assert (
        "error: T301 <<CtxVariable>> applies to Property, not to a Class; move the stereotype to "
        "the right element (an attribute of 'Control'); 21 findings (L408) about 'cycleRate' are "
        "checked once this is fixed "
        "[WebLab::ContextAwareNavigation::Adaptation::Control (BOUML_0x20002_4)]"
    ) in line
    assert re.match(rf"{re.escape(str(tmp_path))}/weblab\.xmi:\d+:1: ", line)


def test_a_variable_stereotype_on_the_class_stands_for_the_rules_using_its_attribute_papyrus(
    tmp_path: Path,
) -> None:
    model = _ventilation(tmp_path, ('base_Property="_Fan.speed"', 'base_Class="_Fan"'))
    result, found = _validate(model)
    assert codes_in(result.out) == {"T301"}, result.out
    (line,) = found
    assert line.endswith(
        "error: T301 <<CtxVariable>> applies to Property, not to a Class; move the stereotype to "
        "the right element (an attribute of 'Fan'); 3 findings (L408) about 'Fan.speed' are "
        "checked once this is fixed "
        "[Components::Fan (_Fan)]"
    ), line


def test_a_component_stereotype_on_an_attribute_stands_for_what_its_component_lacks(
    tmp_path: Path,
) -> None:
    # before: A511, A517 (FanPort belongs to no component), 7 x L402/L406 ('no element named
    # 'Fan''), around the T301
    model = _ventilation(
        tmp_path,
        (
            '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Class="_Fan"',
            '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Property="_Fan.speed"',
        ),
    )
    result, found = _validate(model)
    assert codes_in(result.out) == {"T301"}, result.out
    (line,) = found
    assert (
        "T301 <<CtxComponent>> applies to Class or Component, not to a Property; move the "
        "stereotype to the right element (perhaps 'Fan', the Class it belongs to); 10 findings "
        "(A511, A517, L402, L406) about 'FanPort', "
        "'FanLink', 'Fan.speed' and 3 more are checked once this is fixed "
        "[Components::Fan::speed (_Fan.speed)]"
    ) in line


def test_a_misspelt_id_in_two_relations_is_told_with_what_it_stands_for(tmp_path: Path) -> None:
    # before: R202, R202, A506 (Fan not deployed), 3 x L402 ('Fan' not in the scope of Airflow)
    model = _ventilation(
        tmp_path,
        (
            'name="hostsFan" client="_Plant" supplier="_Fan"',
            'name="hostsFan" client="_Plant" supplier="_Fna"',
        ),
        (
            'name="adaptsFan" client="_Airflow" supplier="_Fan"',
            'name="adaptsFan" client="_Airflow" supplier="_Fna"',
        ),
    )
    result, found = _validate(model)
    assert [line.split(": ")[2][:4] for line in found] == ["R202", "R202"], result.out
    hosts, adapts = found
    meant = "which no element of the file has (did you mean '_Fan', <<CtxComponent>> 'Fan'?)"
    assert meant in hosts and meant in adapts
    assert hosts.endswith(
        "; 1 finding (A506) about 'Fan' is checked once this is fixed [Deployment::hostsFan (_Fna)]"
    ), hosts
    assert adapts.endswith(
        "; 3 findings (L402) about 'Fan.speed' are checked once this is fixed "
        "[Adaptation::adaptsFan (_Fna)]"
    ), adapts
    assert "2 errors, 0 warnings" in result.out


def test_a_misspelt_feeds_client_stands_for_the_monitor_and_the_rules_reading_it(
    tmp_path: Path,
) -> None:
    model = _ventilation(
        tmp_path,
        ('name="feedsAirflow" client="_AirSensor"', 'name="feedsAirflow" client="_AirSensr"'),
    )
    _result, found = _validate(model)
    (line,) = found
    assert "(did you mean '_AirSensor', <<CtxMonitor>> 'AirSensor'?)" in line
    assert (
        "; 6 findings (A505, L402) about 'AirSensor', 'co2', 'humidity' are checked once this is "
        "fixed [Adaptation::feedsAirflow (_AirSensr)]"
    ) in line


def test_a_misspelt_association_end_type_stands_for_the_undeployed_component_bouml(
    tmp_path: Path,
) -> None:
    end = (
        'name="vision" xmi:id="BOUML_0x20802_0" visibility="protected" '
        'association="BOUML_ASSOC_0x20802_0" aggregation="none">\n\t\t\t\t\t\t\t'
        '<type xmi:type="uml:Class" xmi:idref="BOUML_0x1f502_4"/>'
    )
    model = weblab_variant(tmp_path, (end, end.replace("0x1f502_4", "0x1f5O2_4")))
    _result, found = _validate(model)
    (line,) = found
    assert ": error: R202 type of 'vision' refers to id 'BOUML_0x1f5O2_4'" in line
    assert "(did you mean 'BOUML_0x1f502_4', <<CtxComponent>> 'Vision'?)" in line
    assert "; 1 finding (A506) about 'Vision' is checked once this is fixed [" in line


def test_a_stereotype_applied_to_a_misspelt_id_stands_for_the_rules_naming_its_element(
    tmp_path: Path,
) -> None:
    model = _ventilation(tmp_path, ('base_Class="_AirSensor"', 'base_Class="_AirSensr"'))
    _result, found = _validate(model)
    (line,) = found
    assert line.endswith(
        "error: R204 stereotype ACORDCS:CtxMonitor is applied to id '_AirSensr', which no element "
        "has (did you mean '_AirSensor', Class 'AirSensor'?); the application is ignored; 5 "
        "findings (L402) about 'co2', 'humidity' are checked once this is fixed [(_AirSensr)]"
    ), line


def test_a_dangling_id_like_no_element_hides_nothing(tmp_path: Path) -> None:
    """An id that misspells no element (one deleted, or of another file): its consequences are
    printed, after it, and it counts none."""
    model = _ventilation(
        tmp_path,
        (
            'name="hostsFan" client="_Plant" supplier="_Fan"',
            'name="hostsFan" client="_Plant" supplier="_Ventilator"',
        ),
    )
    result, found = _validate(model)
    assert [line.split(": ")[2][:4] for line in found] == ["R202", "A506"], result.out
    assert "checked once this is fixed" not in result.out
    assert "did you mean" not in found[0]


def test_a_finding_with_a_cause_not_reported_is_printed(tmp_path: Path) -> None:
    """The WebLab model with one rule naming an attribute no element has: an L402 as always."""
    rule = "smallNarrow: if cycleRate is small and angle is narrow"
    model = weblab_variant(tmp_path, (rule, rule.replace("cycleRate", "cycleRat"), 2))
    result, found = _validate(model)
    assert codes_in(result.out) == {"L402"} and len(found) == 1, result.out


def test_the_output_is_the_same_every_run(tmp_path: Path) -> None:
    model = _ventilation(
        tmp_path,
        (
            '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Class="_Fan"',
            '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Property="_Fan.speed"',
        ),
        ('name="feedsAirflow" client="_AirSensor"', 'name="feedsAirflow" client="_AirSensr"'),
    )
    runs = {run_main(["validate", "--format", "json", str(model)]).out for _ in range(3)}
    assert len(runs) == 1


# ------------------------------------------------------------------------- the fold, by itself
def _d(code: str, line: int, *, severity=None, because=(), explains=(), element="E::x"):
    return diagnostic(
        code,
        f"{code} message",
        file="m.xmi",
        line=line,
        element=element,
        xmi_id=f"id{line}",
        subject=f"r:{code.lower()}",
        severity=severity,
        because=because,
        explains=explains,
    )


def test_a_cause_further_down_leads_and_counts_what_it_explains() -> None:
    found = [
        _d("L408", 10, because=("k",)),
        _d("L408", 11, because=("k",)),
        _d("A506", 12),
        _d("T301", 90, explains=("k",)),
    ]
    out = settled(found)
    assert [d.code for d in out] == ["A506", "T301"]
    assert out[1].message == (
        "T301 message; 2 findings (L408) about 'l408' are checked once this is fixed"
    )
    assert [d.message for d in found[:3]] == ["L408 message", "L408 message", "A506 message"]


def test_a_warning_never_hides_an_error_it_explains_which_follows_it() -> None:
    cause = _d("R202", 90, severity=Severity.WARNING, explains=("k",))
    error = _d("A506", 10, because=("k",))
    out = settled([error, _d("A509", 50), cause])
    assert [d.code for d in out] == ["A509", "R202", "A506"]  # the consequence after its cause
    assert out[1].message == "R202 message"


def test_a_chain_of_causes_counts_at_its_root_and_a_circle_hides_nothing() -> None:
    root = _d("R204", 5, explains=("a",))
    middle = _d("T301", 6, because=("a",), explains=("b",))
    leaf = _d("L408", 7, because=("b",))
    out = settled([leaf, middle, root])
    assert [d.code for d in out] == ["R204"]
    assert "2 findings (L408, T301)" in out[0].message
    first = _d("T301", 1, because=("y",), explains=("x",))
    second = _d("T302", 2, because=("x",), explains=("y",))
    assert [d.code for d in settled([second, first])] == ["T301", "T302"]


@pytest.mark.parametrize("n", [4, 5])
def test_a_cause_names_three_subjects_and_counts_the_rest(n: int) -> None:
    hidden = [
        diagnostic("L402", "m", file="f", line=i, subject=f"r:v{i}", because=("k",))
        for i in range(1, n + 1)
    ]
    (cause,) = settled([*hidden, _d("T302", 99, explains=("k",))])
    assert f"{n} findings (L402) about 'v1', 'v2', 'v3' and {n - 3} more are checked" in (
        cause.message
    )


# ----------------------------------------------------------------------- the codes page's examples
def _shown(section: str | None) -> list[str]:
    """The ``ventilation.uml:`` lines docs/diagnostics.md shows in the section of ``section`` (a
    code), or before the first code's section (None)."""
    page = (ROOT / "docs" / "diagnostics.md").read_text(encoding="utf-8")
    text = page.split("\n### ", 1)[0] if section is None else page.split(f"{{#{section}}}", 1)[1]
    text = text.split("\n### ", 1)[0]
    return re.findall(r"^ventilation\.uml:\d+:.*$", text, flags=re.M)


@pytest.mark.parametrize(
    ("section", "edits"),
    [
        (
            None,
            (
                (
                    'name="hostsFan" client="_Plant" supplier="_Fan"',
                    'name="hostsFan" client="_Plant" supplier="_Fna"',
                ),
                (
                    'name="adaptsFan" client="_Airflow" supplier="_Fan"',
                    'name="adaptsFan" client="_Airflow" supplier="_Fna"',
                ),
            ),
        ),
        ("t301", (('base_Property="_Fan.speed"', 'base_Class="_Fan"'),)),
        ("r204", (('base_Class="_AirSensor"', 'base_Class="_AirSensr"'),)),
    ],
    ids=["causes-first", "t301", "r204"],
)
def test_the_codes_page_shows_this_output(tmp_path: Path, monkeypatch, section, edits) -> None:
    shown = _shown(section)
    assert shown, section
    model = _ventilation(tmp_path, *edits)
    monkeypatch.chdir(tmp_path)
    out = run_main(["validate", model.name]).out.splitlines()
    assert [line for line in out if re.match(r"ventilation\.uml:\d+:", line)] == shown
