"""The same model gives the same descriptor bytes: twice from one reading, and from two readings."""

from __future__ import annotations

from acordcs.descriptor import to_xml
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.toolchain import SMARTROOM, WEBLAB


def test_same_bytes_twice(weblab_reading):
    first = to_xml(describe(weblab_reading.architecture))
    assert to_xml(describe(weblab_reading.architecture)) == first


def test_same_bytes_from_two_readings_of_each_sample():
    for path in (WEBLAB, SMARTROOM):
        a = to_xml(describe(read_model(str(path)).architecture))
        b = to_xml(describe(read_model(str(path)).architecture))
        assert a == b


def test_elements_sorted_by_name_then_id(weblab):
    for items in (
        weblab.containers,
        weblab.components,
        weblab.connections,
        weblab.monitors,
        weblab.policy_sets,
        *(c.ports for c in weblab.components),
        *(ps.policies for ps in weblab.policy_sets),
    ):
        keys = [(i.name, i.id) for i in items]
        assert keys == sorted(keys)
    for ps in weblab.policy_sets:
        names = [(v.name, v.id) for v in ps.variables]
        assert names == sorted(names)


def test_utf8_pretty_printed_with_declaration(weblab):
    data = to_xml(weblab)
    assert data.startswith(b'<?xml version="1.0" encoding="UTF-8"?>\n<application ')
    assert b"\n  <containers>\n    <container " in data
    assert data.endswith(b"</application>\n")
