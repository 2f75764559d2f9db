"""``describe`` refuses a connection it cannot resolve to a required and a provided port (a model
with errors A501/A503), naming the connection, where it is, and what to do."""

from __future__ import annotations

import pytest

from acordcs.descriptor import DescriptorError
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.toolchain import replace, replace_in_element, write_model


def test_connection_joining_two_required_ports_refused(tmp_path, weblab_text):
    text = replace(
        weblab_text,
        'kind="synchronous" role="provided" base_Element="BOUML_0x1f782_4"',
        'kind="synchronous" role="required" base_Element="BOUML_0x1f782_4"',
    )
    text = replace_in_element(
        text,
        "VisionPort",
        '"ACORDCS:CtxPort:role" value="provided"',
        '"ACORDCS:CtxPort:role" value="required"',
    )
    path = write_model(tmp_path, text)
    reading = read_model(str(path))
    assert "A501" in {d.code for d in reading.diagnostics}
    with pytest.raises(DescriptorError) as err:
        describe(reading.architecture)
    e = err.value
    assert "'VisionLink'" in e.message and "2 required and 0 provided" in e.message
    assert e.file == str(path) and e.line
    assert "acordcs-gen validate" in e.hint
