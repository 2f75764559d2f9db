"""Every sample ships its model in the text notation beside its XMI: the text is what
acordcs-gen convert writes from the XMI, and reads as the same application."""

from __future__ import annotations

from pathlib import Path

import pytest

from acordcs.generator.describe import describe
from acordcs.model.outline_builder import to_form
from acordcs.model.reading import read_model
from tests.notation.test_round_trips_through_every_form import SHIPPED


@pytest.mark.parametrize("model", SHIPPED, ids=lambda p: p.name)
def test_the_text_beside_a_sample_is_its_conversion(model: Path) -> None:
    text = model.with_suffix(".acord")
    assert text.is_file(), (
        f"{model.name} has no text form beside it: acordcs-gen convert {model} -o {text}"
    )
    xmi = read_model(str(model))
    assert text.read_bytes() == to_form(xmi.architecture, "text"), (
        f"{text.name} is stale: acordcs-gen convert {model} -o {text}"
    )
    written = read_model(str(text))
    assert [str(d) for d in written.diagnostics] == []
    assert describe(written.architecture) == describe(xmi.architecture)
