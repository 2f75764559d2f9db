"""The BOUML samples and the synthetic benchmark model: well-formed, BOUML-shaped, and consistent.

This is an independent oracle for the reader and the validator: it reads the XMI with nothing but
lxml and XPath, computes the ACORD-CS structure itself from docs/modelling.md (relations between
stereotyped classes carry deployment, ports, connections, policy membership, adapts, feeds and
sources; a rule's scope is the attributes of the monitors feeding its set, of the elements the set
adapts and of an adapted component's ports), and uses only the project's rule parser
(``parse_rule``, ``parse_terms``) and profile declaration.
"""

from __future__ import annotations

import importlib.util
import itertools
import keyword
import re
from collections import defaultdict
from dataclasses import dataclass, field
from functools import cache
from pathlib import Path

import pytest
from lxml import etree

from acordcs.profile import profile
from acordcs.rules import Assign, Call, Consequent, parse_rule, parse_terms
from tests.support.toolchain import ROOT, SMARTROOM, WEBLAB

XMI = "http://schema.omg.org/spec/XMI/2.1"
ACORDCS = "http:///schemas/ACORDCS/1"
NS = {"xmi": XMI, "ACORDCS": ACORDCS}
XID = f"{{{XMI}}}id"
XTYPE = f"{{{XMI}}}type"
XIDREF = f"{{{XMI}}}idref"

BOUML_ID = re.compile(
    r"^(themodel|COMMENT_\d+|BOUML_(0x[0-9a-f]+_\d+"
    r"|(ASSOC|REVERSE|MULTIPLICITY_L|MULTIPLICITY_U|VALUE|PRFA|STELT|EXT|EXTEND|BASE|MMR)_0x[0-9a-f]+_\d+"
    r"|datatype_\d+|op_param_\d+|return_\d+))$"
)
JAVA_KEYWORDS = frozenset(
    (
        "abstract",
        "assert",
        "boolean",
        "break",
        "byte",
        "case",
        "catch",
        "char",
        "class",
        "const",
        "continue",
        "default",
        "do",
        "double",
        "else",
        "enum",
        "extends",
        "final",
        "finally",
        "float",
        "for",
        "goto",
        "if",
        "implements",
        "import",
        "instanceof",
        "int",
        "interface",
        "long",
        "native",
        "new",
        "package",
        "private",
        "protected",
        "public",
        "return",
        "short",
        "static",
        "strictfp",
        "super",
        "switch",
        "synchronized",
        "this",
        "throw",
        "throws",
        "transient",
        "try",
        "void",
        "volatile",
        "while",
        "true",
        "false",
        "null",
        "var",
        "record",
        "yield",
        "sealed",
        "permits",
    )
)
IDENT = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
STEREOTYPES = {s.name: s for s in profile()}


def valid_identifier(name: str) -> bool:
    return bool(IDENT.match(name)) and not keyword.iskeyword(name) and name not in JAVA_KEYWORDS


def load_generator():
    from tools.bouml_writer import synthetic

    return synthetic


# ------------------------------------------------------------------------ the independent reading
@dataclass
class Element:
    id: str
    name: str
    node: etree._Element
    stereotype: str | None = None  # ACORDCS stereotype name (from the root-level application)
    tags: dict[str, str] = field(default_factory=dict)


@dataclass
class Model:
    path: Path
    tree: etree._ElementTree
    by_id: dict[str, etree._Element]
    classes: dict[str, Element]  # class id -> element
    attributes: dict[str, Element]  # attribute id -> element
    root_apps: dict[tuple[str, str], dict[str, str]]  # (base id, stereotype) -> tags
    ext_apps: dict[tuple[str, str], dict[str, str]]
    related: dict[str, set[str]]  # class id -> ids of classes joined by an association/dependency

    def of(self, stereotype: str) -> list[Element]:
        return [c for c in self.classes.values() if c.stereotype == stereotype]

    def neighbours(self, cls: Element, stereotype: str) -> list[Element]:
        return [
            self.classes[i]
            for i in sorted(self.related[cls.id])
            if self.classes[i].stereotype == stereotype
        ]

    def attrs(self, cls: Element) -> dict[str, etree._Element]:
        """Owned properties that are not association ends."""
        return {
            a.get("name"): a
            for a in cls.node.xpath(
                "ownedAttribute[@xmi:type='uml:Property'][not(@association)]", namespaces=NS
            )
        }

    def ops(self, cls: Element) -> dict[str, etree._Element]:
        return {o.get("name"): o for o in cls.node.xpath("ownedOperation", namespaces=NS)}

    def rules(self, policy: Element) -> list[str]:
        out = []
        for tag, value in policy.tags.items():
            if tag.startswith("Rule"):
                out += [ln.strip() for ln in value.splitlines() if ln.strip()]
        return out


@cache
def read(path: Path) -> Model:
    parser = etree.XMLParser(resolve_entities=False, no_network=True, remove_comments=False)
    tree = etree.parse(str(path), parser)
    root = tree.getroot()
    by_id: dict[str, etree._Element] = {}
    for el in root.iter():
        i = el.get(XID)
        if i is not None:
            assert i not in by_id, f"duplicate xmi:id {i}"
            by_id[i] = el
    classes = {
        c.get(XID): Element(c.get(XID), c.get("name"), c)
        for c in root.xpath("//packagedElement[@xmi:type='uml:Class']", namespaces=NS)
    }
    attributes = {
        a.get(XID): Element(a.get(XID), a.get("name"), a)
        for a in root.xpath(
            "//packagedElement[@xmi:type='uml:Class']/ownedAttribute[not(@association)]",
            namespaces=NS,
        )
    }
    root_apps = {}
    for app in root.xpath("/xmi:XMI/ACORDCS:*", namespaces=NS):
        st = etree.QName(app).localname
        tags = {
            k: v for k, v in app.attrib.items() if not k.startswith("{") and k != "base_Element"
        }
        key = (app.get("base_Element"), st)
        assert key not in root_apps, f"stereotype {st} applied twice to {key[0]}"
        root_apps[key] = tags
    ext_apps = {}
    for ext in root.xpath("//xmi:Extension[@extender='Bouml'][stereotype]", namespaces=NS):
        for st in ext.xpath("stereotype/@name"):
            if not st.startswith("ACORDCS:"):
                continue
            name = st.split(":", 1)[1]
            prefix = f"{st}:"
            tags = {
                tv.get("tag")[len(prefix) :]: tv.get("value")
                for tv in ext.xpath("taggedValue")
                if tv.get("tag").startswith(prefix)
            }
            ext_apps[(ext.getparent().get(XID), name)] = tags
    for (base, st), tags in root_apps.items():
        target = classes.get(base) or attributes.get(base)
        if target is not None:
            target.stereotype, target.tags = st, tags
    related: dict[str, set[str]] = defaultdict(set)
    for assoc in root.xpath("//packagedElement[@xmi:type='uml:Association']", namespaces=NS):
        ends = [by_id[i] for i in assoc.xpath("memberEnd/@xmi:idref", namespaces=NS)]
        types = []
        for end in ends:
            t = end.get("type") or end.xpath("type/@xmi:idref", namespaces=NS)[0]
            types.append(t)
        a, b = types
        related[a].add(b)
        related[b].add(a)
    for dep in root.xpath("//packagedElement[@xmi:type='uml:Dependency']", namespaces=NS):
        a, b = dep.get("client"), dep.get("supplier")
        related[a].add(b)
        related[b].add(a)
    return Model(path, tree, by_id, classes, attributes, root_apps, ext_apps, related)


@pytest.fixture(scope="session")
def synthetic_file(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("synthetic") / "synthetic.xmi"
    load_generator().write(out, classes=2000, seed=7)
    return out


@pytest.fixture(params=["weblab", "smartroom", "synthetic"], scope="module")
def model(request) -> Model:
    paths = {"weblab": WEBLAB, "smartroom": SMARTROOM}
    path = paths.get(request.param) or request.getfixturevalue("synthetic_file")
    return read(path)


# ------------------------------------------------------------------------------ scope per docs
def scope(m: Model, pset: Element) -> tuple[list[Element], list[Element]]:
    """(monitors feeding the set, elements in scope: those monitors, adapted elements, ports)."""
    monitors = m.neighbours(pset, "CtxMonitor")
    adapted = []
    for st in ("CtxContainer", "CtxComponent", "CtxPort", "CtxPortConnection"):
        adapted += m.neighbours(pset, st)
    ports = [
        p for c in adapted if c.stereotype == "CtxComponent" for p in m.neighbours(c, "CtxPort")
    ]
    seen, out = set(), []
    for e in monitors + adapted + ports:
        if e.id not in seen:
            seen.add(e.id)
            out.append(e)
    return monitors, out


def resolve(m: Model, elements: list[Element], text: str) -> tuple[Element, etree._Element]:
    head, dot, member = text.rpartition(".")
    if dot:
        hits = [
            (e, m.attrs(e)[member]) for e in elements if e.name == head and member in m.attrs(e)
        ]
    else:
        hits = [(e, m.attrs(e)[member]) for e in elements if member in m.attrs(e)]
    assert len(hits) == 1, f"{text}: {len(hits)} attributes in scope {[e.name for e in elements]}"
    return hits[0]


def membership_breakpoints(term) -> list[float]:
    return list(term.parameters[0::2]) if term.shape == "points" else list(term.parameters)


def mu(term, x: float) -> float:
    p = term.parameters
    if term.shape == "trapezoid":
        a, b, c, d = p
        if b <= x <= c:
            return 1.0
        if a < x < b:
            return (x - a) / (b - a)
        if c < x < d:
            return (d - x) / (d - c)
        return 0.0
    if term.shape == "triangle":
        a, b, c = p
        if x == b:
            return 1.0
        if a < x < b:
            return (x - a) / (b - a)
        if b < x < c:
            return (c - x) / (c - b)
        return 0.0
    if term.shape == "singleton":
        return 1.0 if x == p[0] else 0.0
    return 1.0  # gauss, gbell, sigm: positive everywhere


def terms_of(attr: Element) -> dict[str, object]:
    return {t.name.text: t for t in parse_terms(attr.tags["terms"])}


# ---------------------------------------------------------------------------------------- tests
def test_envelope_is_bouml(model: Model):
    root = model.tree.getroot()
    text = model.path.read_text(encoding="utf-8")
    assert text.startswith('<?xml version="1.0" encoding="UTF-8"?>')
    assert root.tag == f"{{{XMI}}}XMI"
    assert root.get(f"{{{XMI}}}version") == "2.1"
    assert re.fullmatch(r"http://schema\.omg\.org/spec/UML/2\.[123]", root.nsmap["uml"])
    assert root.nsmap["ACORDCS"] == ACORDCS
    doc = root.find(f"{{{XMI}}}Documentation")
    assert doc is not None and doc.get("exporter") == "Bouml" and doc.get("exporterVersion")
    children = [c for c in root if isinstance(c.tag, str)]
    assert children[0] is doc
    the_model = children[1]
    assert etree.QName(the_model).localname == "Model" and the_model.get(XID) == "themodel"
    assert the_model.get(XTYPE) == "uml:Model"
    # after </uml:Model>: only root-level stereotype applications
    for app in children[2:]:
        assert etree.QName(app).namespace == ACORDCS
        assert app.get(XID) == "BOUML_STELT_" + app.get("base_Element")[len("BOUML_") :]
    # BOUML writes packages as `name ="x"`
    for line in text.splitlines():
        if 'xmi:type="uml:Package"' in line or 'xmi:type="uml:Profile"' in line:
            assert ' name ="' in line, line
    # the root package carries the exporter options, generate-extensions on
    rootpkg = the_model.find("packagedElement")
    assert rootpkg.get(XID) == "BOUML_0x81_22"
    opts = {
        tv.get("tag"): tv.get("value")
        for tv in rootpkg.xpath("xmi:Extension/taggedValue", namespaces=NS)
    }
    assert opts["gxmi gen extensions"] == "yes" and opts["gxmi encoding"] == "UTF-8"


def test_ids_are_bouml_and_references_resolve(model: Model):
    root = model.tree.getroot()
    for i in model.by_id:
        assert BOUML_ID.match(i), i
    for ref in root.xpath("//@xmi:idref", namespaces=NS):
        assert ref in model.by_id, f"dangling xmi:idref {ref}"
    for attr in ("general", "client", "supplier", "association", "base_Element"):
        for ref in root.xpath(f"//@{attr}"):
            assert ref in model.by_id, f"dangling {attr} {ref}"
    for ref in root.xpath("//ownedEnd[@xmi:type='uml:Property']/@type", namespaces=NS):
        assert ref in model.by_id
    # non-primitive types are DataTypes at the end of the root package, primitives are OMG hrefs
    rootpkg = root.xpath(
        "/xmi:XMI/uml:Model/packagedElement", namespaces={**NS, "uml": root.nsmap["uml"]}
    )[0]
    kinds = [c.get(XTYPE) for c in rootpkg if isinstance(c.tag, str) and c.tag == "packagedElement"]
    n_dt = kinds.count("uml:DataType")
    assert n_dt >= 1 and set(kinds[len(kinds) - n_dt :]) == {"uml:DataType"}
    for t in root.xpath("//type[@href]"):
        assert t.get(XTYPE) == "uml:PrimitiveType" or t.get("href").endswith("#Element")
        assert t.get("href").startswith("http://schema.omg.org/spec/UML/2.")
    for t in root.xpath("//type[@xmi:idref]", namespaces=NS):
        assert model.by_id[t.get(XIDREF)].get(XTYPE) in ("uml:DataType", "uml:Class")


def test_associations_have_bouml_shape(model: Model):
    root = model.tree.getroot()
    assocs = root.xpath("//packagedElement[@xmi:type='uml:Association']", namespaces=NS)
    assert assocs
    for a in assocs:
        assert a.get("memberEnd") is None
        ends = a.xpath("memberEnd/@xmi:idref", namespaces=NS)
        assert len(ends) == 2 and a.get(XID).startswith("BOUML_ASSOC_")
        for e in ends:
            end = model.by_id[e]
            assert end.get("association") == a.get(XID)
            if end.tag == "ownedEnd":
                assert end.getparent() is a and end.get("isNavigable") == "false"
                assert e.startswith("BOUML_REVERSE_")
            else:
                assert end.tag == "ownedAttribute" and end.getparent().get(XTYPE) == "uml:Class"


def test_profile_is_in_the_model(model: Model):
    root = model.tree.getroot()
    applied = root.xpath("//profileApplication/appliedProfile/@xmi:idref", namespaces=NS)
    assert len(applied) == 1
    prof = model.by_id[applied[0]]
    assert prof.get(XTYPE) == "uml:Profile" and prof.get("name") == "ACORDCS"
    declared = {
        s.get("name"): s
        for s in prof.xpath("packagedElement[@xmi:type='uml:Stereotype']", namespaces=NS)
    }
    assert set(declared) == set(STEREOTYPES)
    for name, st in STEREOTYPES.items():
        tags = set(declared[name].xpath("ownedAttribute/@name")) - {"base_Element"}
        assert tags == {t.name for t in st.tags}


def test_both_stereotype_places_agree(model: Model):
    assert model.root_apps, "no root-level stereotype applications"
    assert model.root_apps == model.ext_apps
    for (base, st), tags in model.root_apps.items():
        assert st in STEREOTYPES, st
        assert set(tags) == {t.name for t in STEREOTYPES[st].tags}, (st, tags)
        node = model.by_id[base]
        if st == "CtxVariable":
            assert node.tag == "ownedAttribute" and node.get("association") is None
        else:
            assert node.get(XTYPE) == "uml:Class"
        for t in STEREOTYPES[st].tags:
            # an enumeration without a default may be left unset: BOUML writes it empty
            unset_allowed = t.default is None and tags[t.name] == ""
            if t.values and not unset_allowed:
                assert tags[t.name] in t.values, (st, t.name, tags[t.name])


def test_names_are_identifiers(model: Model):
    synthetic = model.path.name == "synthetic.xmi"
    for c in model.classes.values():
        if synthetic and c.stereotype is None:
            continue
        assert valid_identifier(c.name), c.name
        for a in c.node.xpath("ownedAttribute[not(@association)]/@name"):
            assert valid_identifier(a), (c.name, a)
        for o in c.node.xpath("ownedOperation"):
            assert valid_identifier(o.get("name")), (c.name, o.get("name"))
            for p in o.xpath("ownedParameter[@direction='in']/@name"):
                assert valid_identifier(p), (c.name, o.get("name"), p)
    ctx_names = [c.name for c in model.classes.values() if c.stereotype]
    assert len(ctx_names) == len(set(ctx_names)), "ACORD-CS class names must be unique"


def test_terms_parse_and_cover_the_range(model: Model):
    variables = [a for a in model.attributes.values() if a.stereotype == "CtxVariable"]
    assert variables
    for v in variables:
        lo, hi = float(v.tags["min"]), float(v.tags["max"])
        assert lo < hi, v.name
        terms = parse_terms(v.tags["terms"])
        names = [t.name.text for t in terms]
        assert len(names) == len(set(names)) and all(valid_identifier(n) for n in names)
        xs = {lo, hi}
        for t in terms:
            for x in membership_breakpoints(t):
                assert lo <= x <= hi, f"{v.name}: {t.name.text} leaves [{lo}, {hi}]"
                xs.add(x)
        xs = sorted(xs)
        probes = xs + [(a + b) / 2 for a, b in itertools.pairwise(xs)]
        for x in probes:
            assert max(mu(t, x) for t in terms) > 0, f"{v.name}: {x} is not covered"


def test_structure(model: Model):
    for st in ("CtxComponent", "CtxMonitor", "CtxPolicySet"):
        for e in model.of(st):
            hosts = model.neighbours(e, "CtxContainer")
            assert len(hosts) == 1, f"{e.name} deployed in {[h.name for h in hosts]}"
    for mon in model.of("CtxMonitor"):
        assert model.neighbours(mon, "CtxPolicySet"), f"{mon.name} feeds no policy set"
        f = mon.tags["frequency"]
        assert f == "" or float(f) > 0
    for pset in model.of("CtxPolicySet"):
        assert model.neighbours(pset, "CtxPolicy"), f"{pset.name} has no policy"
        if pset.tags["trigger"] == "periodic":
            assert float(pset.tags["frequency"]) > 0
    for conn in model.of("CtxPortConnection"):
        ports = model.neighbours(conn, "CtxPort")
        assert len(ports) == 2, conn.name
        assert {p.tags["role"] for p in ports} == {"provided", "required"}, conn.name
        assert ports[0].tags["kind"] == ports[1].tags["kind"], conn.name
    for port in model.of("CtxPort"):
        assert len(model.neighbours(port, "CtxComponent")) == 1, port.name
    for pol in model.of("CtxPolicy"):
        assert len(model.neighbours(pol, "CtxPolicySet")) == 1, pol.name


def test_rules_parse_and_resolve_in_scope(model: Model):
    n_rules = 0
    for pset in model.of("CtxPolicySet"):
        kind = "fuzzy" if pset.tags["engine"] == "fuzzy" else "crisp"
        _, in_scope = scope(model, pset)
        inputs, outputs = set(), set()
        for pol in model.neighbours(pset, "CtxPolicy"):
            for text in model.rules(pol):
                rule = parse_rule(text, kind)
                n_rules += 1
                assert rule.label and valid_identifier(rule.label), text
                for name in rule.variables_read():
                    _, attr = resolve(model, in_scope, name.text)
                    inputs.add(attr.get(XID))
                for action in rule.actions:
                    if isinstance(action, Consequent | Assign):
                        _, attr = resolve(model, in_scope, action.var.text)
                        outputs.add(attr.get(XID))
                    if isinstance(action, Call):
                        head, dot, op = action.target.text.rpartition(".")
                        owners = [
                            e
                            for e in in_scope
                            if (not dot or e.name == head) and op in model.ops(e)
                        ]
                        assert len(owners) == 1, text
                        params = model.ops(owners[0])[op].xpath(
                            "ownedParameter[@direction!='return']"
                        )
                        assert len(params) == len(action.args), text
                if kind == "fuzzy":
                    for cond in _is_nodes(rule.condition):
                        _, attr = resolve(model, in_scope, cond.var.text)
                        assert cond.term.text in terms_of(model.attributes[attr.get(XID)]), text
                    for cons in rule.actions:
                        _, attr = resolve(model, in_scope, cons.var.text)
                        assert cons.term.text in terms_of(model.attributes[attr.get(XID)]), text
        if kind == "fuzzy":
            assert not inputs & outputs, f"{pset.name}: a fuzzy output is also an input"
            for i in inputs | outputs:
                assert model.attributes[i].stereotype == "CtxVariable"
    assert n_rules > 0


def _is_nodes(node):
    from acordcs.rules import BoolOp, Is, Not

    if isinstance(node, Is):
        yield node
    elif isinstance(node, BoolOp):
        yield from _is_nodes(node.left)
        yield from _is_nodes(node.right)
    elif isinstance(node, Not):
        yield from _is_nodes(node.operand)


# ------------------------------------------------------------------------------ per-sample facts
def _by_name(m: Model, name: str) -> Element:
    hits = [c for c in m.classes.values() if c.name == name]
    assert len(hits) == 1, name
    return hits[0]


def test_weblab_is_figure_4():
    m = read(WEBLAB)
    assert m.tree.getroot().nsmap["uml"].endswith("/2.1")
    components = {c.name for c in m.of("CtxComponent")}
    assert components == {
        "Navigator",
        "Vision",
        "Locomotion",
        "Access",
        "PanoramicCamera",
        "Recovery",
    }
    assert {c.name for c in m.of("CtxMonitor")} == {"Control", "Telemetry", "Usage"}
    assert {c.name for c in m.of("CtxContainer")} == {"UserSide", "WebLabSide"}
    sets = {c.name: c for c in m.of("CtxPolicySet")}
    assert set(sets) == {"SpeedLimiting", "Recovering", "BandwidthLimiting"}
    user = _by_name(m, "UserSide")
    weblab = _by_name(m, "WebLabSide")
    for st in ("CtxComponent", "CtxMonitor", "CtxPolicySet"):
        for e in m.of(st):
            want = user if e.name == "Navigator" else weblab
            assert m.neighbours(e, "CtxContainer") == [want], e.name

    def rules(pset):
        return [r for p in m.neighbours(sets[pset], "CtxPolicy") for r in m.rules(p)]

    speed, recov, bw = rules("SpeedLimiting"), rules("Recovering"), rules("BandwidthLimiting")
    assert len(speed) == 12 and len(bw) == 9 and len(recov) >= 1
    assert sets["SpeedLimiting"].tags | {"frequency": ""} == {
        "engine": "fuzzy",
        "semantics": "mamdani",
        "trigger": "event",
        "frequency": "",
    }
    assert sets["Recovering"].tags["engine"] == "clips"
    assert sets["BandwidthLimiting"].tags["trigger"] == "periodic"
    assert float(sets["BandwidthLimiting"].tags["frequency"]) > 0
    # speed limiting: cycleRate x angle -> maxSpeed; bandwidth: cycleRate x numUsers -> fps
    for text in speed:
        r = parse_rule(text, "fuzzy")
        assert {n.member for n in r.variables_read()} == {"cycleRate", "angle"}
        assert [n.member for n in r.variables_written()] == ["maxSpeed"]
    for text in bw:
        r = parse_rule(text, "fuzzy")
        assert {n.member for n in r.variables_read()} == {"cycleRate", "numUsers"}
        assert [n.member for n in r.variables_written()] == ["fps"]
    calls = {c.target.member for t in recov for c in parse_rule(t, "crisp").calls()}
    assert calls == {"recover", "askUser"}
    assert float(_by_name(m, "Usage").tags["frequency"]) > 0
    assert _by_name(m, "Control").tags["frequency"] == ""  # event-driven: it intercepts calls
    # Navigator's required ports reach the WebLab's provided ports through remote connections
    nav_ports = m.neighbours(_by_name(m, "Navigator"), "CtxPort")
    assert nav_ports and all(p.tags["role"] == "required" for p in nav_ports)
    kinds = {p.tags["kind"] for p in m.of("CtxPort")}
    assert kinds == {"synchronous", "asynchronous", "stream"}
    for p in nav_ports:
        (conn,) = m.neighbours(p, "CtxPortConnection")
        assert conn.tags["connector"] in ("remote", "shaped")
    ops = m.ops(_by_name(m, "Locomotion"))["move"].xpath("ownedParameter/@name")
    assert ops == ["speed", "turn"]
    assert len(m.tree.getroot().xpath("//ownedComment")) >= 5


def test_smartroom_is_another_domain():
    m = read(SMARTROOM)
    assert m.tree.getroot().nsmap["uml"].endswith("/2.3")
    engines = sorted(s.tags["engine"] for s in m.of("CtxPolicySet"))
    assert engines == ["clips", "fuzzy"]
    assert len(m.of("CtxContainer")) == 1


def test_synthetic_size_and_shape(synthetic_file):
    m = read(synthetic_file)
    assert len(m.classes) == 2000
    stereotyped = [c for c in m.classes.values() if c.stereotype]
    assert 0.2 <= len(stereotyped) / 2000 <= 0.3
    sets = m.of("CtxPolicySet")
    assert len(sets) == 100
    for s in sets:
        assert sum(len(m.rules(p)) for p in m.neighbours(s, "CtxPolicy")) == 12
    assert 3_000_000 <= synthetic_file.stat().st_size <= 6_000_000
    plain = [c for c in m.classes.values() if not c.stereotype]
    assert sum(1 for c in plain if c.node.find("ownedComment") is not None) > 100
    assert sum(1 for c in plain if c.node.find("ownedOperation") is not None) > 1000


def test_synthetic_is_deterministic(tmp_path):
    gen = load_generator()
    a = gen.generate(classes=200, seed=3)
    assert a == gen.generate(classes=200, seed=3)
    assert a != gen.generate(classes=200, seed=4)
    out = tmp_path / "s.xmi"
    assert gen.main(["--classes", "200", "--seed", "3", "--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == a
    etree.fromstring(a.encode("utf-8"))


def test_samples_are_up_to_date():
    """The committed samples are what samples/build_samples.py writes."""
    spec = importlib.util.spec_from_file_location(
        "build_samples", ROOT / "samples" / "build_samples.py"
    )
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    for path, text in mod.render().items():
        assert path.read_text(encoding="utf-8") == text, f"{path}: run samples/build_samples.py"


# ------------------------------------------------------------------- the oracle is not vacuous
MUTATIONS = {
    "misspelt variable": (
        "then Locomotion.maxSpeed is slow&#10;smallMedium",
        "then Locomotion.maxSpeedd is slow&#10;smallMedium",
        test_rules_parse_and_resolve_in_scope,
    ),
    "undefined term": (
        "numUsers is low then",
        "numUsers is lowish then",
        test_rules_parse_and_resolve_in_scope,
    ),
    "terms leave a gap": (
        "medium := trian 0.9 1.4 1.9",
        "medium := trian 1.3 1.4 1.45",
        test_terms_parse_and_cover_the_range,
    ),
    "extension disagrees": (
        'tag="ACORDCS:CtxContainer:host" value="user.example.org"',
        'tag="ACORDCS:CtxContainer:host" value="other.example.org"',
        test_both_stereotype_places_agree,
    ),
    "dangling reference": (
        'client="',
        'client="BOUML_0xdead_4" old="',
        test_ids_are_bouml_and_references_resolve,
    ),
}


@pytest.mark.parametrize("name", sorted(MUTATIONS))
def test_oracle_catches_mutations(name, tmp_path):
    old, new, check = MUTATIONS[name]
    text = WEBLAB.read_text(encoding="utf-8")
    if old not in text:
        pytest.skip(f"the sample has no {old!r}")
    path = tmp_path / "mutant.xmi"
    path.write_text(text.replace(old, new), encoding="utf-8")
    with pytest.raises(AssertionError):
        check(read(path))
