"""Deferred members (readers/deferred.py): reading with them gives exactly what reading without does.

The oracle is the reader itself with deferral off: for every real export, both samples, a
synthetic model and models broken in each way that forbids deferring a member, the whole UML view
(every element with every field, once all deferred members are read) and every diagnostic of
``read_model`` (run before anything forced the deferred members) must be equal. The order of
``model.elements`` is the one thing allowed to differ (ids are registered as members are read).
"""

from __future__ import annotations

import importlib.util
import sys
from dataclasses import fields
from pathlib import Path

import pytest
from gen_helpers import ROOT, SMARTROOM, WEBLAB, XMI_SAMPLES, no_crash, run_process
from lxml import etree

from acordcs.generator.pipeline import ModelReading, read_model
from acordcs.generator.readers import xmi2
from acordcs.generator.readers.deferred import LazyElements
from acordcs.generator.uml import Classifier, Element, UmlModel
from acordcs.generator.xmlsafe import read_xml

XMI = "http://schema.omg.org/spec/XMI/2.1"
XID = f"{{{XMI}}}id"
XIDREF = f"{{{XMI}}}idref"


def _synthetic(tmp_path: Path, classes: int = 120) -> Path:
    spec = importlib.util.spec_from_file_location(
        "gen_synthetic_bouml", ROOT / "benchmarks" / "gen_synthetic_bouml.py"
    )
    mod = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("gen_synthetic_bouml", mod)
    spec.loader.exec_module(mod)
    path = tmp_path / "synthetic.xmi"
    path.write_text(mod.generate(classes=classes, seed=3), encoding="utf-8")
    return path


def read_deferring(path: Path) -> ModelReading:
    return read_model(str(path))


def read_eagerly(path: Path) -> ModelReading:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(xmi2, "read", lambda xml: xmi2._Reader(xml, lazy=False).read())
        reading = read_model(str(path))
    assert pending(reading.uml) == 0
    return reading


def pending(uml: UmlModel) -> int:
    return sum(1 for c in uml.classifiers if c._pending is not None)


def dump(uml: UmlModel) -> dict:
    """Everything the view holds, with every deferred member read."""

    def value(v):
        if isinstance(v, Element):
            return v.id
        if isinstance(v, list):
            return [value(x) for x in v]
        if isinstance(v, dict):
            return {k: value(x) for k, x in v.items()}
        return v

    def element(e: Element) -> dict:
        out = {"type": type(e).__name__}
        for f in fields(e):
            if f.name in ("_pending", "_load"):
                continue
            name = f.name.lstrip("_")
            v = getattr(e, name)
            out[name] = (
                [element(x) for x in v]
                if isinstance(v, list) and v and isinstance(v[0], Element)
                else value(v)
            )
        return out

    return {
        "elements": {k: element(e) for k, e in sorted(uml.elements.items())},
        "classifiers": [element(c) for c in uml.classifiers],
        "packages": [p.id for p in uml.packages],
        "associations": [a.id for a in uml.associations],
        "applications": [
            (k, a.line, list(a.tags.items()), list(a.tag_lines.items()), a.id, sorted(a.places))
            for k, a in uml.applications.items()
        ],
        "counts": uml.counts(),
    }


def roles_and_relations(reading: ModelReading) -> tuple:
    arch = reading.architecture
    if arch is None:
        return ()
    roles = [(r.id, r.kind, sorted(r.tags.items())) for r in arch.roles.values()]
    relations = {
        name: {source: [r.id for r in targets] for source, targets in by_source.items()}
        for name, by_source in arch.relations.items()
    }
    return roles, relations


def assert_same_reading(path: Path) -> tuple[ModelReading, ModelReading]:
    eager = read_eagerly(path)
    lazy = read_deferring(path)
    assert [repr(d) for d in lazy.diagnostics] == [repr(d) for d in eager.diagnostics]
    assert roles_and_relations(lazy) == roles_and_relations(eager)  # before the dump reads all
    assert dump(lazy.uml) == dump(eager.uml)
    return eager, lazy


SAMPLES = [
    WEBLAB,
    SMARTROOM,
    *sorted(XMI_SAMPLES.glob("*.xmi")),
    *sorted(XMI_SAMPLES.glob("*.uml")),
]


@pytest.mark.parametrize("path", SAMPLES, ids=lambda p: p.name)
def test_real_exports_read_the_same_with_deferred_members(path: Path) -> None:
    assert_same_reading(path)


def test_synthetic_model_defers_and_reads_the_same(tmp_path: Path) -> None:
    path = _synthetic(tmp_path)
    lazy = read_deferring(path)
    # Validation left most plain classes unread: the point of deferring.
    assert pending(lazy.uml) > len(lazy.uml.classifiers) // 2
    assert_same_reading(path)


# ------------------------------------------------------------------- models that forbid deferring
def _plain_classes(root: etree._Element) -> list[etree._Element]:
    """Classes with plain attributes and an operation with parameters, and no stereotype."""
    stereotyped = {e.get(next(iter(e.attrib))) for e in root if "base_" in "".join(e.attrib)}
    return [
        cls
        for cls in root.iter("packagedElement")
        if cls.get(f"{{{XMI}}}type") == "uml:Class"
        and cls.get(XID) not in stereotyped
        and cls.find(f"{{{XMI}}}Extension") is None
        and any(a.get("association") is None for a in cls.iterfind("ownedAttribute"))
        and any(len(op) for op in cls.iterfind("ownedOperation"))
    ]


def _plain_class(root: etree._Element) -> etree._Element:
    return _plain_classes(root)[0]


def _attribute(cls: etree._Element) -> etree._Element:
    return next(a for a in cls.iterfind("ownedAttribute") if a.get("association") is None)


def _retype(attr: etree._Element, ident: str) -> None:
    """Type ``attr`` by the element with id ``ident``, as BOUML writes it."""
    typ = attr.find("type")
    if typ is None:
        typ = etree.SubElement(attr, "type")
    typ.attrib.clear()
    typ.set(f"{{{XMI}}}type", "uml:Class")
    typ.set(XIDREF, ident)


def _mutations():
    def dangling_type(root, cls):
        _retype(_attribute(cls), "NO_SUCH_ID")

    def attribute_without_id(root, cls):
        del _attribute(cls).attrib[XID]

    def parameter_without_id(root, cls):
        op = next(op for op in cls.iterfind("ownedOperation") if len(op))
        del op.find("ownedParameter").attrib[XID]

    def duplicate_id(root, cls):
        _attribute(cls).set(XID, cls.get(XID))

    def stereotype_in_attribute(root, cls):
        ext = etree.SubElement(_attribute(cls), f"{{{XMI}}}Extension", extender="Bouml")
        etree.SubElement(ext, "stereotype", name="ACORDCS:CtxVariable")
        etree.SubElement(ext, "taggedValue", tag="ACORDCS:CtxVariable:min", value="0")

    def comment_in_operation(root, cls):
        op = cls.find("ownedOperation")
        etree.SubElement(op, "ownedComment", body="see the class").set(XID, "NEW_COMMENT")

    def namespaced_member(root, cls):
        _attribute(cls).tag = f"{{{root.nsmap['uml']}}}ownedAttribute"

    def root_application_on_attribute(root, cls):
        app = etree.SubElement(root, "{http:///schemas/ACORDCS/1}CtxVariable")
        app.set(XID, "NEW_APPLICATION")
        app.set("base_Element", _attribute(cls).get(XID))
        app.set("min", "0")

    def type_is_a_deferred_member(root, cls):
        other = _attribute(cls)
        target = next(a for a in root.iter("ownedAttribute") if a is not other)
        _retype(target, other.get(XID))

    def type_attribute_beside_href(root, cls):
        # The reader ignores a type child's idref beside an href and keeps the type attribute's.
        attr = _attribute(cls)
        for typ in attr.findall("type"):
            attr.remove(typ)
        attr.set("type", "NO_SUCH_ID")
        typ = etree.SubElement(
            attr, "type", href="http://schema.omg.org/spec/UML/2.1/uml.xml#String"
        )
        typ.set(XIDREF, cls.get(XID))

    def conflicting_root_applications_on_attribute(root, cls):
        for n in ("0", "1"):  # R205 names the attribute: read when the conflict is found
            app = etree.SubElement(root, "{http:///schemas/ACORDCS/1}CtxVariable")
            app.set(XID, f"NEW_APPLICATION_{n}")
            app.set("base_Property", _attribute(cls).get(XID))
            app.set("min", n)

    return [
        type_attribute_beside_href,
        conflicting_root_applications_on_attribute,
        dangling_type,
        attribute_without_id,
        parameter_without_id,
        duplicate_id,
        stereotype_in_attribute,
        comment_in_operation,
        namespaced_member,
        root_application_on_attribute,
        type_is_a_deferred_member,
    ]


@pytest.mark.parametrize("mutate", _mutations(), ids=lambda f: f.__name__)
def test_broken_models_read_the_same_with_deferred_members(tmp_path: Path, mutate) -> None:
    tree = etree.parse(str(_synthetic(tmp_path)))
    root = tree.getroot()
    mutate(root, _plain_class(root))
    path = tmp_path / "mutated.xmi"
    tree.write(str(path), xml_declaration=True, encoding="UTF-8")
    eager, _ = assert_same_reading(path)
    expected = {
        "dangling_type": "R202",
        "type_attribute_beside_href": "R202",
        "attribute_without_id": "R207",
        "duplicate_id": "R203",
        "conflicting_root_applications_on_attribute": "R205",
    }.get(mutate.__name__)
    if expected:
        found = [d for d in eager.diagnostics if d.code == expected]
        assert found
        if expected in ("R202", "R205"):  # they name the element (R203, R207 name none)
            assert all(d.element for d in found)


def test_files_with_dangling_or_duplicate_ids_are_read_without_deferring(tmp_path: Path) -> None:
    tree = etree.parse(str(_synthetic(tmp_path)))
    root = tree.getroot()
    _retype(_attribute(_plain_class(root)), "NO_SUCH_ID")
    path = tmp_path / "dangling.xmi"
    tree.write(str(path), xml_declaration=True, encoding="UTF-8")
    assert pending(read_deferring(path).uml) == 0
    assert pending(read_deferring(_synthetic(tmp_path)).uml) > 0


def test_lazy_elements_read_a_class_when_one_of_its_member_ids_is_asked_for(
    tmp_path: Path,
) -> None:
    path = _synthetic(tmp_path)
    root = etree.parse(str(path)).getroot()
    cls_el = _plain_class(root)
    attr_id = _attribute(cls_el).get(XID)
    param_id = next(op for op in cls_el.iterfind("ownedOperation") if len(op))[0].get(XID)
    uml = read_deferring(path).uml
    elements = uml.elements
    assert isinstance(elements, LazyElements)
    cls = dict.__getitem__(elements, cls_el.get(XID))
    assert isinstance(cls, Classifier) and cls._pending is not None
    assert not dict.__contains__(elements, attr_id)
    assert attr_id in elements  # reads the class
    assert cls._pending is None
    assert elements[attr_id] in cls.attributes
    assert elements.get(param_id).kind == "Parameter"
    assert elements.get("NO_SUCH_ID") is None and "NO_SUCH_ID" not in elements
    with pytest.raises(KeyError):
        elements["NO_SUCH_ID"]
    before = pending(uml)
    assert before > 0
    assert len(elements) == len(list(elements)) == len(dict(elements.items()))
    assert pending(uml) == 0


def test_validate_reports_what_a_deferred_member_holds(tmp_path: Path) -> None:
    """Through ``acordcs-gen`` itself: a dangling type reference and a missing id inside plain
    classes are reported."""
    tree = etree.parse(str(_synthetic(tmp_path)))
    root = tree.getroot()
    first, second = _plain_classes(root)[:2]
    _retype(_attribute(first), "NO_SUCH_ID")
    op = next(op for op in second.iterfind("ownedOperation") if len(op))
    del op.find("ownedParameter").attrib[XID]
    path = tmp_path / "broken.xmi"
    tree.write(str(path), xml_declaration=True, encoding="UTF-8")
    result = run_process(["validate", str(path)])
    no_crash(result)
    assert result.code == 1
    assert "R202" in result.out and "NO_SUCH_ID" in result.out
    assert "R207" in result.out
    assert result.out == run_process(["validate", "--format", "text", str(path)]).out


# ------------------------------------------------------------------- ids seen instead of searched
def _walk(path: Path):
    xml = read_xml(str(path))
    reader = xmi2._Reader(xml, lazy=True)
    reader.read()
    return xml, reader


XMI2_SAMPLES = [p for p in SAMPLES if xmi2.accepts(read_xml(str(p)).root)]  # not XMI 1.2


@pytest.mark.parametrize("path", XMI2_SAMPLES, ids=lambda p: p.name)
def test_ids_seen_by_the_walk_are_the_files_when_as_many(path: Path) -> None:
    """The reader takes the ids its walk saw for all of them when they are as many as the file
    has (each element is seen once): checked here against XPath."""
    xml, reader = _walk(path)
    if not xml._ids:  # the fast path: no XPath list was needed
        everything = xml.root.xpath("//@x:id", namespaces={"x": reader.xmi_ns}, smart_strings=False)
        assert sorted(reader.seen) == sorted(everything)


def test_ids_are_seen_without_xpath_in_bouml_exports(tmp_path: Path) -> None:
    for path in (WEBLAB, _synthetic(tmp_path)):
        xml, reader = _walk(path)
        assert xml._ids == {}, path  # every id was seen: no XPath list
        assert len(reader.seen) == xml.id_count(reader.xmi_ns)


def test_a_duplicate_id_where_the_walk_does_not_look_is_still_found(tmp_path: Path) -> None:
    tree = etree.parse(str(_synthetic(tmp_path)))
    root = tree.getroot()
    cls = _plain_class(root)
    value = next(v for v in root.iter("defaultValue") if v.get(XID))
    value.set(XID, cls.get(XID))  # a default value inside some attribute, with a class's id
    path = tmp_path / "duplicate.xmi"
    tree.write(str(path), xml_declaration=True, encoding="UTF-8")
    _, lazy = assert_same_reading(path)
    assert [d.code for d in lazy.diagnostics].count("R203") == 1
