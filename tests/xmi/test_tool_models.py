"""The ACORDCS profile as each profile-capable tool applies it: one hand-written model per tool
(``tests/xmi/tool_models``, each marked as such in its header comment and written from the tool's
documented export form), the same small architecture in each. Each validates clean through the normal
``validate`` path and reads as the same ACORD-CS architecture."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest

from acordcs.model.reading import read_model
from tests.support.toolchain import no_crash, run_main

MODELS = Path(__file__).parent / "tool_models"
TOOLS = {
    "acordcs_enterprise_architect.xmi": ("omg-xmi2", "Enterprise Architect 6.5"),
    "acordcs_magicdraw.xmi": ("omg-xmi2", "MagicDraw UML 19.0"),
    "acordcs_modelio.xmi": ("eclipse-uml2", "Objing 3.0.0"),
    "acordcs_visual_paradigm.xmi": ("omg-xmi2", "Visual Paradigm 17.2"),
}
ARCHITECTURE = {
    "elements": {
        "CtxVariable": ["level", "lux"],
        "CtxContainer": ["Host"],
        "CtxComponent": ["Lamp"],
        "CtxPolicySet": ["Dimming"],
        "CtxPolicy": ["DimRules"],
        "CtxMonitor": ["Light"],
    },
    "deployment": {"Host": ["Dimming", "Lamp", "Light"]},
    "policy_sets": {
        "Dimming": {
            "engine": "fuzzy",
            "trigger": "event",
            "policies": ["DimRules"],
            "rules": 2,
            "adapts": ["Lamp"],
            "fed_by": ["Light"],
        }
    },
    "persistent": [],
}


def test_every_tool_has_a_model() -> None:
    assert sorted(p.name for p in MODELS.glob("*.xmi")) == sorted(TOOLS)
    for path in MODELS.glob("*.xmi"):
        assert "Hand-written test model, NOT an export" in path.read_text(encoding="cp1252")


@pytest.mark.parametrize("name", sorted(TOOLS))
def test_tool_model_validates_clean(name: str) -> None:
    result = run_main(["validate", str(MODELS / name)])
    no_crash(result)
    assert result.code == 0 and "0 errors, 0 warnings, 0 infos" in result.out, result.out


@pytest.mark.parametrize("name", sorted(TOOLS))
def test_tool_model_reads_as_the_same_architecture(name: str) -> None:
    result = run_main(["inspect", "--format", "json", str(MODELS / name)])
    data = json.loads(result.out)
    assert (data["dialect"], data["exporter"]) == TOOLS[name]
    assert data["acordcs"] == ARCHITECTURE
    reading = read_model(str(MODELS / name))
    light = next(r for r in reading.architecture.roles.values() if r.name == "Light")
    lux = next(r for r in reading.architecture.roles.values() if r.name == "lux")
    assert light.tag("frequency") == "1"
    assert lux.tag("terms").startswith("dark := trape 0 0 100 300")


def test_visual_paradigm_applied_stereotype_alone_applies_the_stereotype(tmp_path: Path) -> None:
    """Without the standard applications, the <appliedStereotype> references alone name the roles."""
    text = (MODELS / "acordcs_visual_paradigm.xmi").read_text(encoding="utf-8")
    text, removed = re.subn(r"\n  <ACORDCS:\w+ [^>]*/>", "", text)
    assert removed == 7
    target = tmp_path / "vp.xmi"
    target.write_text(text, encoding="utf-8")
    data = json.loads(run_main(["inspect", "--format", "json", str(target)]).out)
    assert data["acordcs"]["elements"] == ARCHITECTURE["elements"]


def test_enterprise_architect_types_from_its_extension() -> None:
    reading = read_model(str(MODELS / "acordcs_enterprise_architect.xmi"))
    light = next(c for c in reading.uml.classifiers if c.name == "Light")
    assert [(a.name, a.type_name) for a in light.attributes] == [("lux", "double")]
