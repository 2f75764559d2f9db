"""The descriptor's structure is declared once, in the annotated dataclasses of
:mod:`acordcs.descriptor.application`: the shipped schema is what that declaration writes (byte for
byte), every field of every dataclass declares its XML form, and any application the declaration
allows (every field, every optional one set or not, every enumerated value) is written as a
document the schema validates and read back equal."""

from __future__ import annotations

import dataclasses
import math
import sys
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from lxml import etree

from acordcs import vocabularies
from acordcs.descriptor import Application, application, from_xml, schema, to_xml, xsd
from acordcs.descriptor.xml_form import Element, Layout, Part, attr, layout
from tests.support.toolchain import ROOT

SHIPPED = ROOT / "src" / "acordcs" / "descriptor" / "acordcs-descriptor.xsd"
COMMAND = ".venv/bin/python tools/write_schema_enumerations.py"


# -------------------------------------------------------------------------------- the schema
def test_the_shipped_schema_is_what_the_declaration_writes() -> None:
    assert SHIPPED.read_bytes() == xsd.schema_text().encode("utf-8"), (
        f"{SHIPPED.name} is not what the declaration in acordcs/descriptor/application.py writes: "
        f"change the declaration, not the file, and run {COMMAND}"
    )


def test_the_tool_finds_the_schema_current(capsys: pytest.CaptureFixture[str]) -> None:
    from tools.write_schema_enumerations import main

    assert main(["--check"]) == 0
    assert capsys.readouterr().out.endswith(": current\n")


def test_the_written_schema_compiles_and_judges_a_descriptor(weblab: Application) -> None:
    written = etree.XMLSchema(etree.fromstring(xsd.schema_text().encode("utf-8")))
    document = etree.fromstring(to_xml(weblab))
    assert written.validate(document), written.error_log
    del document.attrib["name"]  # an application has a name
    assert not written.validate(document)


def test_the_enumerations_are_the_vocabularies() -> None:
    enumerated = xsd.enumerations()
    for simple in enumerated.values():
        if simple.eenum:
            literals = vocabularies.literals(simple.eenum)
            assert xsd.enumeration_values(simple) == tuple(
                v for v in literals if v not in simple.left_out
            )
    assert xsd.enumeration_values(enumerated["valueKind"]) == application.KINDS
    assert xsd.enumeration_values(enumerated["elementKind"]) == application.ELEMENT_KINDS
    assert xsd.enumeration_values(enumerated["memberKind"]) == application.MEMBER_KINDS


def test_a_definition_the_layout_does_not_place_is_refused(monkeypatch) -> None:
    monkeypatch.setattr(xsd, "LAYOUT", tuple(n for n in xsd.LAYOUT if n != "term"))
    with pytest.raises(ValueError, match=r"LAYOUT does not place \['term'\]"):
        xsd.schema_text()


# --------------------------------------------------------------------------- the declaration
def _dataclasses() -> list[type]:
    return [
        c
        for c in vars(application).values()
        if isinstance(c, type)
        and dataclasses.is_dataclass(c)
        and c.__module__ == application.__name__
    ]


def _reachable(declared: Layout, found: set[type]) -> set[type]:
    found.add(declared.cls)
    for part in declared.fields:
        if part.layout is not None and part.layout.cls not in found:
            _reachable(part.layout, found)
    return found


def test_every_dataclass_of_the_model_is_declared_and_in_the_document() -> None:
    classes = _dataclasses()
    for cls in classes:
        assert {p.field for p in layout(cls).fields} == {f.name for f in dataclasses.fields(cls)}
    assert _reachable(layout(Application), set()) == set(classes)


def test_a_field_that_declares_no_xml_form_is_refused() -> None:
    @dataclasses.dataclass(frozen=True)
    class Odd:
        XML = Element("odd")
        name: str = dataclasses.field(metadata=attr())
        colour: str = "red"

    with pytest.raises(TypeError, match=r"Odd\.colour declares no XML form"):
        layout(Odd)


# ------------------------------------------------------- any application the declaration allows
# Strings a descriptor can hold: anything but what XML 1.0 cannot (tested apart, in
# test_hostile_strings.py), with the characters an escaping bug would trip on made likely.
_TEXT = st.text(
    st.one_of(
        st.characters(exclude_categories=("Cs",), exclude_characters="\ufffe\uffff"),
        st.sampled_from("\"'<>&]\n\r\t "),
    ).filter(lambda c: c in "\t\n\r" or ord(c) >= 0x20),
    max_size=5,
)
_NAME = st.text(st.sampled_from("abcXYZ_.09é"), min_size=1, max_size=6)
_REAL = st.floats(allow_nan=False, allow_infinity=False)


def _bounds(part: Part) -> dict[str, Any]:
    """The numeric bounds the schema puts on the attribute (its facets, xs: integer types)."""
    simple, bounds = part.node.type, {}
    while simple is not None:
        for facet, value in simple.facets:
            if facet in ("minInclusive", "minExclusive"):
                bounds.setdefault("min_value", float(value) if part.codec == "real" else int(value))
                bounds["exclude_min"] = facet == "minExclusive"
            if facet == "maxInclusive":
                bounds.setdefault("max_value", int(value))
        if simple.name == "xs:positiveInteger":
            bounds.setdefault("min_value", 1)
        if simple.name == "xs:nonNegativeInteger":
            bounds.setdefault("min_value", 0)
        simple = simple.base
    return bounds


def _typed(kind: str | None) -> st.SearchStrategy[Any]:
    return {"int": st.integers(), "double": _REAL, "bool": st.booleans(), "string": _TEXT}.get(
        kind or "", st.none()
    )


def _attribute(part: Part) -> st.SearchStrategy[Any]:
    simple, codec, bounds = part.node.type, part.codec, _bounds(part)
    if simple.values or simple.eenum:
        found: st.SearchStrategy[Any] = st.sampled_from(xsd.enumeration_values(simple))
    elif codec == "real":
        exclude = bounds.pop("exclude_min", False)
        found = st.floats(allow_nan=False, allow_infinity=False, exclude_min=exclude, **bounds)
    elif codec == "integer":
        bounds.pop("exclude_min", None)
        found = st.integers(**bounds)
    elif codec == "flag":
        found = st.booleans()
    elif codec == "names":
        found = st.lists(_NAME, min_size=1, max_size=3).map(tuple)
    elif codec == "reals":
        found = st.lists(_REAL, max_size=4).map(tuple)
    else:
        found = _TEXT
    return st.none() | found if part.optional else found


@st.composite
def _instance(draw: st.DrawFn, cls: type, depth: int = 0) -> Any:
    """An instance of ``cls`` (lists of two elements at the application's level, one below)."""
    declared = layout(cls)
    most = 2 if depth == 0 else 1
    values: dict[str, Any] = {}
    for part in declared.fields:  # a default's kind is drawn before it
        role = part.node.role
        if part.codec == "typed":
            kind = values[part.node.typed_by]
            found = _typed(kind) if kind is not None else st.none()
            values[part.field] = draw(st.none() | found if part.optional else found)
        elif role == "attribute":
            values[part.field] = draw(_attribute(part))
        elif role in ("text", "documentation"):
            values[part.field] = draw(_TEXT)
        elif role == "names":
            values[part.field] = tuple(draw(st.lists(_NAME, max_size=most)))
        elif role == "child":
            assert part.layout is not None
            one = _instance(part.layout.cls, depth + 1)
            values[part.field] = draw(st.none() | one if part.optional else one)
        else:
            assert part.layout is not None
            many = st.lists(_instance(part.layout.cls, depth + 1), max_size=most)
            values[part.field] = tuple(draw(many))
    return cls(**values)


def _consistent(app: Application, data: st.DataObject) -> Application:
    """``app`` with what the schema's keys require: ids and names unique where they must be, and
    connection ends, reached containers and fed policy sets naming elements described here."""
    r = dataclasses.replace
    counter = iter(range(sys.maxsize))

    def own(item: Any, **changes: Any) -> Any:
        n = next(counter)
        return r(item, id=f"id{n}", name=f"{item.name}#{n}", **changes)

    containers = tuple(own(c) for c in app.containers)
    names = [c.name for c in containers]
    containers = tuple(
        r(c, reaches=tuple(data.draw(st.sampled_from(names)) for _ in c.reaches))
        for c in containers
    )
    components = tuple(own(c, ports=tuple(own(p) for p in c.ports)) for c in app.components)
    sets = tuple(own(p, policies=tuple(own(q) for q in p.policies)) for p in app.policy_sets)
    ends = [c.name for c in components]
    connections = tuple(
        own(
            k,
            required=r(k.required, component=data.draw(st.sampled_from(ends))),
            provided=r(k.provided, component=data.draw(st.sampled_from(ends))),
        )
        for k in app.connections
        if ends
    )
    fed = [p.name for p in sets]
    monitors = tuple(
        own(m, feeds=tuple(r(f, name=data.draw(st.sampled_from(fed))) for f in m.feeds if fed))
        for m in app.monitors
    )
    return r(
        app,
        containers=containers,
        components=components,
        connections=connections,
        monitors=monitors,
        policy_sets=sets,
    )


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(app=_instance(Application), data=st.data())
def test_any_application_the_declaration_allows_is_valid_and_reads_back_equal(
    app: Application, data: st.DataObject
) -> None:
    app = _consistent(app, data)
    written = to_xml(app)
    schema().assertValid(etree.fromstring(written))
    back = from_xml(written)
    assert back == app
    assert to_xml(back) == written
    for p in (p for c in back.components for p in c.properties if p.kind == "double"):
        assert isinstance(p.default, float) and math.isfinite(p.default)
