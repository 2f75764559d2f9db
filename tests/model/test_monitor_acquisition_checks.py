"""What each monitor acquisition kind needs (A514), tags a kind does not read (A515), and container
ports (T314): on the WebLab sample, whose Control intercepts, Telemetry subscribes and Usage polls."""

from __future__ import annotations

import re

import pytest
from lxml import etree

from tests.support.toolchain import codes_in, run_main, write_model

STELT = {
    "Control": "BOUML_STELT_0x20002_4",
    "Telemetry": "BOUML_STELT_0x20082_4",
    "Usage": "BOUML_STELT_0x20102_4",
}
STELT_WEBLAB_SIDE = "BOUML_STELT_0x20582_4"  # the second container
ORDER = ["Control", "Telemetry", "Usage"]  # their order in the file, in both places BOUML writes


def set_tag(text: str, monitor: str, tag: str, value: str, kind: str = "CtxMonitor") -> str:
    """``text`` with the tag set to ``value`` in both places BOUML writes it."""
    # the root stereotype application
    line = re.search(rf'<ACORDCS:{kind} xmi:id="{STELT.get(monitor, monitor)}"[^>]*>', text)
    assert line, monitor
    app = re.sub(rf'\b{tag}="[^"]*"', f'{tag}="{value}"', line.group(0))
    text = text[: line.start()] + app + text[line.end() :]
    # the taggedValue in the class's extension
    tagged = list(re.finditer(rf'tag="ACORDCS:{kind}:{tag}" value="[^"]*"', text))
    index = ORDER.index(monitor) if kind == "CtxMonitor" else int(monitor == STELT_WEBLAB_SIDE)
    hit = tagged[index]
    return text[: hit.start()] + f'tag="ACORDCS:{kind}:{tag}" value="{value}"' + text[hit.end() :]


def validate(tmp_path, text: str):
    return run_main(["validate", str(write_model(tmp_path, text))])


def test_the_sample_uses_all_three_kinds_cleanly(weblab_text, tmp_path):
    assert 'acquisition="subscribe"' in weblab_text
    result = validate(tmp_path, weblab_text)
    assert result.code == 0, result.out


@pytest.mark.parametrize(
    ("monitor", "tag", "value", "says"),
    [
        ("Telemetry", "xpath", "", "subscribes to the context provider but has no tag xpath"),
        ("Telemetry", "xpath", "/telemetry[", "is not XPath 1.0"),
        (
            "Usage",
            "operation",
            "",
            "has no tag operation: set it to one of authenticate, countUsers",
        ),
        ("Usage", "operation", "countUser", "(did you mean 'countUsers'?)"),
        ("Usage", "operation", "authenticate", "which takes input"),
        ("Usage", "frequency", "", "polls but has no frequency"),
    ],
)
def test_what_a_kind_needs_is_an_error(weblab_text, tmp_path, monitor, tag, value, says):
    result = validate(tmp_path, set_tag(weblab_text, monitor, tag, value))
    assert result.code == 1, result.out
    assert codes_in(result.out) == {"A514"}, result.out
    assert says in result.out
    assert f"Adaptation::{monitor}" in result.out


def test_an_interceptor_without_a_source_is_an_error(weblab_text, tmp_path):
    # Telemetry's only source is a port; made to intercept without it, it would see nothing
    text = set_tag(weblab_text, "Telemetry", "acquisition", "intercept")
    text = set_tag(text, "Telemetry", "xpath", "")
    dependency = re.search(
        r'<packagedElement xmi:type="uml:Dependency"[^>]*client="BOUML_0x20082_4".*?</packagedElement>',
        text,
        re.S,
    )
    assert dependency, "the Telemetry -> TelemetryPort dependency"
    text = text.replace(dependency.group(0), "")
    result = validate(tmp_path, text)
    assert codes_in(result.out) == {"A514"}, result.out
    assert "intercepts calls but has no source port or component" in result.out


@pytest.mark.parametrize(
    ("monitor", "tag", "value", "says"),
    [
        ("Control", "xpath", "/robot", "ignores its tag 'xpath' (read by acquisition subscribe)"),
        (
            "Telemetry",
            "operation",
            "grab",
            "ignores its tag 'operation' (read by acquisition poll)",
        ),
        ("Control", "frequency", "2", "intercepts calls and ignores its frequency (2 Hz)"),
    ],
)
def test_a_tag_the_kind_does_not_read_is_a_warning(
    weblab_text, tmp_path, monitor, tag, value, says
):
    result = validate(tmp_path, set_tag(weblab_text, monitor, tag, value))
    assert result.code == 0, result.out  # a warning
    assert codes_in(result.out) == {"A515"}, result.out
    assert says in result.out


def test_an_unset_kind_is_intercept_or_custom_with_a_frequency(weblab_text, tmp_path):
    # Usage without acquisition: custom (it has a frequency); its operation is then unread
    text = set_tag(weblab_text, "Usage", "acquisition", "")
    result = validate(tmp_path, text)
    assert codes_in(result.out) == {"A515"}, result.out
    assert "monitor 'Usage' acquires by custom" in result.out


def test_an_unknown_kind_is_reported_once_as_a_tag_value(weblab_text, tmp_path):
    result = validate(tmp_path, set_tag(weblab_text, "Usage", "acquisition", "polling"))
    assert codes_in(result.out) == {"T305"}, result.out
    assert "permitted: intercept, subscribe, poll, custom" in result.out


@pytest.mark.parametrize(("value", "code"), [("0", "T314"), ("70000", "T314"), ("http", "T304")])
def test_a_container_port_is_a_tcp_port(weblab_text, tmp_path, value, code):
    text = set_tag(weblab_text, STELT_WEBLAB_SIDE, "port", value, kind="CtxContainer")
    result = validate(tmp_path, text)
    assert result.code == 1
    assert codes_in(result.out) == {code}, result.out


def test_xpath_syntax_is_judged_by_the_engine_that_evaluates_it():
    # the oracle: lxml (libxml2) is what the context provider compiles subscriptions with
    for good in ("/telemetry", "//robot[battery < 20]", "count(/a/b) > 1"):
        etree.XPath(good)
    with pytest.raises(etree.XPathSyntaxError):
        etree.XPath("/telemetry[")
