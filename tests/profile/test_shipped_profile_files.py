"""The shipped profile files (BOUML XMI and Papyrus .profile.uml) say what the declaration says.

The content checks read the files with plain lxml XPath, not with anything from profile_files.py, so a
bug in the exporter cannot hide itself. Shape checks compare with real files in
../shared/reference/xmi-samples (a Papyrus-made profile and a BOUML in-model profile).
"""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path

import pytest
from lxml import etree

from acordcs.profile import profile_files
from acordcs.profile.declaration import PROFILE_NAME, Stereotype, Tag, profile
from tests.support.toolchain import xmi_sample

PACKAGE_DIR = Path(profile_files.__file__).resolve().parent
SHIPPED_BOUML = PACKAGE_DIR / "ACORDCS.xmi"
SHIPPED_ECLIPSE = PACKAGE_DIR / "ACORDCS.profile.uml"
CODEGEN_SAMPLE = "pyuml2-codegen__Codegen.profile.uml"  # in ../shared/reference/xmi-samples
BOUML_SAMPLE = "SecondStageModels__CDKatalog.xmi"

XMI21 = "http://schema.omg.org/spec/XMI/2.1"
UML21 = "http://schema.omg.org/spec/UML/2.1"
XMI_ECLIPSE = "http://www.omg.org/spec/XMI/20131001"
UML_ECLIPSE = "http://www.eclipse.org/uml2/5.0.0/UML"
PRIMITIVES = "pathmap://UML_LIBRARIES/UMLPrimitiveTypes.library.uml#"
METAMODEL = "pathmap://UML_METAMODELS/UML.metamodel.uml#"
BOUML_HREF = "http://schema.omg.org/spec/UML/2.1/uml.xml#"

_PARSER = etree.XMLParser(resolve_entities=False, no_network=True, huge_tree=False)


def _parse(path: Path) -> etree._ElementTree:
    return etree.parse(str(path), _PARSER)


def _sample(name: str) -> etree._ElementTree:
    """A real export: skip without it, fail when CI=true (see tests.support.toolchain)."""
    return _parse(xmi_sample(name))


def _tags() -> Iterator[tuple[Stereotype, Tag]]:
    for st in profile():
        for tag in st.tags:
            yield st, tag


# --- up to date and idempotent -------------------------------------------------------------------


def test_shipped_files_are_up_to_date(tmp_path):
    written = profile_files.write_profiles(tmp_path)
    assert {p.name for p in written} == {SHIPPED_BOUML.name, SHIPPED_ECLIPSE.name}
    for shipped in (SHIPPED_BOUML, SHIPPED_ECLIPSE):
        assert shipped.is_file(), f"{shipped} is missing: run `python -m acordcs.profile`"
        assert (tmp_path / shipped.name).read_bytes() == shipped.read_bytes(), (
            f"{shipped} is stale against the declaration in acordcs.ecore: "
            "run `python -m acordcs.profile` and commit the result"
        )


def test_output_is_byte_identical_on_rerun(tmp_path):
    assert profile_files.bouml_xmi() == profile_files.bouml_xmi()
    assert profile_files.eclipse_profile() == profile_files.eclipse_profile()
    profile_files.write_profiles(tmp_path)
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in tmp_path.iterdir()}
    assert profile_files.write_profiles(tmp_path) == [], (
        "an unchanged profile must not be rewritten"
    )
    after = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in tmp_path.iterdir()}
    assert before == after


def test_changed_file_is_rewritten(tmp_path):
    profile_files.write_profiles(tmp_path)
    (tmp_path / SHIPPED_ECLIPSE.name).write_bytes(b"stale")
    assert profile_files.write_profiles(tmp_path) == [tmp_path / SHIPPED_ECLIPSE.name]
    assert (tmp_path / SHIPPED_ECLIPSE.name).read_bytes() == profile_files.eclipse_profile()


def test_write_into_missing_directory_says_what_to_do(tmp_path):
    with pytest.raises(NotADirectoryError, match="not a directory"):
        profile_files.write_profiles(tmp_path / "nowhere")


def test_undeclarable_tag_type_is_refused():
    bad = Stereotype("X", ("Class",), (Tag("t", "Complex", None, (), "t"),))
    with pytest.raises(profile_files.ProfileExportError, match=r"X\.t has type 'Complex'"):
        profile_files.eclipse_profile([bad])
    with pytest.raises(profile_files.ProfileExportError, match="metaclass"):
        profile_files.bouml_xmi([Stereotype("Y", (), ())])


# --- BOUML XMI -----------------------------------------------------------------------------------

B_NS = {"xmi": XMI21, "uml": UML21}


def _bx(node, path: str, **vars_):
    return node.xpath(path, namespaces=B_NS, **vars_)


def _bouml_profile():
    tree = _parse(SHIPPED_BOUML)
    profiles = _bx(tree, "//packagedElement[@xmi:type='uml:Profile'][@name=$n]", n=PROFILE_NAME)
    assert len(profiles) == 1, f"{SHIPPED_BOUML}: expected one uml:Profile named {PROFILE_NAME}"
    return tree, profiles[0]


def _ids(tree) -> dict[str, etree._Element]:
    ids: dict[str, etree._Element] = {}
    for el in tree.iter():
        for key in (f"{{{XMI21}}}id", f"{{{XMI_ECLIPSE}}}id"):
            if key in el.attrib:
                assert el.get(key) not in ids, f"duplicate xmi:id {el.get(key)}"
                ids[el.get(key)] = el
    return ids


def test_bouml_has_exactly_the_declared_stereotypes():
    _, prof = _bouml_profile()
    names = _bx(prof, "packagedElement[@xmi:type='uml:Stereotype']/@name")
    assert sorted(names) == sorted(s.name for s in profile())


def test_bouml_stereotypes_extend_their_metaclasses():
    tree, prof = _bouml_profile()
    ids = _ids(tree)
    for st in profile():
        (el,) = _bx(prof, "packagedElement[@xmi:type='uml:Stereotype'][@name=$n]", n=st.name)
        bases = _bx(el, "ownedAttribute[starts-with(@name, 'base_')]")
        assert {b.get("name") for b in bases} == {f"base_{m}" for m in st.metaclasses}
        for b in bases:
            metaclass = b.get("name")[len("base_") :]
            assert _bx(b, "type/@href") == [BOUML_HREF + metaclass]
            ext = ids[b.get("association")]
            assert ext.get(f"{{{XMI21}}}type") == "uml:Extension"
            assert b.get(f"{{{XMI21}}}id") in ext.get("memberEnd").split()
            (end,) = _bx(ext, "ownedEnd[@xmi:type='uml:ExtensionEnd']")
            assert end.get("type") == el.get(f"{{{XMI21}}}id")
        # BOUML keeps the extended metaclasses in this property of its "stereotype" class.
        (ext_prop,) = _bx(el, "xmi:Extension/taggedValue[@tag='stereotypeExtension']/@value")
        assert ext_prop.split() == [BOUML_HREF + m for m in st.metaclasses]
        assert _bx(el, "xmi:Extension/stereotype/@name") == ["stereotype"]


def test_bouml_tags_have_type_default_and_permitted_values():
    tree, prof = _bouml_profile()
    ids = _ids(tree)
    bouml_types = {"String": "String", "Integer": "Integer", "Boolean": "Boolean"}
    for st in profile():
        (el,) = _bx(prof, "packagedElement[@xmi:type='uml:Stereotype'][@name=$n]", n=st.name)
        tag_names = _bx(el, "ownedAttribute[not(starts-with(@name, 'base_'))]/@name")
        assert sorted(tag_names) == sorted(t.name for t in st.tags), st.name
        for tag in st.tags:
            where = f"{SHIPPED_BOUML.name}: {st.name}.{tag.name}"
            (attr,) = _bx(el, "ownedAttribute[@name=$n]", n=tag.name)
            (type_el,) = _bx(attr, "type")
            idref = type_el.get(f"{{{XMI21}}}idref")
            if tag.values:
                assert idref in ids, f"{where}: type is not a reference to an enumeration"
                enum = ids[idref]
                assert enum.get(f"{{{XMI21}}}type") == "uml:Enumeration", where
                assert enum.get("name") == tag.type, where
                assert tuple(_bx(enum, "ownedLiteral/@name")) == tag.values, where
            elif tag.type in bouml_types:
                assert type_el.get("href") == BOUML_HREF + bouml_types[tag.type], where
            else:
                # As BOUML writes `double`: a uml:DataType of that name.
                assert tag.type == "Real", where
                assert idref in ids, f"{where}: type is not a reference to a DataType"
                dt = ids[idref]
                assert dt.get(f"{{{XMI21}}}type") == "uml:DataType", where
                assert dt.get("name") == "double", where
            defaults = _bx(attr, "defaultValue[@xmi:type='uml:LiteralString']/@value")
            assert defaults == ([] if tag.default is None else [tag.default]), where


def test_bouml_references_resolve():
    tree, _ = _bouml_profile()
    ids = _ids(tree)
    for el in tree.iter():
        for key in (f"{{{XMI21}}}idref", "association", "type", "metamodelReference"):
            if key in el.attrib and not (key == "type" and el.tag == "type"):
                assert el.get(key) in ids, f"{key}={el.get(key)!r} on line {el.sourceline} dangles"
        for ref in (el.get("memberEnd") or "").split():
            assert ref in ids, f"memberEnd {ref!r} on line {el.sourceline} dangles"


def test_bouml_shape_matches_a_real_bouml_profile():
    sample = _sample(BOUML_SAMPLE).getroot()
    ours = _parse(SHIPPED_BOUML).getroot()
    assert ours.tag == sample.tag == f"{{{XMI21}}}XMI"
    assert ours.get(f"{{{XMI21}}}version") == sample.get(f"{{{XMI21}}}version") == "2.1"
    assert ours.nsmap["uml"] == sample.nsmap["uml"]
    assert ours.nsmap["xmi"] == sample.nsmap["xmi"]

    def shape(root):
        (prof,) = _bx(root, "//packagedElement[@xmi:type='uml:Profile']")
        st = _bx(prof, "packagedElement[@xmi:type='uml:Stereotype']")[0]
        ext = _bx(prof, "packagedElement[@xmi:type='uml:Extension']")[0]
        mmr = prof.get("metamodelReference")
        return {
            "profile stereotype": _bx(prof, "xmi:Extension/stereotype/@name"),
            "metamodelReference is a packageImport": bool(
                _bx(prof, "packageImport[@xmi:id=$i]/importedPackage/@href", i=mmr)
            ),
            "stereotype keys": {k for k in st.attrib if k != "isAbstract"},
            "stereotype extension": _bx(st, "xmi:Extension/stereotype/@name"),
            "base type": _bx(st, "ownedAttribute[starts-with(@name,'base_')]/type/@xmi:type")[:1],
            "extension keys": set(ext.attrib),
            "extension end": _bx(ext, "ownedEnd/@xmi:type"),
        }

    assert shape(ours) == shape(sample)


# --- Eclipse UML2 / Papyrus ----------------------------------------------------------------------

E_NS = {"xmi": XMI_ECLIPSE, "uml": UML_ECLIPSE}


def _ex(node, path: str, **vars_):
    return node.xpath(path, namespaces=E_NS, **vars_)


def _eclipse_profile():
    tree = _parse(SHIPPED_ECLIPSE)
    (prof,) = _ex(tree, "/xmi:XMI/uml:Profile[@name=$n]", n=PROFILE_NAME)
    return tree, prof


def _eid(el) -> str:
    return el.get(f"{{{XMI_ECLIPSE}}}id")


def test_eclipse_has_exactly_the_declared_stereotypes():
    _, prof = _eclipse_profile()
    names = _ex(prof, "packagedElement[@xmi:type='uml:Stereotype']/@name")
    assert sorted(names) == sorted(s.name for s in profile())


def test_eclipse_stereotypes_extend_their_metaclasses():
    tree, prof = _eclipse_profile()
    ids = _ids(tree)
    referenced = set(prof.get("metaclassReference").split())
    for st in profile():
        (el,) = _ex(prof, "packagedElement[@xmi:type='uml:Stereotype'][@name=$n]", n=st.name)
        bases = _ex(el, "ownedAttribute[starts-with(@name, 'base_')]")
        assert {b.get("name") for b in bases} == {f"base_{m}" for m in st.metaclasses}
        for b in bases:
            metaclass = b.get("name")[len("base_") :]
            assert _ex(b, "type[@xmi:type='uml:Class']/@href") == [METAMODEL + metaclass]
            if len(st.metaclasses) > 1:
                # Applied to one metaclass, the other base_* stays empty: it must be optional.
                assert _ex(b, "lowerValue[not(@value) or @value='0']"), f"{st.name}.{b.get('name')}"
            ext = ids[b.get("association")]
            assert ext.get(f"{{{XMI_ECLIPSE}}}type") == "uml:Extension"
            (end,) = _ex(ext, "ownedEnd[@xmi:type='uml:ExtensionEnd']")
            assert end.get("type") == _eid(el)
            assert end.get("aggregation") == "composite"
            assert end.get("association") == _eid(ext)
            assert ext.get("memberEnd").split() == [_eid(end), _eid(b)]
            imports = _ex(prof, "elementImport[importedElement/@href=$h]", h=METAMODEL + metaclass)
            assert len(imports) == 1 and _eid(imports[0]) in referenced, metaclass


def test_eclipse_tags_have_type_default_and_permitted_values():
    tree, prof = _eclipse_profile()
    ids = _ids(tree)
    literal_kinds = {
        "String": "uml:LiteralString",
        "Real": "uml:LiteralReal",
        "Integer": "uml:LiteralInteger",
        "Boolean": "uml:LiteralBoolean",
    }
    for st in profile():
        (el,) = _ex(prof, "packagedElement[@xmi:type='uml:Stereotype'][@name=$n]", n=st.name)
        tag_names = _ex(el, "ownedAttribute[not(starts-with(@name, 'base_'))]/@name")
        assert sorted(tag_names) == sorted(t.name for t in st.tags), st.name
        for tag in st.tags:
            where = f"{SHIPPED_ECLIPSE.name}: {st.name}.{tag.name}"
            (attr,) = _ex(el, "ownedAttribute[@name=$n]", n=tag.name)
            assert _ex(attr, "lowerValue[not(@value) or @value='0']"), f"{where}: not optional"
            assert _ex(attr, "upperValue/@value") == ["1"], where
            defaults = _ex(attr, "defaultValue")
            if tag.values:
                assert attr.get("type") in ids, f"{where}: type is not an enumeration of the file"
                enum = ids[attr.get("type")]
                assert enum.get(f"{{{XMI_ECLIPSE}}}type") == "uml:Enumeration", where
                assert enum.get("name") == tag.type, where
                assert tuple(_ex(enum, "ownedLiteral/@name")) == tag.values, where
                if tag.default is not None:
                    (d,) = defaults
                    assert d.get(f"{{{XMI_ECLIPSE}}}type") == "uml:InstanceValue", where
                    assert d.get("instance") in ids, f"{where}: default names no literal"
                    assert ids[d.get("instance")].get("name") == tag.default, where
                    assert ids[d.get("instance")].getparent() is enum, where
            else:
                assert _ex(attr, "type/@href") == [PRIMITIVES + tag.type], where
                if tag.default is not None:
                    (d,) = defaults
                    assert d.get(f"{{{XMI_ECLIPSE}}}type") == literal_kinds[tag.type], where
                    assert d.get("value") == tag.default, where
            if tag.default is None:
                assert defaults == [], where


def test_eclipse_references_resolve():
    tree, _ = _eclipse_profile()
    ids = _ids(tree)
    for el in tree.iter():
        for key in (
            "association",
            "type",
            "instance",
            "annotatedElement",
            "base_Package",
            "references",
            "eType",
        ):
            value = el.get(key)
            if value is not None:
                assert value in ids, f"{key}={value!r} on line {el.sourceline} dangles"
        for key in ("memberEnd", "metaclassReference"):
            for ref in (el.get(key) or "").split():
                assert ref in ids, f"{key} {ref!r} on line {el.sourceline} dangles"
        href = el.get("href")
        if href is not None:  # UML2's libraries, or (the definition) the UML metamodel's Ecore
            assert href.startswith(("pathmap://", "http://www.eclipse.org/uml2/5.0.0/")), (
                f"href {href!r} on line {el.sourceline}"
            )


def test_eclipse_shape_matches_the_real_codegen_profile():
    sample = _sample(CODEGEN_SAMPLE).getroot()
    ours = _parse(SHIPPED_ECLIPSE).getroot()
    assert ours.tag == sample.tag
    assert ours.get(f"{{{XMI_ECLIPSE}}}version") == sample.get(f"{{{XMI_ECLIPSE}}}version")
    assert ours.nsmap == sample.nsmap
    schema = "{http://www.w3.org/2001/XMLSchema-instance}schemaLocation"
    assert ours.get(schema) == sample.get(schema)

    def order(prof) -> list[str]:
        kinds: list[str] = []
        for child in prof:
            if not kinds or kinds[-1] != child.tag:
                kinds.append(child.tag)
        return kinds

    def shape(root):
        (prof,) = _ex(root, "/xmi:XMI/uml:Profile")
        ext = _ex(prof, "packagedElement[@xmi:type='uml:Extension']")[0]
        base = _ex(prof, "packagedElement/ownedAttribute[starts-with(@name,'base_')]")[0]
        enum = _ex(prof, "packagedElement[@xmi:type='uml:Enumeration']")[0]
        applied = next(el for el in root if el.tag.endswith("}EPackage"))
        return {
            "profile keys": set(prof.attrib),
            # The sample is not defined (no eAnnotations): test_papyrus_definition checks ours.
            "child order": [t for t in order(prof) if t not in ("packagedElement", "eAnnotations")],
            "extension keys": set(ext.attrib),
            "extension end keys": set(_ex(ext, "ownedEnd")[0].attrib),
            "base keys": set(base.attrib),
            "base type": [
                (t.get(f"{{{XMI_ECLIPSE}}}type"), t.get("href").split("#")[0])
                for t in _ex(base, "type")
            ],
            "enumeration literal kind": _ex(enum, "ownedLiteral/@xmi:type")[:1],
            "Ecore application keys": set(applied.attrib),
            "profile application": _ex(prof, "profileApplication/appliedProfile/@href"),
        }

    assert shape(ours) == shape(sample)
