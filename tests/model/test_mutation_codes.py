"""Mutations of the WebLab sample: each yields exactly the expected diagnostic codes and nothing else.

Every mutation edits a copy of samples/weblab/weblab.xmi as text. A tag lives in two places in a BOUML
export (the root-level stereotype application and the element's ``xmi:Extension``), and a mutation of a
tag edits both, so that only the intended problem is left.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from acordcs.cli.summary import summarize
from acordcs.diagnostics import Severity
from acordcs.model.reading import read_model
from tests.support.toolchain import (
    WEBLAB,
    codes_in,
    no_crash,
    remove_regex,
    replace,
    replace_in_element,
    run_main,
    write_model,
)

FIRST_RULE = (
    "smallNarrow: if cycleRate is small and angle is narrow then Locomotion.maxSpeed is slow"
)
NUM_USERS_TERMS = "low := trape 0 0 1 3; medium := trian 2 4 7; high := trape 5 8 10 10"


def rename_attribute(text: str, old: str, new: str) -> str:
    return replace(text, f'name="{old}" xmi:id=', f'name="{new}" xmi:id=')


def rename_class(text: str, old: str, new: str) -> str:
    return replace(text, f'name="{old}" xmi:id=', f'name="{new}" xmi:id=')


def set_tag(text: str, element: str, stelt: str, tag: str, old: str, new: str) -> str:
    """Change ``tag`` of the stereotype application on class ``element`` in both places."""
    text = replace_in_element(text, element, f':{tag}" value="{old}"/>', f':{tag}" value="{new}"/>')
    root_app = re.search(rf'<ACORDCS:\w+ xmi:id="{stelt}"[^>]*/>', text)
    assert root_app, stelt
    edited = replace(root_app.group(0), f' {tag}="{old}"', f' {tag}="{new}"')
    return text[: root_app.start()] + edited + text[root_app.end() :]


def remove_association(text: str, end_id: str, assoc_id: str) -> str:
    """Remove a navigable association end (an ownedAttribute) and its uml:Association."""
    text = remove_regex(
        text, rf'\s*<ownedAttribute [^>]*xmi:id="{end_id}"[^>]*>.*?</ownedAttribute>'
    )
    return remove_regex(
        text,
        rf'\s*<packagedElement xmi:type="uml:Association" xmi:id="{assoc_id}".*?</packagedElement>',
    )


def add_application(text: str, element: str, base_id: str, stereotype: str, tags: dict) -> str:
    """Apply ACORDCS:``stereotype`` to class ``element`` in both places."""
    ext = (
        f'\n\t\t\t\t\t\t<xmi:Extension extender="Bouml">\n\t\t\t\t\t\t\t<stereotype name="ACORDCS:{stereotype}"/>'
        + "".join(
            f'\n\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:{stereotype}:{k}" value="{v}"/>'
            for k, v in tags.items()
        )
        + "\n\t\t\t\t\t\t</xmi:Extension>"
    )
    head = re.search(rf'<packagedElement xmi:type="uml:Class" name="{element}"[^>]*>', text)
    assert head
    text = text[: head.end()] + ext + text[head.end() :]
    attrs = "".join(f' {k}="{v}"' for k, v in tags.items())
    root = f'\t<ACORDCS:{stereotype} xmi:id="BOUML_STELT_TEST"{attrs} base_Element="{base_id}"/>\n'
    return replace(text, "</xmi:XMI>", root + "</xmi:XMI>")


NEW_ATTRIBUTE = (
    '<ownedAttribute xmi:type="uml:Property" name="numUsers" xmi:id="BOUML_0x3f002_1" '
    'visibility="private">\n\t\t\t\t\t\t\t<type xmi:type="uml:Class" xmi:idref="BOUML_datatype_0"/>'
    "\n\t\t\t\t\t\t</ownedAttribute>\n\t\t\t\t\t\t"
)


@dataclass
class Mutation:
    id: str
    edit: Callable[[str], str]
    codes: set[str]
    elements: set[str]  # names that must appear in the element of the expected diagnostics
    message: list[str] = field(default_factory=list)  # fragments of some expected message


MUTATIONS = [
    Mutation(
        "operation-named-like-the-component-api",
        lambda t: replace(t, 'name="odometry" xmi:id=', 'name="port" xmi:id='),
        {"N604"},
        {"Locomotion::port"},
        ["'port' of Locomotion is also a member of every component", "rename the operation"],
    ),
    Mutation(
        "operation-named-like-a-port-handler",
        lambda t: replace(t, 'name="grab" xmi:id=', 'name="on_VisionPort" xmi:id='),
        {"N605"},
        {"Vision::on_VisionPort"},
        ["becomes the handler of port 'VisionPort'"],
    ),
    Mutation(
        "element-names-differing-only-in-case",
        lambda t: rename_class(t, "Navigator", "vision"),
        {"N606"},
        {"vision"},
        ["'Vision', 'vision' differ only in letter case"],
    ),
    Mutation(
        "misspelt-rule-variable",
        lambda t: replace(
            t, FIRST_RULE, FIRST_RULE.replace("if cycleRate is", "if cycleRat is"), count=2
        ),
        {"L402"},
        {"StraightRules"},
        ["'cycleRat'", "did you mean 'cycleRate'"],
    ),
    Mutation(
        "undefined-term",
        lambda t: replace(
            t, FIRST_RULE, FIRST_RULE.replace("angle is narrow", "angle is narow"), count=2
        ),
        {"L404"},
        {"StraightRules"},
        ["'narow'", "did you mean 'narrow'"],
    ),
    Mutation(
        "wrong-kind-port-connection",
        lambda t: set_tag(
            t, "NavVisionPort", "BOUML_STELT_0x1fa02_4", "kind", "synchronous", "asynchronous"
        ),
        {"A502"},
        {"VisionLink"},
        ["asynchronous", "synchronous"],
    ),
    Mutation(
        "provided-provided-connection",
        lambda t: set_tag(
            t, "NavVisionPort", "BOUML_STELT_0x1fa02_4", "role", "required", "provided"
        ),
        {"A501"},
        {"VisionLink"},
        ["provided and a required"],
    ),
    Mutation(
        "zero-frequency",
        lambda t: set_tag(t, "Usage", "BOUML_STELT_0x20102_4", "frequency", "1", "0"),
        {"T306"},
        {"Usage"},
        ["positive"],
    ),
    Mutation(
        "undeployed-component",
        lambda t: remove_association(t, "BOUML_0x20802_0", "BOUML_ASSOC_0x20802_0"),
        {"A506"},
        {"Vision"},
        ["'Vision' is not deployed"],
    ),
    Mutation(
        "java-keyword-attribute",
        lambda t: rename_attribute(t, "heading", "native"),
        {"N602"},
        {"Telemetry::native"},
        ["'native' is a reserved word in Java"],
    ),
    Mutation(
        "java-keyword-class",
        lambda t: rename_class(t, "Vision", "synchronized"),
        {"N602"},
        {"synchronized"},
        ["'synchronized' is a reserved word in Java"],
    ),
    Mutation(
        "python-keyword-attribute",
        lambda t: rename_attribute(t, "heading", "lambda"),
        {"N602"},
        {"Telemetry::lambda"},
        ["'lambda' is a reserved word in Python"],
    ),
    Mutation(
        "invalid-identifier",
        lambda t: rename_attribute(t, "heading", "heading-deg"),
        {"N601"},
        {"Telemetry::heading-deg"},
        ["not an identifier"],
    ),
    Mutation(
        "ambiguous-unqualified-variable",
        lambda t: replace_in_element(
            t,
            "Control",
            '<ownedAttribute xmi:type="uml:Property" name="speedLimiting"',
            NEW_ATTRIBUTE + '<ownedAttribute xmi:type="uml:Property" name="speedLimiting"',
        ),
        {"L403"},
        {"FrameRateRules"},
        ["ambiguous", "Control.numUsers", "Usage.numUsers"],
    ),
    Mutation(
        "missing-operation",
        lambda t: replace(t, "Recovery.recover()", "Recovery.recovr()", count=2),
        {"L406"},
        {"RecoveryRules"},
        ["'Recovery.recovr'", "did you mean 'recover'"],
    ),
    Mutation(
        "wrong-arity",
        lambda t: replace(t, "Recovery.askUser()", "Recovery.askUser(1)", count=2),
        {"L407"},
        {"RecoveryRules"},
        ["takes 0 argument(s)", "given 1"],
    ),
    Mutation(
        "fuzzy-output-as-input",
        lambda t: replace(
            t,
            FIRST_RULE,
            FIRST_RULE.replace("angle is narrow", "Locomotion.maxSpeed is slow"),
            count=2,
        ),
        {"L405"},
        {"StraightRules"},
        ["'Locomotion.maxSpeed' is an output", "SpeedLimiting"],
    ),
    Mutation(
        "rule-syntax-error",
        lambda t: replace(
            t, FIRST_RULE, FIRST_RULE.replace("angle is narrow", "angle narrow"), count=2
        ),
        {"L401"},
        {"StraightRules"},
        # the rule text is "smallNarrow: if cycleRate is small and angle narrow then ...":
        # the unexpected word 'narrow' starts at column 46
        ["column 46", "'narrow'"],
    ),
    Mutation(
        "monitor-feeds-nothing",
        lambda t: remove_association(t, "BOUML_0x20382_0", "BOUML_ASSOC_0x20382_0"),
        # Recovering's rules read Telemetry.progress, out of the set's scope once it is not fed
        {"A505", "L402"},
        {"Telemetry", "RecoveryRules"},
        ["'Telemetry' feeds no policy set", "variable 'Telemetry.progress'"],
    ),
    Mutation(
        "stereotype-on-wrong-metaclass",
        lambda t: add_application(
            t,
            "Image",
            "BOUML_0x1f402_4",
            "CtxVariable",
            {"min": "0", "max": "1", "terms": "low := trape 0 0 0.5 1"},
        ),
        {"T301"},
        {"Image"},
        ["<<CtxVariable>> applies to Property", "not to a Class"],
    ),
    Mutation(
        "unknown-acordcs-stereotype",
        lambda t: add_application(t, "Image", "BOUML_0x1f402_4", "CtxSensor", {}),
        {"T302"},
        {"Image"},
        ["no stereotype 'CtxSensor'"],
    ),
    Mutation(
        "unknown-tag",
        lambda t: replace(
            replace_in_element(
                t,
                "Usage",
                '<taggedValue tag="ACORDCS:CtxMonitor:frequency" value="1"/>',
                '<taggedValue tag="ACORDCS:CtxMonitor:frequency" value="1"/>'
                '<taggedValue tag="ACORDCS:CtxMonitor:priority" value="high"/>',
            ),
            'frequency="1" base_Element="BOUML_0x20102_4"',
            'frequency="1" priority="high" base_Element="BOUML_0x20102_4"',
        ),
        {"T303"},
        {"Usage"},
        ["no tag 'priority'"],
    ),
    Mutation(
        "enum-tag-out-of-set",
        lambda t: set_tag(t, "Vision", "BOUML_STELT_0x1f502_4", "language", "python", "cobol"),
        {"T305"},
        {"Vision"},
        ["'cobol'", "python", "java"],
    ),
    Mutation(
        "term-outside-range",
        lambda t: replace(
            t,
            NUM_USERS_TERMS,
            NUM_USERS_TERMS.replace("high := trape 5 8 10 10", "high := trape 5 8 10 12"),
            count=2,
        ),
        {"T308"},
        {"Usage::numUsers"},
        ["'high'", "12", "[0, 10]"],
    ),
    Mutation(
        "terms-leave-gap",
        lambda t: replace(
            t,
            NUM_USERS_TERMS,
            NUM_USERS_TERMS.replace("medium := trian 2 4 7", "medium := trian 4 5 6"),
            count=2,
        ),
        {"T309"},
        {"Usage::numUsers"},
        ["[3, 4]"],
    ),
    Mutation(
        "inverted-trapezoid",
        lambda t: replace(
            t,
            NUM_USERS_TERMS,
            NUM_USERS_TERMS.replace("high := trape 5 8 10 10", "high := trape 8 5 10 10"),
            count=2,
        ),
        {"T311"},
        {"Usage::numUsers"},
        ["'high'", "must not decrease"],
    ),
]


def _findings(path: Path):
    reading = read_model(str(path))
    return [d for d in reading.diagnostics if d.severity >= Severity.WARNING]


def test_unmutated_sample_is_clean() -> None:
    """The baseline every mutation is measured against."""
    assert read_model(str(WEBLAB)).diagnostics == []


@pytest.mark.parametrize("mutation", MUTATIONS, ids=[m.id for m in MUTATIONS])
def test_mutation_gives_exactly_its_codes(
    mutation: Mutation, weblab_text: str, tmp_path: Path
) -> None:
    target = tmp_path / "weblab.xmi"
    target.write_text(mutation.edit(weblab_text), encoding="utf-8")
    found = _findings(target)
    assert {d.code for d in found} == mutation.codes, "\n".join(d.format_text() for d in found)
    expected = [d for d in found if d.code in mutation.codes]
    for name in mutation.elements:
        assert any(d.element and d.element.endswith(name) for d in expected), (
            name,
            [d.element for d in expected],
        )
    for fragment in mutation.message:
        assert any(fragment in d.message for d in expected), (
            fragment,
            [d.message for d in expected],
        )
    # every diagnostic points into the file, at a line of the mutated text
    lines = target.read_text(encoding="utf-8").count("\n") + 1
    assert all(1 <= d.line <= lines for d in expected)


def test_rule_syntax_error_names_policy_tag_and_rule_column(weblab_text: str, tmp_path: Path):
    broken = FIRST_RULE.replace("angle is narrow", "angle narrow")
    target = tmp_path / "weblab.xmi"
    target.write_text(replace(weblab_text, FIRST_RULE, broken, count=2), encoding="utf-8")
    (diag,) = [d for d in read_model(str(target)).diagnostics if d.code == "L401"]
    column = broken.index(" narrow") + 2  # 1-based column of 'narrow' in the rule text
    assert f"column {column}" in diag.message
    assert "'Rule'" in diag.message and "StraightRules" in diag.message
    # the location is the line of the file that holds the broken rule (the Rule tag)
    text_line = target.read_text(encoding="utf-8").splitlines()[diag.line - 1]
    assert "Rule" in text_line and "angle narrow" in text_line


def test_a_number_too_long_for_int_is_a_syntax_error_and_the_other_rules_are_still_checked(
    weblab_text, tmp_path
):
    text = replace(
        weblab_text, "Control.speed == 0 then", "Control.speed == " + "9" * 5000 + " then", count=2
    )
    text = replace(
        text,
        "if cycleRate is small and angle is narrow",
        "if cycleRat is small and angle is narrow",
        count=2,
    )
    result = run_main(["validate", str(write_model(tmp_path, text))])
    no_crash(result)
    assert codes_in(result.out) == {"L401", "L402"}, result.out
    assert "Z901" not in result.out


@pytest.mark.parametrize("name", ["open", "module", "to", "requires"])
def test_java_contextual_keywords_are_valid_attribute_names(
    name: str, weblab_text: str, tmp_path: Path
) -> None:
    target = tmp_path / "weblab.xmi"
    target.write_text(rename_attribute(weblab_text, "heading", name), encoding="utf-8")
    assert _findings(target) == []


def test_rules_in_a_tag_named_rule_something(weblab_text: str, tmp_path: Path) -> None:
    """The paper puts the rule name in the tag name: BOUML keeps such a tag as a plain key/value."""
    anchor = '<stereotype name="ACORDCS:CtxPolicy"/>\n\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxPolicy:Rule" value="smallNarrow'
    extra = (
        '<stereotype name="ACORDCS:CtxPolicy"/>\n\t\t\t\t\t\t\t<taggedValue tag="RuleSlowDown" '
        'value="slowDown: if cycleRate is large and angle is sharp then Locomotion.maxSpeed is crawl"/>'
        '\n\t\t\t\t\t\t\t<taggedValue tag="ACORDCS:CtxPolicy:Rule" value="smallNarrow'
    )
    text = replace(weblab_text, anchor, extra)
    target = tmp_path / "weblab.xmi"
    target.write_text(text, encoding="utf-8")
    reading = read_model(str(target))
    assert reading.diagnostics == []
    assert summarize(reading)["acordcs"]["policy_sets"]["SpeedLimiting"]["rules"] == 13
    target.write_text(
        text.replace("slowDown: if cycleRate", "slowDown: if cycleRat"), encoding="utf-8"
    )
    found = _findings(target)
    assert [d.code for d in found] == ["L402"]
    assert "'RuleSlowDown'" in found[0].message
