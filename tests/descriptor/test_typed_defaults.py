"""UML default values typed by the attribute's type, as ``assemble`` will initialise properties
(the rule of today's runtime builder); a default that does not fit its type is refused by
``describe`` with the attribute's file, line and a hint."""

from __future__ import annotations

import pytest

from acordcs.descriptor import DescriptorError, typed_default, value_kind
from acordcs.generator.describe import describe
from acordcs.model.reading import read_model
from tests.support.toolchain import replace_in_element, write_model


@pytest.mark.parametrize(
    ("type_name", "variable", "kind"),
    [
        ("int", False, "int"),
        ("Integer", False, "int"),
        ("long", True, "int"),
        ("double", False, "double"),
        ("Real", False, "double"),
        ("float", False, "double"),
        ("bool", False, "bool"),
        ("Boolean", False, "bool"),
        ("string", False, "string"),
        ("Image", False, "string"),
        (None, False, "string"),
        (None, True, "double"),
        ("bool", True, "double"),
    ],
)
def test_value_kind(type_name, variable, kind):
    assert value_kind(type_name, variable=variable) == kind


@pytest.mark.parametrize(
    ("kind", "text", "range_min", "value"),
    [
        ("int", "10", None, 10),
        ("int", " -3 ", None, -3),
        ("int", "10.7", None, 10),  # truncated, as the runtime does
        ("int", None, None, 0),
        ("int", "", 2.0, 2),
        ("double", "0.5", None, 0.5),
        ("double", "2e3", None, 2000.0),
        ("double", None, None, 0.0),
        ("double", "", 1.5, 1.5),
        ("bool", "true", None, True),
        ("bool", "YES", None, True),
        ("bool", "1", None, True),
        ("bool", "false", None, False),
        ("bool", None, None, False),
        ("string", "640x480", None, "640x480"),
        ("string", None, None, ""),
        ("string", " padded ", None, " padded "),
    ],
)
def test_typed_default(kind, text, range_min, value):
    got = typed_default(kind, text, range_min)
    assert got == value and type(got) is type(value)


@pytest.mark.parametrize(("kind", "text"), [("int", "ten"), ("double", "nan"), ("double", "1e999")])
def test_number_that_does_not_parse_raises_value_error(kind, text):
    with pytest.raises(ValueError):
        typed_default(kind, text)


def test_linguistic_variable_without_default_starts_at_its_range_min(weblab):
    control = next(m for m in weblab.monitors if m.name == "Control")
    assert [(p.name, p.kind, p.default) for p in control.properties] == [
        ("cycleRate", "double", 0.0),
        ("angle", "double", 0.0),
        ("speed", "double", 0.0),
    ]


def test_describe_refuses_a_default_that_does_not_fit_its_type(tmp_path, weblab_text):
    text = replace_in_element(weblab_text, "Access", 'value="1800"', 'value="half an hour"')
    path = write_model(tmp_path, text)
    reading = read_model(str(path))
    with pytest.raises(DescriptorError) as err:
        describe(reading.architecture)
    e = err.value
    assert "Access.sessionTimeout" in e.message and "half an hour" in e.message
    assert e.file == str(path) and e.line and e.hint
    assert "BOUML_0x1fb02_1" in e.element
