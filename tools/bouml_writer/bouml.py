"""Write BOUML-style XMI 2.1 models: the writer.

The writer imitates what BOUML's ``xmi2`` exporter writes (see ``shared/reference/bouml-xmi.md``
and the real export ``xmi-samples/SecondStageModels__CDKatalog.xmi``): tab indentation,
``name ="x"`` on packages, ``BOUML_<hex>_<kind>`` ids, primitive types as OMG hrefs and every other
type as a ``uml:DataType`` ``BOUML_datatype_N`` at the end of the root package, associations with
``memberEnd`` children and a non-navigable ``ownedEnd`` for one-way relations, the profile inside
the model with its ``profileApplication``, and every ACORDCS stereotype written twice: in an
``xmi:Extension`` block inside the element and as a root-level application after
``</uml:Model>``, with the same tag values.

The in-memory elements are in :mod:`tools.bouml_writer.elements`; a large synthetic model in
:mod:`tools.bouml_writer.synthetic`.
"""

from __future__ import annotations

from tools.bouml_writer.elements import Assoc, Attr, Cls, End, Op, Pkg

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
