"""``acordcs-gen inspect``: the JSON summary of the WebLab sample, text and JSON agreeing with each
other and with a count by hand, elements of the same name kept apart, an unreadable file."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from tests.support.toolchain import SMARTROOM, WEBLAB, no_crash, run_main, write_model

WEBLAB_ACORDCS = {
    "CtxContainer": ["UserSide", "WebLabSide"],
    "CtxComponent": ["Access", "Locomotion", "Navigator", "PanoramicCamera", "Recovery", "Vision"],
    "CtxMonitor": ["Control", "Telemetry", "Usage"],
    "CtxPolicySet": ["BandwidthLimiting", "Recovering", "SpeedLimiting"],
    "CtxPolicy": ["FrameRateRules", "RecoveryRules", "StraightRules", "TurnRules"],
    "CtxPortConnection": [
        "AccessLink",
        "LocomotionLink",
        "PanoramaLink",
        "RecoveryLink",
        "TelemetryLink",
        "VisionLink",
    ],
    "CtxVariable": ["angle", "cycleRate", "fps", "maxSpeed", "numUsers", "speed"],
}


def test_inspect_json_weblab_acordcs_section() -> None:
    result = run_main(["inspect", "--format", "json", str(WEBLAB)])
    assert result.code == 0
    data = json.loads(result.out)
    assert (data["dialect"], data["exporter"], data["model"]) == (
        "bouml-xmi2",
        "Bouml 4.22.2",
        "WebLab",
    )
    acordcs = data["acordcs"]
    for kind, names in WEBLAB_ACORDCS.items():
        assert acordcs["elements"][kind] == names, kind
    assert len(acordcs["elements"]["CtxPort"]) == 11
    assert acordcs["deployment"]["UserSide"] == ["Navigator"]
    web = acordcs["deployment"]["WebLabSide"]
    assert "Navigator" not in web and len(web) == 11
    assert set(web) == (
        set(WEBLAB_ACORDCS["CtxComponent"]) - {"Navigator"}
        | set(WEBLAB_ACORDCS["CtxMonitor"])
        | set(WEBLAB_ACORDCS["CtxPolicySet"])
    )
    sets = acordcs["policy_sets"]
    summary = {name: (s["engine"], s["rules"]) for name, s in sets.items()}
    assert summary == {
        "SpeedLimiting": ("fuzzy", 12),
        "Recovering": ("clips", 5),
        "BandwidthLimiting": ("fuzzy", 9),
    }
    assert sets["SpeedLimiting"]["policies"] == ["StraightRules", "TurnRules"]
    assert sets["SpeedLimiting"]["adapts"] == ["Locomotion"]
    assert sets["Recovering"]["adapts"] == ["Recovery"]
    assert sets["BandwidthLimiting"]["adapts"] == ["PanoramicCamera"]
    assert sets["BandwidthLimiting"]["fed_by"] == ["Control", "Usage"]
    assert sets["BandwidthLimiting"]["trigger"] == "periodic"
    assert data["diagnostics"] == 0


def _rule_lines(path: Path) -> int:
    """Rules in the file's root-level CtxPolicy applications, counted by hand."""
    from lxml import etree

    root = etree.parse(str(path)).getroot()
    total = 0
    for app in root.iterfind("{http:///schemas/ACORDCS/1}CtxPolicy"):
        for key, value in app.items():
            if key.startswith("Rule"):
                total += sum(
                    1
                    for ln in value.splitlines()
                    if ln.strip() and not ln.strip().startswith(("#", "//"))
                )
    return total


@pytest.mark.parametrize("path", [WEBLAB, SMARTROOM], ids=["weblab", "smartroom"])
def test_inspect_text_and_json_agree(path: Path) -> None:
    text = run_main(["inspect", str(path)])
    data = json.loads(run_main(["inspect", "--format", "json", str(path)]).out)
    assert text.code == 0
    lines = text.out.splitlines()
    assert lines[0] == f"{path}: {data['dialect']} ({data['exporter']}), model {data['model']!r}"
    for key in (
        "attributes",
        "operations",
        "associations",
        "generalizations",
        "dependencies",
        "packages",
    ):
        assert f"  {key}: {data[key]}" in lines
    for kind, names in data["acordcs"]["elements"].items():
        assert f"    {kind} ({len(names)}): {', '.join(names)}" in lines
    for name, info in data["acordcs"]["policy_sets"].items():
        assert any(
            ln.startswith(f"    policy set {name}: engine {info['engine']}, {info['rules']} rules")
            for ln in lines
        )
    assert sum(s["rules"] for s in data["acordcs"]["policy_sets"].values()) == _rule_lines(path)
    deployed = {n for hosted in data["acordcs"]["deployment"].values() for n in hosted}
    elements = data["acordcs"]["elements"]
    assert deployed == {
        n for k in ("CtxComponent", "CtxMonitor", "CtxPolicySet") for n in elements.get(k, [])
    }


def test_inspect_unreadable_file(tmp_path: Path) -> None:
    result = run_main(["inspect", str(tmp_path / "missing.xmi")])
    no_crash(result)
    assert result.code == 2
    assert " X101 " in result.err and result.out == ""


def test_inspect_keeps_two_containers_of_the_same_name(weblab_text, tmp_path):
    text = weblab_text.replace('name="WebLabSide"', 'name="UserSide"')
    result = run_main(["inspect", str(write_model(tmp_path, text))])
    assert result.out.count("container UserSide") == 2, result.out
