"""Features read when first asked for change nothing: for each model here, ``validate``'s findings,
``inspect``'s counts and the application descriptor are the same as when every classifier's features
are read at once (the oracle: the same reader with the deferral off). The models carry what forces a
classifier's features to be read at once (a dangling type, an attribute without id, a stereotype
applied to an attribute of a class that plays no role, a comment annotating an attribute, a type only
an extension defines) in classes that play no role, where the deferral would otherwise hide it."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from acordcs.cli.summary import summarize
from acordcs.descriptor import to_xml
from acordcs.model.describe import describe
from acordcs.model.reading import read_model
from acordcs.xmi.readers import deferred, read_uml
from tests.support.toolchain import SMARTROOM, WEBLAB
from tools.bouml_writer.synthetic import generate

MODELS = Path(__file__).parent / "tool_models"


def _everything(path: Path) -> dict:
    reading = read_model(str(path))
    found = {"findings": [d.format_text() for d in reading.diagnostics]}
    if reading.architecture is not None and not any(d.severity == 2 for d in reading.diagnostics):
        found["descriptor"] = to_xml(describe(reading.architecture))
    found["inspect"] = json.dumps(summarize(read_model(str(path), check=False)), sort_keys=True)
    return found


def _same_read_at_once(path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    lazily = _everything(path)
    with monkeypatch.context() as patched:
        patched.setattr(deferred.DeferredFeatures, "offer", lambda self, cls, features: False)
        at_once = _everything(path)
    assert lazily == at_once


def _synthetic(tmp_path: Path, edit=None) -> Path:
    text = generate(classes=120, seed=7)
    if edit is not None:
        text = edit(text)
    path = tmp_path / "synthetic.xmi"
    path.write_text(text, encoding="utf-8")
    return path


def _first_plain_attribute(text: str) -> tuple[int, int]:
    """Where the first typed attribute of a class that plays no role starts and ends."""
    uml = read_uml(str(_write(text)))
    bases = {a.base for a in uml.applications.values()}
    attribute = next(
        a
        for c in uml.classifiers
        if c.kind == "Class" and c.id not in bases
        for a in c.attributes
        if a.type_ref and not a.association and a.id not in bases
    )
    start = text.rindex("<ownedAttribute", 0, text.index(f'xmi:id="{attribute.id}"'))
    return start, text.index("</ownedAttribute>", start) + len("</ownedAttribute>")


def _write(text: str) -> Path:
    import tempfile

    with tempfile.NamedTemporaryFile("w", suffix=".xmi", delete=False, encoding="utf-8") as out:
        out.write(text)
    return Path(out.name)


def _edit_first_plain_attribute(old: str, new: str):
    def edit(text: str) -> str:
        start, end = _first_plain_attribute(text)
        attribute = text[start:end]
        assert old in attribute, attribute
        return text[:start] + attribute.replace(old, new, 1) + text[end:]

    return edit


def _edit_first_owned_end(old: str, new: str):
    """An association's owned end (BOUML writes one for each one-way relation): the first."""

    def edit(text: str) -> str:
        start = text.index("<ownedEnd", text.index('xmi:type="uml:Association"'))
        end = text.index(">", start)
        assert old in text[start:end], text[start:end]
        return text[:start] + text[start:end].replace(old, new, 1) + text[end:]

    return edit


EDITS = {
    "owned end with a dangling type": _edit_first_owned_end(' type="', ' type="nowhere_'),
    "owned end without id": _edit_first_owned_end(' xmi:id="', ' xmi:nid="'),
    "as generated": None,
    "dangling type": _edit_first_plain_attribute('xmi:idref="', 'xmi:idref="nowhere_'),
    "attribute without id": _edit_first_plain_attribute(' xmi:id="', ' xmi:nid="'),
    "BOUML stereotype on it": _edit_first_plain_attribute(
        "</ownedAttribute>",
        '<xmi:Extension extender="Bouml"><stereotype name="CtxVariable"/>'
        '<taggedValue tag="note" value="x"/></xmi:Extension></ownedAttribute>',
    ),
    "comment on it": _edit_first_plain_attribute(
        "</ownedAttribute>", '<ownedComment xmi:id="cm" body="why"/></ownedAttribute>'
    ),
}


@pytest.mark.parametrize("edit", sorted(EDITS))
def test_synthetic_model_reads_the_same(edit: str, tmp_path, monkeypatch) -> None:
    _same_read_at_once(_synthetic(tmp_path, EDITS[edit]), monkeypatch)


def test_an_application_at_the_root_on_a_plain_attribute(tmp_path, monkeypatch) -> None:
    def edit(text: str) -> str:
        start, _ = _first_plain_attribute(text)
        ident = text[text.index('xmi:id="', start) + 8 :].split('"', 1)[0]
        app = f'<ACORDCS:CtxVariable xmi:id="app_x" base_Property="{ident}" min="0" max="1"/>\n'
        return text.replace("</xmi:XMI>", app + "</xmi:XMI>")

    path = _synthetic(tmp_path, edit)
    _same_read_at_once(path, monkeypatch)
    assert any(a.id == "app_x" for a in read_uml(str(path)).applications.values())


@pytest.mark.parametrize(
    "path",
    [WEBLAB, SMARTROOM, *sorted(MODELS.glob("*.xmi"))],
    ids=lambda p: p.name,
)
def test_samples_and_tool_models_read_the_same(path: Path, monkeypatch) -> None:
    _same_read_at_once(path, monkeypatch)


def test_features_of_classes_without_a_role_are_not_built_by_validate(tmp_path) -> None:
    """What the deferral is for: validate reads the features of the classes playing a role."""
    reading = read_model(str(_synthetic(tmp_path)))
    roles = [c for c in reading.uml.classifiers if c.id in reading.architecture.roles]
    plain = [c for c in reading.uml.classifiers if c.kind == "Class" and c not in roles]
    assert plain and roles
    assert all(c.features_pending is not None for c in plain)
    assert all(c.features_pending is None for c in roles)
    # asked for, they are there
    read = [c.attributes for c in plain]
    assert any(read) and all(c.features_pending is None for c in plain)
