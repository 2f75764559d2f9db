"""The elements a BOUML-style model is made of, in memory: packages, classes, attributes,
operations, associations and dependencies, before :mod:`tools.bouml_writer.bouml` writes them."""

from __future__ import annotations

from dataclasses import dataclass, field


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
