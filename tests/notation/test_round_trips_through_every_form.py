"""Round trips of acordcs-gen convert, on every shipped sample and every real export of the
reference folder: text -> XMI (Papyrus's form, BOUML's) -> text gives the same text; XMI -> text
-> XMI gives the same application descriptor (the oracle: describe(), which the build runs)."""

from __future__ import annotations

from pathlib import Path

import pytest

from acordcs.generator.describe import describe
from acordcs.model.outline_builder import to_form
from acordcs.model.reading import read_model
from tests.support.toolchain import SAMPLES, XMI_SAMPLES, reference_params

SHIPPED = sorted(
    p
    for p in [*SAMPLES.glob("*/*.xmi"), *SAMPLES.glob("*/*.uml")]
    if p.parent.name != "mistakes" and not p.name.startswith("ACORDCS.")
)
XMI_SUFFIX = {"papyrus": ".uml", "bouml": ".xmi"}


def _written(tmp_path: Path, name: str, data: bytes) -> Path:
    path = tmp_path / name
    path.write_bytes(data)
    return path


def _reading(path: Path):
    reading = read_model(str(path))
    assert reading.architecture is not None, [str(d) for d in reading.diagnostics]
    return reading


@pytest.mark.parametrize("model", SHIPPED, ids=lambda p: p.name)
@pytest.mark.parametrize("form", ["papyrus", "bouml"])
def test_a_sample_converts_to_text_and_back_to_the_same_descriptor_and_text(
    model: Path, form: str, tmp_path: Path
) -> None:
    original = _reading(model)
    text = to_form(original.architecture, "text")
    from_text = _reading(_written(tmp_path, "model.acord", text))
    xmi = to_form(from_text.architecture, form)
    back = _reading(_written(tmp_path, "model" + XMI_SUFFIX[form], xmi))
    assert describe(back.architecture) == describe(original.architecture)
    assert describe(from_text.architecture) == describe(original.architecture)
    assert to_form(back.architecture, "text") == text
    # what the readers found wrong (nothing, for a shipped sample) is found wrong again
    codes = sorted(d.code for d in back.diagnostics if d.code != "T321")
    assert codes == sorted(d.code for d in original.diagnostics if d.code != "T321")


@pytest.mark.parametrize("export", reference_params(XMI_SAMPLES), ids=lambda p: p.name)
def test_a_real_export_converts_to_text_and_back_to_the_same_descriptor(
    export: Path, tmp_path: Path
) -> None:
    """None of the real exports applies ACORDCS today, so what ACORD-CS reads of them is an empty
    application: the text says so, and the round trip keeps it (and the name of the model)."""
    original = _reading(export)
    text = to_form(original.architecture, "text")
    from_text = _reading(_written(tmp_path, "model.acord", text))
    for form, suffix in XMI_SUFFIX.items():
        back = _reading(_written(tmp_path, "model" + suffix, to_form(from_text.architecture, form)))
        assert describe(back.architecture) == describe(original.architecture)
        assert to_form(back.architecture, "text") == text
    if not original.architecture.roles:
        lines = text.decode().strip().splitlines()
        assert len(lines) <= 1  # the model's name and id at most, and nothing in it
        assert all(line.startswith("model ") for line in lines)
