"""Both samples describe to descriptors that validate against the shipped schema and read back
equal, and the document read back writes the same bytes."""

from __future__ import annotations

import pytest
from lxml import etree

from acordcs.descriptor import NAMESPACE, from_xml, schema, to_xml
from tests.support.toolchain import ROOT


@pytest.fixture(params=["weblab", "smartroom"])
def app(request):
    return request.getfixturevalue(request.param)


def test_descriptor_validates_against_the_shipped_schema(app):
    doc = etree.fromstring(to_xml(app))
    schema().assertValid(doc)
    assert doc.tag == f"{{{NAMESPACE}}}application"


def test_schema_is_xsd_1_0_and_compiles_on_its_own():
    xsd = ROOT / "src" / "acordcs" / "descriptor" / "acordcs-descriptor.xsd"
    tree = etree.parse(str(xsd))
    assert tree.getroot().get("targetNamespace") == NAMESPACE
    etree.XMLSchema(tree)  # raises if the schema does not compile


def test_schema_is_package_data():
    pyproject = (ROOT / "pyproject.toml").read_text(encoding="utf-8")
    assert '"*.xsd"' in pyproject


def test_round_trip_gives_an_equal_application(app):
    assert from_xml(to_xml(app)) == app


def test_document_read_back_writes_the_same_bytes(app):
    data = to_xml(app)
    assert to_xml(from_xml(data)) == data


def test_typed_defaults_keep_their_python_types_through_xml(app):
    back = from_xml(to_xml(app))
    pairs = [
        (a, b)
        for c1, c2 in zip(app.components, back.components, strict=True)
        for a, b in zip(c1.properties, c2.properties, strict=True)
    ]
    assert pairs
    for a, b in pairs:
        assert type(a.default) is type(b.default), (a, b)
