"""Write BOUML-style XMI 2.1 models: a small writer, and a synthetic large ACORD-CS model.

The writer imitates what BOUML's ``xmi2`` exporter writes (see ``shared/reference/bouml-xmi.md``
and the real export ``xmi-samples/SecondStageModels__CDKatalog.xmi``): tab indentation,
``name ="x"`` on packages, ``BOUML_<hex>_<kind>`` ids, primitive types as OMG hrefs and every other
type as a ``uml:DataType`` ``BOUML_datatype_N`` at the end of the root package, associations with
``memberEnd`` children and a non-navigable ``ownedEnd`` for one-way relations, the profile inside
the model with its ``profileApplication``, and every ACORDCS stereotype written twice: in an
``xmi:Extension`` block inside the element and as a root-level application after
``</uml:Model>``, with the same tag values.

``synthetic_model(classes=2000, seed=1)`` builds a model of ``classes`` classes, about a quarter
of them with ACORD-CS stereotypes (containers, components, ports, connections, monitors, 100
policy sets of 12 rules each, their policies), that follows the README's section on modelling and should
validate clean: every rule variable is an attribute in the set's scope, every term is defined,
every component, monitor and set is deployed, every monitor feeds a set. The rest are plain
classes with attributes, operations, comments, associations and generalizations, as in a real
large model (about 4.5 MB for 2,000 classes).

CLI: ``python benchmarks/gen_synthetic_bouml.py --classes 2000 --out /tmp/syn.xmi [--seed 1]``.
"""

from __future__ import annotations

import argparse
import random
import sys
from dataclasses import dataclass, field
from pathlib import Path

PROFILE = "ACORDCS"
PROFILE_URI = "http:///schemas/ACORDCS/1"
PRIMITIVES = {
    "int": "Integer",
    "bool": "Boolean",
    "string": "String",
    "long": "UnlimitedNatural",
}


# ---------------------------------------------------------------------------------------- escaping
def esc(text: str) -> str:
    """Escape an XML attribute value as BOUML's ``FileOut::quote``: newlines become ``&#10;``."""
    return (
        str(text)
        .replace("&", "&amp;")
        .replace("<", "&lt;")
        .replace(">", "&gt;")
        .replace('"', "&quot;")
        .replace("\r", "&#13;")
        .replace("\n", "&#10;")
    )


# --------------------------------------------------------------------------------------- the model
@dataclass
class Attr:
    name: str
    type: str  # int, bool, string, long, double, ... or a Cls
    visibility: str = "private"
    default: str | None = None
    stereotype: str | None = None  # "ACORDCS:CtxVariable"
    tags: dict[str, str] = field(default_factory=dict)
    is_static: bool = False
    id: str = ""


@dataclass
class Op:
    name: str
    params: list[tuple[str, object]] = field(default_factory=list)
    returns: object | None = None
    visibility: str = "public"
    id: str = ""


@dataclass
class Cls:
    name: str
    stereotype: str | None = None  # "ACORDCS:CtxComponent" or a free stereotype ("entity")
    tags: dict[str, str] = field(default_factory=dict)
    attrs: list[Attr] = field(default_factory=list)
    ops: list[Op] = field(default_factory=list)
    comment: str | None = None
    general: Cls | None = None
    visibility: str = "package"
    id: str = ""
    gen_id: str = ""
    ends: list[End] = field(default_factory=list)  # navigable association ends owned by this class

    def attr(self, *args, **kw) -> Attr:
        a = Attr(*args, **kw)
        self.attrs.append(a)
        return a

    def op(self, *args, **kw) -> Op:
        o = Op(*args, **kw)
        self.ops.append(o)
        return o


@dataclass
class End:
    name: str
    owner: Cls  # the class at this end's opposite side, which owns it when navigable
    type: Cls
    navigable: bool
    aggregation: str = "none"
    multiplicity: str | None = None
    id: str = ""


@dataclass
class Assoc:
    a: End  # always navigable (BOUML relations start at a class)
    b: End  # navigable for a bidirectional relation, else written as ownedEnd
    name: str | None = None
    id: str = ""


@dataclass
class Dep:
    client: Cls
    supplier: Cls
    id: str = ""


@dataclass
class Pkg:
    name: str
    classes: list[Cls] = field(default_factory=list)
    assocs: list[Assoc] = field(default_factory=list)
    deps: list[Dep] = field(default_factory=list)
    packages: list[Pkg] = field(default_factory=list)
    id: str = ""

    def cls(self, *args, **kw) -> Cls:
        c = Cls(*args, **kw)
        self.classes.append(c)
        return c

    def package(self, name: str) -> Pkg:
        p = Pkg(name)
        self.packages.append(p)
        return p

    def associate(
        self,
        src: Cls,
        dst: Cls,
        role: str,
        *,
        back: str | None = None,
        aggregation: str = "none",
        name: str | None = None,
        multiplicity: str | None = None,
    ) -> Assoc:
        """A BOUML relation from ``src`` to ``dst``; ``back`` makes it bidirectional."""
        a = End(role, src, dst, True, "none", multiplicity)
        b = End(back or "", dst, src, back is not None, aggregation)
        src.ends.append(a)
        if back is not None:
            dst.ends.append(b)
        assoc = Assoc(a, b, name)
        self.assocs.append(assoc)
        return assoc

    def depend(self, client: Cls, supplier: Cls) -> Dep:
        d = Dep(client, supplier)
        self.deps.append(d)
        return d


# ------------------------------------------------------------------------------------------ writer
class BoumlWriter:
    """Serialize a ``Pkg`` tree as BOUML's xmi2 exporter would, the ACORDCS profile in-model."""

    def __init__(
        self,
        model_name: str,
        *,
        uml_version: str = "2.1",
        exporter_version: str = "4.22.2",
        encoding: str = "UTF-8",
        user_id: int = 0x02,
        first: int = 0x1F400,
        gxmi_path: str = "",
    ):
        self.model_name = model_name
        self.uml = uml_version
        self.exporter_version = exporter_version
        self.encoding = encoding
        self.user_id = user_id
        self.first = first
        self.gxmi_path = gxmi_path
        self._next: dict[int, int] = {}
        self._datatypes: dict[str, str] = {}
        self._comments = 0
        self._params = 0
        self._returns = 0
        self.applications: list[tuple[str, str, dict[str, str]]] = []
        self.out: list[str] = []

    # ---- ids
    def new_id(self, kind: int) -> str:
        n = self._next.get(kind, self.first)
        self._next[kind] = n + 0x80
        return f"BOUML_{n + self.user_id:#x}_{kind}"

    def _href(self, name: str) -> str:
        return f"http://schema.omg.org/spec/UML/{self.uml}/uml.xml#{name}"

    def _datatype(self, text: str) -> str:
        if text not in self._datatypes:
            self._datatypes[text] = f"BOUML_datatype_{len(self._datatypes)}"
        return self._datatypes[text]

    def _type(self, t: object, indent: str) -> str:
        if isinstance(t, Cls):
            return f'{indent}<type xmi:type="uml:Class" xmi:idref="{t.id}"/>'
        if t in PRIMITIVES:
            return (
                f'{indent}<type xmi:type="uml:PrimitiveType" href="{self._href(PRIMITIVES[t])}"/>'
            )
        return f'{indent}<type xmi:type="uml:Class" xmi:idref="{self._datatype(str(t))}"/>'

    # ---- stereotypes
    def _extension(self, stereotype: str | None, tags: dict[str, str], indent: str) -> list[str]:
        if not stereotype and not tags:
            return []
        head = f'{indent}<xmi:Extension extender="Bouml">'
        st = f'<stereotype name="{esc(stereotype)}"/>' if stereotype else ""
        if not tags:
            return [f"{head}{st}</xmi:Extension>"]
        lines = [head]
        if st:
            lines.append(f"{indent}\t{st}")
        for k, v in tags.items():
            tag = f"{stereotype}:{k}" if stereotype and stereotype.count(":") == 1 else k
            lines.append(f'{indent}\t<taggedValue tag="{esc(tag)}" value="{esc(v)}"/>')
        lines.append(f"{indent}</xmi:Extension>")
        return lines

    def _apply(self, element_id: str, stereotype: str | None, tags: dict[str, str]) -> None:
        if stereotype and stereotype.startswith(PROFILE + ":"):
            self.applications.append((stereotype, element_id, tags))

    # ---- ids for the whole tree, before writing (references may point forward)
    def _assign(self, pkg: Pkg, root: bool = False) -> None:
        pkg.id = "BOUML_0x81_22" if root else self.new_id(22)
        for c in pkg.classes:
            c.id = self.new_id(4)
        for c in pkg.classes:
            for a in c.attrs:
                a.id = self.new_id(1)
            for o in c.ops:
                o.id = self.new_id(2)
            if c.general is not None:
                c.gen_id = self.new_id(0)
        for a in pkg.assocs:
            a.a.id = self.new_id(0)
            a.b.id = self.new_id(0) if a.b.navigable else f"BOUML_REVERSE_{a.a.id[6:]}"
            a.id = f"BOUML_ASSOC_{a.a.id[6:]}"
        for d in pkg.deps:
            d.id = self.new_id(0)
        for p in pkg.packages:
            self._assign(p)

    # ---- elements
    def _attr(self, a: Attr, ind: str) -> list[str]:
        flags = ' isStatic="true"' if a.is_static else ""
        lines = [
            f'{ind}<ownedAttribute xmi:type="uml:Property" name="{esc(a.name)}" xmi:id="{a.id}"'
            f' visibility="{a.visibility}"{flags}>',
            self._type(a.type, ind + "\t"),
        ]
        if a.default is not None:
            lines.append(
                f'{ind}\t<defaultValue xmi:type="uml:LiteralString" xmi:id="BOUML_VALUE_{a.id[6:]}"'
                f' value="{esc(a.default)}"/>'
            )
        lines += self._extension(a.stereotype, a.tags, ind + "\t")
        self._apply(a.id, a.stereotype, a.tags)
        lines.append(f"{ind}</ownedAttribute>")
        return lines

    def _end(self, e: End, assoc: Assoc, ind: str) -> list[str]:
        lines = [
            f'{ind}<ownedAttribute xmi:type="uml:Property" name="{esc(e.name)}" xmi:id="{e.id}"'
            f' visibility="protected" association="{assoc.id}" aggregation="{e.aggregation}">',
            self._type(e.type, ind + "\t"),
        ]
        if e.multiplicity is not None:
            lo, _, hi = e.multiplicity.partition("..")
            hi = hi or lo
            lines.append(
                f'{ind}\t<lowerValue xmi:type="uml:LiteralString" xmi:id="BOUML_MULTIPLICITY_L_'
                f'{e.id[6:]}" value="{esc(lo)}"/>'
            )
            lines.append(
                f'{ind}\t<upperValue xmi:type="uml:LiteralString" xmi:id="BOUML_MULTIPLICITY_U_'
                f'{e.id[6:]}" value="{esc(hi)}"/>'
            )
        lines.append(f"{ind}</ownedAttribute>")
        return lines

    def _op(self, o: Op, ind: str) -> list[str]:
        lines = [
            f'{ind}<ownedOperation xmi:type="uml:Operation" name="{esc(o.name)}" xmi:id="{o.id}"'
            f' visibility="{o.visibility}" isAbstract="false">'
        ]
        if o.returns is not None:
            self._returns += 1
            lines.append(
                f'{ind}\t<ownedParameter name="return" xmi:id="BOUML_return_{self._returns}"'
                ' direction="return">'
            )
            lines.append(self._type(o.returns, ind + "\t\t"))
            lines.append(f"{ind}\t</ownedParameter>")
        for name, t in o.params:
            self._params += 1
            lines.append(
                f'{ind}\t<ownedParameter xmi:type="uml:Parameter" name="{esc(name)}"'
                f' xmi:id="BOUML_op_param_{self._params}" direction="in">'
            )
            lines.append(self._type(t, ind + "\t\t"))
            lines.append(f"{ind}\t</ownedParameter>")
        lines.append(f"{ind}</ownedOperation>")
        return lines

    def _class(self, c: Cls, ind: str) -> list[str]:
        lines = [
            f'{ind}<packagedElement xmi:type="uml:Class" name="{esc(c.name)}" xmi:id="{c.id}"'
            f' visibility="{c.visibility}">'
        ]
        if c.comment:
            self._comments += 1
            lines.append(
                f'{ind}\t<ownedComment xmi:type="uml:Comment" xmi:id="COMMENT_{self._comments}"'
                f' body="{esc(c.comment)}"/>'
            )
        lines += self._extension(c.stereotype, c.tags, ind + "\t")
        self._apply(c.id, c.stereotype, c.tags)
        if c.general is not None:
            lines.append(
                f'{ind}\t<generalization xmi:type="uml:Generalization" xmi:id="{c.gen_id}"'
                f' general="{c.general.id}"/>'
            )
        for a in c.attrs:
            lines += self._attr(a, ind + "\t")
        for e in c.ends:
            lines += self._end(e, self._assoc_of[id(e)], ind + "\t")
        for o in c.ops:
            lines += self._op(o, ind + "\t")
        lines.append(f"{ind}</packagedElement>")
        return lines

    def _assoc(self, a: Assoc, ind: str) -> list[str]:
        name = f' name="{esc(a.name)}"' if a.name else ""
        lines = [
            f'{ind}<packagedElement xmi:type="uml:Association" xmi:id="{a.id}"{name}'
            f' visibility="protected">',
            f'{ind}\t<memberEnd xmi:idref="{a.a.id}"/>',
        ]
        if a.b.navigable:
            lines.append(f'{ind}\t<memberEnd xmi:idref="{a.b.id}"/>')
        else:
            lines.append(
                f'{ind}\t<ownedEnd xmi:type="uml:Property" xmi:id="{a.b.id}" association="{a.id}"'
                f' visibility="private" type="{a.b.type.id}" aggregation="{a.b.aggregation}"'
                f' isNavigable="false"/>'
            )
            lines.append(f'{ind}\t<memberEnd  xmi:idref="{a.b.id}"/>')
        lines.append(f"{ind}</packagedElement>")
        return lines

    def _package(self, p: Pkg, ind: str, root: bool = False) -> list[str]:
        lines = [
            f'{ind}<packagedElement xmi:type="uml:Package" xmi:id="{p.id}" name ="{esc(p.name)}">'
        ]
        if root:
            lines += self._gxmi(ind + "\t")
        for c in p.classes:
            lines += self._class(c, ind + "\t")
        for d in p.deps:
            lines.append(
                f'{ind}\t<packagedElement xmi:type="uml:Dependency" xmi:id="{d.id}"'
                f' client="{d.client.id}" supplier="{d.supplier.id}">'
            )
            lines.append(f"{ind}\t</packagedElement>")
        for a in p.assocs:
            lines += self._assoc(a, ind + "\t")
        for sub in p.packages:
            lines += self._package(sub, ind + "\t")
        if root:
            lines += self._profile(ind + "\t")
            for text, dt in sorted(self._datatypes.items(), key=lambda kv: kv[0]):
                lines.append(
                    f'{ind}\t<packagedElement xmi:type="uml:DataType" xmi:id="{dt}"'
                    f' name="{esc(text)}"/>'
                )
        lines.append(f"{ind}</packagedElement>")
        return lines

    def _gxmi(self, ind: str) -> list[str]:
        umlv = self.uml.replace(".", "")
        opts = [
            ("gxmi gen extensions", "yes"),
            ("gxmi comment exporter", "no"),
            ("gxmi primitive type", "no"),
            ("gxmi umlversion", umlv),
            ("gxmi gen eclipse", "no"),
            ("gxmi path", self.gxmi_path),
            ("gxmi vis prefix", "no"),
            ("gxmi no model", "no"),
            ("gxmi linefeed", "no"),
            ("gxmi gen views", "no"),
            ("gxmi pk prefix", "no"),
            ("gxmi encoding", self.encoding),
        ]
        lines = [f'{ind}<xmi:Extension extender="Bouml">']
        lines += [f'{ind}\t<taggedValue tag="{k}" value="{esc(v)}"/>' for k, v in opts]
        lines.append(f"{ind}</xmi:Extension>")
        return lines

    # ---- the in-model profile, from the project's own declaration
    def _profile(self, ind: str) -> list[str]:
        from acordcs.profile import profile

        apply_on = {
            "Class": "Class",
            "Component": "Class",
            "AssociationClass": "Class",
            "Port": "Class",
            "Property": "Attribute",
        }
        pid = self._profile_id
        lines = [
            f'{ind}<packagedElement xmi:type="uml:Profile" xmi:id="{pid}" name ="{PROFILE}"'
            f' metamodelReference="BOUML_MMR_{pid[6:]}">',
            f'{ind}\t<xmi:Extension extender="Bouml">',
            f'{ind}\t\t<stereotype name="profile"/>',
            f'{ind}\t\t<taggedValue tag="xmiId" value="{PROFILE}_Profile"/>',
            f'{ind}\t\t<taggedValue tag="metamodelReference" value="{self._href("")[:-1]}"/>',
            f'{ind}\t\t<taggedValue tag="uri" value="{PROFILE_URI}"/>',
            f"{ind}\t</xmi:Extension>",
            f'{ind}\t<packageImport xmi:type="uml:PackageImport" xmi:id="BOUML_MMR_{pid[6:]}">',
            f'{ind}\t\t<importedPackage xmi:type="uml:Model" href="{self._href("1")}"/>',
            f"{ind}\t</packageImport>",
        ]
        i2 = ind + "\t"
        for st in profile():
            sid = self.new_id(4)
            on = " ".join(dict.fromkeys(apply_on.get(m, m) for m in st.metaclasses))
            lines.append(
                f'{i2}<packagedElement xmi:type="uml:Stereotype" name="{st.name}" xmi:id="{sid}"'
                f' visibility="package">'
            )
            self._comments += 1
            doc = st.doc + " Applies to UML " + ", ".join(st.metaclasses) + "."
            lines.append(
                f'{i2}\t<ownedComment xmi:type="uml:Comment" xmi:id="COMMENT_{self._comments}"'
                f' body="{esc(doc.strip())}"/>'
            )
            lines += [
                f'{i2}\t<xmi:Extension extender="Bouml">',
                f'{i2}\t\t<stereotype name="stereotype"/>',
                f'{i2}\t\t<taggedValue tag="stereotypeSetParameters" value=""/>',
                f'{i2}\t\t<taggedValue tag="xmiId" value="{st.name}_ID"/>',
                f'{i2}\t\t<taggedValue tag="stereotypeCheckParameters" value=""/>',
                f'{i2}\t\t<taggedValue tag="stereotypeApplyOn" value="{on}"/>',
                f'{i2}\t\t<taggedValue tag="stereotypeSet" value=""/>',
                f'{i2}\t\t<taggedValue tag="stereotypeExtension" value="{self._href("Element")}"/>',
                f'{i2}\t\t<taggedValue tag="stereotypeCheck" value=""/>',
                f"{i2}\t</xmi:Extension>",
            ]
            for tag in st.tags:
                t = {"Real": "double", "Integer": "int", "Boolean": "bool"}.get(tag.type, "string")
                a = Attr(tag.name, t, default=tag.default)
                a.id = self.new_id(1)
                lines += self._attr(a, i2 + "\t")
            bid = self.new_id(0)
            lines += [
                f'{i2}\t<ownedAttribute xmi:type="uml:Property" name="base_Element" xmi:id="{bid}"'
                f' association="BOUML_EXT_{bid[6:]}">',
                f'{i2}\t\t<type xmi:type="uml:Class" href="{self._href("Element")}"/>',
                f"{i2}\t</ownedAttribute>",
                f"{i2}</packagedElement>",
                f'{i2}<packagedElement xmi:type="uml:Extension" name="A_Element_{st.name}"'
                f' xmi:id="BOUML_EXT_{bid[6:]}" memberEnd="BOUML_BASE_{bid[6:]}">',
                f'{i2}\t<ownedEnd xmi:type="uml:ExtensionEnd" name="extension_{st.name}"'
                f' xmi:id="BOUML_EXTEND_{bid[6:]}" type="{bid}" aggregation="composite"/>',
                f"{i2}</packagedElement>",
            ]
        lines.append(f"{ind}</packagedElement>")
        return lines

    # ---- the document
    def write(self, root: Pkg) -> str:
        self._assign(root, root=True)
        self._profile_id = self.new_id(22)
        self._assoc_of = {}
        stack = [root]
        while stack:
            p = stack.pop()
            for a in p.assocs:
                self._assoc_of[id(a.a)] = a
                self._assoc_of[id(a.b)] = a
            stack.extend(p.packages)
        body = self._package(root, "\t\t", root=True)
        head = [
            f'<?xml version="1.0" encoding="{self.encoding}"?>',
            f'<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/{self.uml}"'
            f' xmlns:xmi="http://schema.omg.org/spec/XMI/2.1" xmlns:{PROFILE}="{PROFILE_URI}">',
            f'\t<xmi:Documentation exporter="Bouml" exporterVersion="{self.exporter_version}"/>',
            f'\t<uml:Model xmi:type="uml:Model" xmi:id="themodel" name="{esc(self.model_name)}">',
            f'\t\t<profileApplication xmi:type="uml:ProfileApplication"'
            f' xmi:id="BOUML_PRFA_{self._profile_id[6:]}">',
            f'\t\t\t<appliedProfile xmi:idref="{self._profile_id}"/>',
            "\t\t</profileApplication>",
        ]
        tail = ["\t</uml:Model>"]
        # BOUML keeps the applications in a map keyed by stereotype: grouped, names in order;
        # the tags come first, then one base_<Metaclass> (base_Element: no metaclass extended)
        for stereotype, eid, tags in sorted(self.applications, key=lambda a: a[0]):
            attrs = "".join(f' {k}="{esc(v)}"' for k, v in tags.items())
            tail.append(
                f'\t<{stereotype} xmi:id="BOUML_STELT_{eid[6:]}"{attrs} base_Element="{eid}"/>'
            )
        tail.append("</xmi:XMI>")
        return "\n".join(head + body + tail) + "\n"


def stereotype_tags(stereotype: str, **values: object) -> dict[str, str]:
    """Every tag of an ACORDCS stereotype as BOUML writes them: the value, else default, else ''."""
    from acordcs.profile import stereotype as lookup

    st = lookup(stereotype)
    if st is None:
        raise ValueError(f"no stereotype {stereotype}")
    known = {t.name for t in st.tags}
    unknown = set(values) - known
    if unknown:
        raise ValueError(f"{stereotype} has no tags {sorted(unknown)}")
    out = {}
    for t in st.tags:
        v = values.get(t.name)
        if v is None:
            v = t.default if t.default is not None else ""
        out[t.name] = v if isinstance(v, str) else f"{v:g}" if isinstance(v, float) else str(v)
    return out


def ctx(cls: Cls, stereotype: str, **tags: object) -> Cls:
    """Apply an ACORDCS stereotype with all its tags to a class."""
    cls.stereotype = f"{PROFILE}:{stereotype}"
    cls.tags = stereotype_tags(stereotype, **tags)
    return cls


def ctx_var(cls: Cls, name: str, type_: str, lo: float, hi: float, terms: str, **kw) -> Attr:
    """Add a CtxVariable attribute (range and FCL-style terms) to a class."""
    return cls.attr(
        name,
        type_,
        stereotype=f"{PROFILE}:CtxVariable",
        tags=stereotype_tags("CtxVariable", min=float(lo), max=float(hi), terms=terms),
        **kw,
    )


# -------------------------------------------------------------------------------- synthetic model
WORDS = (
    "account",
    "order",
    "invoice",
    "customer",
    "product",
    "stock",
    "shipment",
    "carrier",
    "route",
    "sensor",
    "reading",
    "alarm",
    "session",
    "user",
    "role",
    "grant",
    "ledger",
    "entry",
    "batch",
    "job",
    "queue",
    "worker",
    "cache",
    "index",
    "report",
    "chart",
    "schedule",
    "slot",
    "booking",
    "room",
    "device",
    "firmware",
    "config",
    "profile",
    "address",
    "contact",
    "payment",
    "refund",
    "coupon",
    "tariff",
    "meter",
    "zone",
    "floor",
    "badge",
    "visit",
    "ticket",
    "issue",
    "comment",
    "review",
    "rating",
    "channel",
    "topic",
)
TYPES = ("int", "double", "bool", "string", "long", "float", "char", "list<string>", "varchar(40)")
LOAD_TERMS = (
    "idle := trape 0 0 10 30; light := trian 10 35 60; busy := trian 40 65 90;"
    " full := trape 70 90 100 100"
)
RATE_TERMS = "low := trape 0 0 20 50; normal := trian 20 50 80; high := trape 50 80 100 100"
LEVEL_TERMS = "small := trape 0 0 2 4; medium := trian 2 5 8; large := trape 6 8 10 10"
LEVELS = ("small", "medium", "large")


def _camel(words: list[str]) -> str:
    return "".join(w.capitalize() for w in words)


def synthetic_model(classes: int = 2000, seed: int = 1, policy_sets: int = 100) -> Pkg:
    """The synthetic model as a package tree (deterministic for ``seed``)."""
    rng = random.Random(seed)
    root = Pkg("Synthetic")
    ctxpkg = root.package("ContextAware")
    n_ctx = classes // 4
    n_sets = min(policy_sets, max(1, n_ctx // 5))
    n_containers = max(1, min(10, n_ctx // 50))
    # quarter budget: containers + sets + policies + monitors + components + ports + connections
    rest = max(0, n_ctx - n_containers - 3 * n_sets)
    n_components = max(n_sets, rest // 2) if rest else n_sets
    n_pairs = max(0, (n_ctx - n_containers - 3 * n_sets - n_components) // 3)

    dep_pkg = ctxpkg.package("Deployment")
    containers = [
        ctx(dep_pkg.cls(f"Node{i}"), "CtxContainer", host=f"node{i}.example.org")
        for i in range(n_containers)
    ]

    comp_pkg = ctxpkg.package("Components")
    components = []
    for i in range(n_components):
        c = ctx(comp_pkg.cls(f"Service{i}"), "CtxComponent", language="python")
        ctx_var(c, "level", "double", 0, 10, LEVEL_TERMS, default="5")
        c.attr("enabled", "bool", default="true")
        c.attr("threshold", "int", default="3")
        c.op("reset")
        c.op("configure", [("key", "string"), ("value", "string")], "bool")
        c.comment = f"Synthetic component {i}."
        components.append(c)
        comp_pkg.associate(containers[i % n_containers], c, f"service{i}", aggregation="composite")

    ports: list[Cls] = []
    for j in range(n_pairs):
        kind = ("synchronous", "asynchronous", "stream")[j % 3]
        prov_c = components[(2 * j) % n_components]
        req_c = components[(2 * j + 1) % n_components]
        p = ctx(comp_pkg.cls(f"Port{j}P"), "CtxPort", kind=kind, role="provided")
        r = ctx(comp_pkg.cls(f"Port{j}R"), "CtxPort", kind=kind, role="required")
        p.attr("calls", "long")
        conn = ctx(comp_pkg.cls(f"Link{j}"), "CtxPortConnection", connector="remote")
        conn.attr("latency", "double", default="0")
        conn.attr("bandwidth", "double", default="0")
        comp_pkg.associate(prov_c, p, f"port{j}p", aggregation="composite")
        comp_pkg.associate(req_c, r, f"port{j}r", aggregation="composite")
        comp_pkg.associate(conn, p, "provider")
        comp_pkg.associate(conn, r, "consumer")
        ports += [p, r]

    adapt_pkg = ctxpkg.package("Adaptation")
    for i in range(n_sets):
        crisp = i % 10 == 9
        comp = components[i % n_components]
        mon = ctx(
            adapt_pkg.cls(f"Monitor{i}"),
            "CtxMonitor",
            frequency=float(rng.choice((0.5, 1, 2, 5, 10))),
        )
        ctx_var(mon, "load", "double", 0, 100, LOAD_TERMS)
        ctx_var(mon, "rate", "double", 0, 100, RATE_TERMS)
        mon.attr("samples", "int", default="0")
        if crisp:
            pset = ctx(
                adapt_pkg.cls(f"PolicySet{i}"), "CtxPolicySet", engine="clips", trigger="event"
            )
            rules = []
            for k in range(12):
                lim = 10 + 7 * k
                rules.append(
                    f"r{k}: if Monitor{i}.load > {lim} and Service{i % n_components}.level < "
                    f"{1 + k % 9} then Service{i % n_components}.level = "
                    f"Service{i % n_components}.level + 1"
                    + (f" and Service{i % n_components}.reset()" if k % 4 == 0 else "")
                )
        else:
            pset = ctx(
                adapt_pkg.cls(f"PolicySet{i}"),
                "CtxPolicySet",
                engine="fuzzy",
                trigger="periodic",
                frequency=1.0,
            )
            rules = []
            k = 0
            for load in ("idle", "light", "busy", "full"):
                for rate in ("low", "normal", "high"):
                    out = LEVELS[min(2, (k * 7 + i) % 3)]
                    hedge = "very " if k % 5 == 0 else ""
                    rules.append(
                        f"r{k}: if Monitor{i}.load is {hedge}{load} and rate is {rate} "
                        f"then Service{i % n_components}.level is {out}"
                    )
                    k += 1
        pol = ctx(adapt_pkg.cls(f"Policy{i}"), "CtxPolicy", Rule="\n".join(rules))
        pol.comment = f"Twelve rules of policy set {i}."
        adapt_pkg.associate(pset, pol, "policy", aggregation="composite")
        adapt_pkg.associate(mon, pset, "feeds")
        adapt_pkg.depend(pset, comp)
        adapt_pkg.associate(containers[i % n_containers], mon, f"monitor{i}")
        adapt_pkg.associate(containers[i % n_containers], pset, f"policySet{i}")
        adapt_pkg.depend(mon, components[(i + 1) % n_components])

    made = sum(len(p.classes) for p in _walk(root))
    plain_total = max(0, classes - made)
    domain = root.package("Domain")
    plain: list[Cls] = []
    pkgs = [domain.package(f"module{m}") for m in range(max(1, plain_total // 100))]
    for n in range(plain_total):
        pkg = pkgs[n % len(pkgs)]
        w = rng.sample(WORDS, 2)
        c = pkg.cls(f"{_camel(w)}{n}")
        if n % 7 == 0:
            c.stereotype = rng.choice(("entity", "boundary", "control"))
        for a in range(rng.randint(1, 4)):
            c.attr(
                f"{rng.choice(WORDS)}{a}",
                rng.choice(TYPES),
                visibility=rng.choice(("private", "protected", "public")),
                default=str(rng.randint(0, 99)) if a % 3 == 0 else None,
                is_static=a == 3 and n % 5 == 0,
            )
        for o in range(rng.randint(1, 2)):
            params = [
                (f"{rng.choice(WORDS)}{p}", rng.choice(TYPES)) for p in range(rng.randint(0, 2))
            ]
            c.op(f"do{_camel([rng.choice(WORDS)])}{o}", params, rng.choice((*TYPES, None)))
        if n % 3 == 0:
            c.comment = (
                f"The {w[0]} {w[1]} of the domain model.\n"
                f"Synthetic class {n}, generated with seed {seed}; no ACORD-CS stereotype."
            )
        if plain and n % 9 == 0:
            c.general = rng.choice(plain[-50:])
        if plain and n % 2 == 0:
            other = rng.choice(plain[-200:])
            pkg.associate(
                c,
                other,
                f"{w[1]}s",
                back=f"{w[0]}" if n % 2 else None,
                aggregation=rng.choice(("none", "shared", "composite")),
                multiplicity=rng.choice(("*", "1", "0..1", "1..*", None, None)),
            )
        if plain and n % 11 == 0:
            pkg.depend(c, rng.choice(plain))
        plain.append(c)
    return root


def _walk(pkg: Pkg):
    yield pkg
    for p in pkg.packages:
        yield from _walk(p)


def generate(classes: int = 2000, seed: int = 1) -> str:
    """The synthetic model as BOUML XMI text."""
    root = synthetic_model(classes, seed)
    return BoumlWriter("Synthetic", gxmi_path="/home/modeller/synthetic.xmi").write(root)


def write(path: str | Path, classes: int = 2000, seed: int = 1) -> Path:
    """Write the synthetic model to ``path`` (UTF-8) and return the path."""
    path = Path(path)
    path.write_text(generate(classes, seed), encoding="utf-8")
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--classes", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", required=True)
    args = ap.parse_args(argv)
    if args.classes < 20:
        ap.error("--classes must be at least 20")
    path = write(args.out, args.classes, args.seed)
    print(f"{path}: {path.stat().st_size} bytes, {args.classes} classes", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
