"""The documentation of the application descriptor (docs/descriptor.md) shows real output: its XML excerpt is made
of runs of lines of the WebLab descriptor, its error example is what ``from_xml`` says, and its
Python example gives the values it claims."""

from __future__ import annotations

import re

from acordcs.descriptor import DescriptorError, from_xml, to_xml
from tests.support.toolchain import ROOT

SECTION = (ROOT / "docs" / "descriptor.md").read_text(encoding="utf-8")


def test_xml_excerpt_is_made_of_runs_of_the_real_descriptor(weblab):
    excerpt = SECTION.split("```xml\n", 1)[1].split("```", 1)[0]
    real = to_xml(weblab).decode("utf-8")
    runs = excerpt.split("...\n")
    assert len(runs) > 1
    position = 0
    for run in runs:
        found = real.find(run, position)
        assert found >= 0, f"not in the real descriptor (in order):\n{run}"
        position = found + len(run)
    assert real.startswith(runs[0]) and real.endswith(runs[-1])


def test_error_example_is_what_from_xml_says(weblab):
    shown = SECTION.split("```\nweblab.descriptor.xml:", 1)[1].split("\n```", 1)[0]
    data = to_xml(weblab).replace(
        b'kind="stream" role="provided"', b'kind="streaming" role="provided"'
    )
    try:
        from_xml(data, file="weblab.descriptor.xml")
    except DescriptorError as err:
        assert str(err) == "weblab.descriptor.xml:" + shown
    else:
        raise AssertionError("the edited descriptor was accepted")


def test_python_example_values(weblab):
    assert "app.container_of(\"Navigator\")       # 'UserSide'" in SECTION
    assert weblab.container_of("Navigator") == "UserSide"
    assert weblab.fed_by("BandwidthLimiting") == ("Control", "Usage")


def test_counts_stated_are_the_descriptors(weblab):
    stated = re.search(
        r"holds (\d+) containers, (\d+) components with (\d+) ports, (\d+) connections, (\d+) "
        r"monitors and (\d+) policy sets with (\d+), (\d+) and (\d+) rules",
        " ".join(SECTION.split()),
    )
    assert stated, "the counts sentence changed"
    rules = {ps.name: len(ps.rules()) for ps in weblab.policy_sets}
    assert tuple(map(int, stated.groups())) == (
        len(weblab.containers),
        len(weblab.components),
        sum(len(c.ports) for c in weblab.components),
        len(weblab.connections),
        len(weblab.monitors),
        len(weblab.policy_sets),
        rules["SpeedLimiting"],
        rules["Recovering"],
        rules["BandwidthLimiting"],
    )
