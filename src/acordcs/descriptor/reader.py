"""Reading a descriptor tree that validated against the schema back into the dataclasses of
:mod:`acordcs.descriptor.model` (the structure is the schema's, so the reader only converts values;
a property's default, a string in the schema, is checked against its kind here)."""

from __future__ import annotations

import re

from acordcs.descriptor.model import (
    Application,
    Bound,
    Component,
    Connection,
    Container,
    DescriptorError,
    End,
    Endpoint,
    Monitor,
    Operation,
    Parameter,
    Policy,
    PolicySet,
    Port,
    Property,
    Ref,
    Rule,
    Term,
    Value,
    Variable,
    parse_real,
)
from acordcs.descriptor.schema import NS as _NS
from acordcs.descriptor.schema import column as _column
from acordcs.descriptor.schema import local_name as _local_name

_INT = re.compile(r"[+-]?[0-9]+")


def read(root, data: bytes, file: str | None) -> Application:
    """The application of a descriptor ``root`` that validated (``data`` and ``file`` for errors)."""
    return _Reader(data, file).application(root)


class _Reader:
    """Builds the dataclasses from a tree that validated: the structure is the schema's."""

    def __init__(self, data: bytes, file: str | None) -> None:
        self.data = data
        self.file = file

    def application(self, root) -> Application:
        groups = {_local_name(g.tag): list(g) for g in root if isinstance(g.tag, str)}
        return Application(
            name=root.get("name"),
            containers=tuple(self.container(e) for e in self._elements(groups["containers"])),
            components=tuple(self.component(e) for e in self._elements(groups["components"])),
            connections=tuple(self.connection(e) for e in self._elements(groups["connections"])),
            monitors=tuple(self.monitor(e) for e in self._elements(groups["monitors"])),
            policy_sets=tuple(self.policy_set(e) for e in self._elements(groups["policy-sets"])),
        )

    @staticmethod
    def _elements(items):
        return [e for e in items if isinstance(e.tag, str)]

    def _children(self, el, tag: str) -> list:
        return el.findall(_NS + tag)

    def _doc(self, el) -> str:
        doc = el.find(_NS + "documentation")
        return (doc.text or "") if doc is not None else ""

    def _traced(self, el) -> tuple[str, str, str]:
        return el.get("id"), el.get("name"), el.get("qname")

    def _value(self, el, kind_attribute: str = "kind") -> Value:
        kind, text = el.get(kind_attribute), el.get("default")
        if kind == "string":
            return text
        if kind == "bool" and text in ("true", "false"):
            return text == "true"
        if kind == "int" and _INT.fullmatch(text):
            return int(text)
        if kind == "double" and parse_real(text) is not None:
            return parse_real(text)
        raise DescriptorError(
            f"property {el.get('name')!r}: default {text!r} is not a valid {kind} literal",
            file=self.file,
            line=el.sourceline,
            column=_column(self.data, el.sourceline, _local_name(el.tag), "default"),
            hint="int: digits; double: a finite number (1, 0.5, 2e3); bool: true or false",
        )

    def _real(self, text: str | None) -> float | None:
        return None if text is None else parse_real(text)

    def properties(self, el, tag: str = "property") -> tuple[Property, ...]:
        return tuple(
            Property(*self._traced(p), p.get("type"), p.get("kind"), self._value(p), self._doc(p))
            for p in self._children(el, tag)
        )

    def operations(self, el) -> tuple[Operation, ...]:
        return tuple(
            Operation(
                *self._traced(op),
                tuple(
                    Parameter(p.get("id"), p.get("name"), p.get("type"), p.get("direction"))
                    for p in self._children(op, "parameter")
                ),
                op.get("returns"),
                self._doc(op),
            )
            for op in self._children(el, "operation")
        )

    def refs(self, el, tag: str) -> tuple[Ref, ...]:
        return tuple(
            Ref(r.get("kind"), r.get("name"), r.get("ref")) for r in self._children(el, tag)
        )

    def container(self, el) -> Container:
        ep = el.find(_NS + "endpoint")
        endpoint = (
            Endpoint(
                ep.get("protocol"),
                ep.get("object"),
                ep.get("host"),
                None if ep.get("port") is None else int(ep.get("port")),
            )
            if ep is not None
            else None
        )
        return Container(
            *self._traced(el),
            el.get("host"),
            endpoint,
            self.refs(el, "hosts"),
            self.properties(el),
            self.operations(el),
            self._doc(el),
            tuple(r.get("name") for r in self._children(el, "reaches")),
        )

    def bound(self, el) -> Bound:
        arity = el.get("arity")
        default = None if el.get("default") is None else self._value(el, "value-kind")
        return Bound(
            el.get("kind"),
            el.get("element"),
            el.get("member"),
            el.get("ref"),
            tuple(el.get("names").split()),
            el.get("value-kind"),
            el.get("type") or "",
            default,
            None if arity is None else int(arity),
        )

    def port(self, el) -> Port:
        return Port(
            *self._traced(el),
            el.get("kind"),
            el.get("role"),
            self.properties(el),
            self.operations(el),
            self._doc(el),
        )

    def component(self, el) -> Component:
        return Component(
            *self._traced(el),
            el.get("language"),
            self.properties(el),
            self.operations(el),
            tuple(self.port(p) for p in self._children(el, "port")),
            self._doc(el),
        )

    def connection(self, el) -> Connection:
        req, prov = (el.find(_NS + tag) for tag in ("required", "provided"))
        return Connection(
            *self._traced(el),
            el.get("connector"),
            End(req.get("component"), req.get("port"), req.get("ref")),
            End(prov.get("component"), prov.get("port"), prov.get("ref")),
            self.properties(el, "qos"),
            self.operations(el),
            self._doc(el),
        )

    def monitor(self, el) -> Monitor:
        return Monitor(
            *self._traced(el),
            self._real(el.get("frequency")),
            el.get("acquisition"),
            el.get("xpath"),
            el.get("operation"),
            self.refs(el, "source"),
            self.refs(el, "feeds"),
            self.properties(el),
            self.operations(el),
            self._doc(el),
        )

    def policy_set(self, el) -> PolicySet:
        policies = tuple(
            Policy(
                *self._traced(p),
                tuple(
                    Rule(
                        r.get("label"),
                        r.text or "",
                        r.get("tag"),
                        int(r.get("priority")),
                        r.get("assigned-label") in ("true", "1"),
                    )
                    for r in self._children(p, "rule")
                ),
                self._doc(p),
            )
            for p in self._children(el, "policy")
        )
        variables = tuple(
            Variable(
                v.get("id"),
                v.get("element"),
                v.get("attribute"),
                v.get("qname"),
                parse_real(v.get("min")),
                parse_real(v.get("max")),
                tuple(
                    Term(
                        t.get("name"),
                        t.get("shape"),
                        tuple(parse_real(x) for x in t.get("parameters").split()),
                    )
                    for t in self._children(v, "term")
                ),
            )
            for v in self._children(el, "variable")
        )
        return PolicySet(
            *self._traced(el),
            el.get("engine"),
            el.get("semantics"),
            el.get("trigger"),
            self._real(el.get("frequency")),
            self.refs(el, "adapts"),
            policies,
            variables,
            self.properties(el),
            self.operations(el),
            self._doc(el),
            tuple(self.bound(b) for b in self._children(el, "bound")),
            *(
                tuple(v.get("name") for v in self._children(el, tag))
                for tag in ("input", "output", "trigger")
            ),
        )
