"""A document that is not a valid descriptor is refused with one error type, DescriptorError (an
AcordError), carrying the file, the line and column of the fault and a hint."""

from __future__ import annotations

import pytest

from acordcs.descriptor import DescriptorError, from_xml, to_xml
from acordcs.errors import AcordError


@pytest.fixture(scope="module")
def data(weblab) -> bytes:
    return to_xml(weblab)


def _refused(data: bytes) -> DescriptorError:
    with pytest.raises(DescriptorError) as err:
        from_xml(data, file="weblab.descriptor.xml")
    return err.value


def _at(data: bytes, err: DescriptorError) -> bytes:
    """The bytes at the error's line and column."""
    return data.split(b"\n")[err.line - 1][err.column - 1 :]


def test_error_type_is_an_acord_error():
    assert issubclass(DescriptorError, AcordError)


def test_invalid_attribute_value_refused_with_line_and_column(data):
    bad = data.replace(b'kind="stream" role="provided"', b'kind="streaming" role="provided"', 1)
    err = _refused(bad)
    assert err.file == "weblab.descriptor.xml"
    assert err.line == bad[: bad.index(b'kind="streaming"')].count(b"\n") + 1
    assert _at(bad, err).startswith(b'kind="streaming"')
    assert "streaming" in err.message and "acordcs-descriptor.xsd" in err.message
    assert err.hint and "to_xml" in err.hint
    assert str(err).startswith(f"weblab.descriptor.xml:{err.line}:{err.column}: error: ")


def test_missing_required_attribute_points_at_the_element(data):
    bad = data.replace(b'<hosts kind="component" name="Navigator" ', b'<hosts kind="component" ', 1)
    err = _refused(bad)
    assert "'name' is required" in err.message
    assert _at(bad, err).startswith(b'<hosts kind="component" ref=')


def test_unexpected_element_refused(data):
    bad = data.replace(b"<components>", b"<components>\n    <robot/>", 1)
    err = _refused(bad)
    assert "robot" in err.message
    assert _at(bad, err).startswith(b"<robot/>")


def test_connection_end_naming_no_component_refused(data):
    bad = data.replace(b'<provided component="Vision"', b'<provided component="Visio"', 1)
    err = _refused(bad)
    assert "Visio" in err.message
    assert _at(bad, err).startswith(b'<provided component="Visio"')


def test_duplicate_id_refused(data):
    bad = data.replace(b'id="BOUML_0x20382_4"', b'id="BOUML_0x20302_4"', 1)
    assert "Duplicate" in _refused(bad).message


def test_default_not_of_its_kind_refused(data):
    bad = data.replace(b'default="1800"', b'default="half an hour"', 1)
    err = _refused(bad)
    assert "sessionTimeout" in err.message
    assert _at(bad, err).startswith(b'default="half an hour"')


def test_not_well_formed_refused_with_position(data):
    bad = data.replace(b"</monitors>", b"</monitor>", 1)
    err = _refused(bad)
    assert "not well-formed" in err.message
    assert err.line == bad[: bad.index(b"</monitor>\n  <policy")].count(b"\n") + 1
    assert err.column


def test_doctype_refused_before_parsing():
    bad = (
        b'<?xml version="1.0"?>\n<!DOCTYPE a [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n<a>&x;</a>'
    )
    err = _refused(bad)
    assert (err.line, err.column) == (2, 1)
    assert "document type" in err.message


def test_other_namespace_refused(data):
    bad = data.replace(b"http://acordcs.org/descriptor/1.0", b"http://acordcs.org/descriptor/2.0")
    err = _refused(bad)
    assert err.line == 2 and "namespace" in err.hint
