"""The tag ``persistent`` of a ``<<CtxComponent>>`` is read from a BOUML export (its tagged value in
the class's extension and its stereotype application), from a Papyrus model (the stereotype
application's attribute) and from the text notation, as ``language`` is; it reaches the descriptor
once (``Component.persistent``), survives its XML form, and a value that is no Boolean is T304.
An unset tag is the profile's default, false; a persistent component without a property is A518."""

from __future__ import annotations

from pathlib import Path

from acordcs.descriptor import from_xml, to_xml
from acordcs.generator.describe import describe
from acordcs.model.ecore_builder import to_ecore
from acordcs.model.reading import read_model
from acordcs.profile import stereotype
from tests.support.toolchain import SAMPLES, WEBLAB, replace, replace_in_element

VENTILATION = SAMPLES / "papyrus" / "ventilation.uml"


def _persistent(path: Path) -> dict[str, bool]:
    """Each component's tag as the descriptor carries it, held equal to the metamodel instance
    ``acordcs-gen export`` writes (an EBoolean there)."""
    reading = read_model(str(path))
    app = describe(reading.architecture)
    assert from_xml(to_xml(app)) == app  # carried by the descriptor's XML form as it is
    exported = {c.name: c.persistent for c in to_ecore(reading.architecture).components}
    found = {c.name: c.persistent for c in app.components}
    assert exported == found
    return found


def _codes(path: Path) -> list[str]:
    return [d.code for d in read_model(str(path)).diagnostics]


def test_the_profile_declares_it_a_boolean_false_by_default():
    tag = stereotype("CtxComponent").tag("persistent")
    assert (tag.type, tag.default, tag.feature) == ("Boolean", "false", "persistent")


def test_from_a_bouml_export(tmp_path):
    # BOUML writes the tag in both places it puts a stereotype: the class's extension and the
    # root-level stereotype application
    text = WEBLAB.read_text()
    text = replace_in_element(
        text,
        "Navigator",
        '<taggedValue tag="ACORDCS:CtxComponent:persistent" value="false"/>',
        '<taggedValue tag="ACORDCS:CtxComponent:persistent" value="true"/>',
    )
    text = replace(
        text,
        'language="python" persistent="false" base_Element="BOUML_0x1f482_4"/>',
        'language="python" persistent="true" base_Element="BOUML_0x1f482_4"/>',
    )
    target = tmp_path / "weblab.xmi"
    target.write_text(text)
    found = _persistent(target)
    assert found["Navigator"] is True
    assert not any(v for k, v in found.items() if k != "Navigator"), found
    assert "A518" not in _codes(target)  # the Navigator declares properties


def test_from_a_papyrus_model(tmp_path):
    text = replace(
        VENTILATION.read_text(),
        '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Class="_Fan"/>',
        '<ACORDCS:CtxComponent xmi:id="_Fan.app" base_Class="_Fan" persistent="true"/>',
    )
    text = replace(text, 'base_Class="_Panel" language="python"/>',
                   'base_Class="_Panel" language="python" persistent="false"/>')  # fmt: skip
    target = tmp_path / "ventilation.uml"
    target.write_text(text)
    (tmp_path / "ACORDCS.profile.uml").write_bytes(
        (VENTILATION.parent / "ACORDCS.profile.uml").read_bytes()
    )
    assert _persistent(target) == {"Fan": True, "Panel": False}
    assert _codes(target) == []


def test_from_the_text_notation_with_its_findings(tmp_path):
    text = (SAMPLES / "papyrus" / "ventilation.acord").read_text()
    text = replace(
        text, 'component Fan id "_Fan" {', 'component Fan id "_Fan" (persistent = TRUE) {'
    )
    text = replace(text, "(language = python)", "(language = python, persistent = true)")
    target = tmp_path / "ventilation.acord"
    target.write_text(text)
    assert _persistent(target) == {"Fan": True, "Panel": True}
    (found,) = [d for d in read_model(str(target)).diagnostics if d.code == "A518"]
    assert "component 'Panel' is tagged persistent but declares no property" in found.message
    assert (
        found.line
        == text.splitlines().index(
            next(line for line in text.splitlines() if "persistent = true" in line)
        )
        + 1
    )
    wrong = tmp_path / "wrong.acord"
    wrong.write_text(replace(text, "persistent = TRUE", "persistent = yes"))
    assert "T304" in _codes(wrong)


def test_unset_is_false_everywhere():
    assert set(_persistent(WEBLAB).values()) == {False}
    assert set(_persistent(VENTILATION).values()) == {False}


def test_a_change_of_the_tag_is_planned_as_a_restart():
    from dataclasses import replace as changed

    from acordcs.descriptor.diff import diff

    old = describe(read_model(str(VENTILATION)).architecture)
    fan = next(c for c in old.components if c.name == "Fan")
    new = changed(old, components=tuple(changed(c, persistent=True) if c is fan else c
                                        for c in old.components))  # fmt: skip
    plan = diff(old, new)
    assert plan.lines == ("~ component Fan: persistent false -> true",)
    assert not plan.live and plan.changes[0].containers == ("Plant",)
