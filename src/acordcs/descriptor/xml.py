"""The descriptor as an XML document: ``to_xml(app) -> bytes`` and ``from_xml(data) -> Application``.

The document (namespace :data:`NAMESPACE`) follows ``acordcs-descriptor.xsd``, shipped beside this
module (:mod:`acordcs.descriptor.schema`); it is what the generator's stylesheets read. ``to_xml`` writes UTF-8,
indented, attributes in a fixed order: the same application gives the same bytes. A string XML 1.0
cannot hold (control characters other than tab, newline and carriage return; U+FFFE, U+FFFF; lone
surrogates) is refused with :class:`DescriptorError` naming the element and field; every other
string, quotes, ``<``, ``&``, ``]]>`` and newlines included, is escaped and read back unchanged:
``from_xml(to_xml(app)) == app``.

``from_xml`` parses only through :func:`acordcs.safexml.parse` (no DTD, no entities, no network)
and validates against the schema before reading; any failure is a :class:`DescriptorError` with the
file, line and column and a hint.
"""

from __future__ import annotations

import math
import re

from lxml import etree

from acordcs import safexml
from acordcs.descriptor.model import (
    Application,
    Component,
    Connection,
    Container,
    DescriptorError,
    Monitor,
    PolicySet,
    Ref,
    Value,
)
from acordcs.descriptor.reader import read
from acordcs.descriptor.schema import (
    HINT,
    NAMESPACE,
    SCHEMA_FILE,
    column,
    local_name,
    schema,
    validate,
)
from acordcs.descriptor.schema import NS as _NS

__all__ = ["NAMESPACE", "SCHEMA_FILE", "from_xml", "schema", "to_xml"]

_DECLARATION = b'<?xml version="1.0" encoding="UTF-8"?>\n'
# what XML 1.0 cannot hold: C0 controls but tab, LF, CR; surrogates; U+FFFE, U+FFFF
_FORBIDDEN = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


# ------------------------------------------------------------------------------------- writing
def to_xml(app: Application) -> bytes:
    """``app`` as a descriptor document (UTF-8, indented, deterministic)."""
    root = etree.Element(_NS + "application", nsmap={None: NAMESPACE})
    _set(root, "name", app.name, "application")
    w = _Writer()
    for tag, items, write in (
        ("containers", app.containers, w.container),
        ("components", app.components, w.component),
        ("connections", app.connections, w.connection),
        ("monitors", app.monitors, w.monitor),
        ("policy-sets", app.policy_sets, w.policy_set),
    ):
        group = etree.SubElement(root, _NS + tag)
        for item in items:
            write(group, item)
    return _DECLARATION + etree.tostring(root, encoding="UTF-8", pretty_print=True)


def _check(value: str, field: str, where: str) -> str:
    if not isinstance(value, str):
        raise DescriptorError(
            f"{where}: {field} must be a string, not {type(value).__name__}",
            hint="build the descriptor with acordcs.generator.describe.describe",
        )
    bad = _FORBIDDEN.search(value)
    if bad:
        raise DescriptorError(
            f"{where}: {field} {value!r} contains U+{ord(bad.group()):04X}, which XML 1.0 cannot hold",
            hint="remove the character in the model (XML 1.0 allows no control character but tab, "
            "newline and carriage return)",
        )
    return value


def _set(el: etree._Element, name: str, value: str, where: str) -> None:
    el.set(name, _check(value, name, where))


def _sub(parent: etree._Element, tag: str, where: str, /, **attrs: str | None) -> etree._Element:
    el = etree.SubElement(parent, _NS + tag)
    for name, value in attrs.items():
        if value is not None:
            _set(el, name.rstrip("_").replace("_", "-"), value, where)
    return el


def _real(value: float, field: str, where: str) -> str:
    if isinstance(value, bool) or not isinstance(value, int | float) or not math.isfinite(value):
        raise DescriptorError(
            f"{where}: {field} must be a finite number, not {value!r}",
            hint="numbers in a descriptor are finite xsd:double values",
        )
    value = float(value)
    return str(int(value)) if value.is_integer() and abs(value) < 2**53 else repr(value)


def _value(kind: str, value: Value, where: str) -> str:
    if kind == "int" and type(value) is int:
        return str(value)
    if kind == "double" and type(value) in (int, float):
        return _real(value, "default", where)
    if kind == "bool" and type(value) is bool:
        return "true" if value else "false"
    if kind == "string" and isinstance(value, str):
        return value
    raise DescriptorError(
        f"{where}: default {value!r} is not of kind {kind}",
        hint="a property's default has the Python type of its kind (int, float, bool, str)",
    )


class _Writer:
    def traced(self, parent, tag: str, item, where: str, /, **attrs) -> etree._Element:
        el = _sub(
            parent, tag, where, id=item.id, name=item.name, qname=item.qualified_name, **attrs
        )
        self.documentation(el, item.documentation, where)
        return el

    @staticmethod
    def documentation(el, text: str, where: str) -> None:
        if text:
            _sub(el, "documentation", where).text = _check(text, "documentation", where)

    def members(self, el, item, where: str, properties=None, tag: str = "property") -> None:
        """``item``'s properties (or ``properties``, written as ``tag``), then its operations."""
        for prop in item.properties if properties is None else properties:
            here = f"{where}, property {prop.name!r}"
            default = _value(prop.kind, prop.default, here)
            self.traced(el, tag, prop, here, type=prop.type, kind=prop.kind, default=default)
        for op in item.operations:
            here = f"{where}, operation {op.name!r}"
            op_el = self.traced(el, "operation", op, here, returns=op.return_type)
            for p in op.parameters:
                _sub(
                    op_el,
                    "parameter",
                    here,
                    id=p.id,
                    name=p.name,
                    type=p.type,
                    direction=p.direction,
                )

    @staticmethod
    def refs(el, tag: str, refs: tuple[Ref, ...], where: str) -> None:
        for r in refs:
            _sub(el, tag, where, kind=r.kind, name=r.name, ref=r.id)

    def container(self, parent, c: Container) -> None:
        where = f"container {c.name!r}"
        el = self.traced(parent, "container", c, where, host=c.host)
        if c.endpoint is not None:
            e = c.endpoint
            port = None if e.port is None else str(e.port)
            _sub(
                el,
                "endpoint",
                where,
                protocol=e.protocol,
                object=e.object_name,
                host=e.host,
                port=port,
            )
        self.refs(el, "hosts", c.hosts, where)
        for name in c.reaches:
            _sub(el, "reaches", where, name=name)
        self.members(el, c, where)

    def component(self, parent, c: Component) -> None:
        where = f"component {c.name!r}"
        el = self.traced(parent, "component", c, where, language=c.language)
        self.members(el, c, where)
        for p in c.ports:
            here = f"{where}, port {p.name!r}"
            self.members(self.traced(el, "port", p, here, kind=p.kind, role=p.role), p, here)

    def connection(self, parent, c: Connection) -> None:
        where = f"connection {c.name!r}"
        el = self.traced(parent, "connection", c, where, connector=c.connector)
        for tag, end in (("required", c.required), ("provided", c.provided)):
            _sub(el, tag, where, component=end.component, port=end.port, ref=end.id)
        self.members(el, c, where, c.qos, "qos")

    def monitor(self, parent, m: Monitor) -> None:
        where = f"monitor {m.name!r}"
        freq = None if m.frequency is None else _real(m.frequency, "frequency", where)
        el = self.traced(
            parent,
            "monitor",
            m,
            where,
            acquisition=m.acquisition,
            frequency=freq,
            xpath=m.xpath,
            operation=m.operation,
        )
        self.refs(el, "source", m.sources, where)
        self.refs(el, "feeds", m.feeds, where)
        self.members(el, m, where)

    def policy_set(self, parent, ps: PolicySet) -> None:
        where = f"policy set {ps.name!r}"
        freq = None if ps.frequency is None else _real(ps.frequency, "frequency", where)
        el = self.traced(
            parent,
            "policy-set",
            ps,
            where,
            engine=ps.engine,
            semantics=ps.semantics,
            trigger=ps.trigger,
            frequency=freq,
        )
        self.refs(el, "adapts", ps.adapts, where)
        for pol in ps.policies:
            here = f"{where}, policy {pol.name!r}"
            pol_el = self.traced(el, "policy", pol, here)
            for rule in pol.rules:
                rule_el = _sub(
                    pol_el,
                    "rule",
                    here,
                    label=rule.label,
                    tag=rule.tag,
                    priority=str(rule.priority),
                    assigned_label="true" if rule.assigned_label else None,
                )
                rule_el.text = _check(rule.text, "rule", here)
        for v in ps.variables:
            here = f"{where}, variable {v.name!r}"
            var_el = _sub(
                el,
                "variable",
                here,
                id=v.id,
                element=v.element,
                attribute=v.attribute,
                qname=v.qualified_name,
                min=_real(v.minimum, "min", here),
                max=_real(v.maximum, "max", here),
            )
            for t in v.terms:
                params = " ".join(_real(p, "parameter", here) for p in t.parameters)
                _sub(var_el, "term", here, name=t.name, shape=t.shape, parameters=params)
        self.members(el, ps, where)
        for b in ps.bound:
            here = f"{where}, bound name {b.target!r}"
            if not b.names or any(not n or any(c.isspace() for c in n) for n in b.names):
                raise DescriptorError(
                    f"{here}: names {b.names!r} must be one or more names without blanks",
                    hint="bound names are the rule names as written (Element.attribute)",
                )
            default = None if b.default is None else _value(b.value_kind or "", b.default, here)
            _sub(
                el,
                "bound",
                here,
                kind=b.kind,
                element=b.element,
                member=b.member,
                ref=b.id,
                names=" ".join(b.names),
                value_kind=b.value_kind,
                type=b.type or None,
                default=default,
                arity=None if b.arity is None else str(b.arity),
            )
        for tag, names in (("input", ps.inputs), ("output", ps.outputs), ("trigger", ps.triggers)):
            for name in names:
                _sub(el, tag, where, name=name)


# ------------------------------------------------------------------------------------- reading
def from_xml(data: bytes, *, file: str | None = None) -> Application:
    """Read a descriptor document (bytes, as :func:`to_xml` writes them); ``file`` names it in
    errors."""
    try:
        root = safexml.parse(data)
    except safexml.Refused as err:
        raise DescriptorError(
            "a descriptor has no document type or entity declarations",
            file=file,
            line=err.line,
            column=err.column,
            hint="remove the <!DOCTYPE ...> or <!ENTITY ...> declaration",
        ) from None
    except etree.XMLSyntaxError as err:
        line, col = err.position
        raise DescriptorError(
            f"not well-formed XML: {err.msg}", file=file, line=line, column=col, hint=HINT
        ) from None
    except (ValueError, LookupError) as err:
        raise DescriptorError(
            f"cannot decode the document: {err}",
            file=file,
            hint="write the descriptor as UTF-8 with a matching encoding declaration",
        ) from None
    if root.tag != _NS + "application":
        raise DescriptorError(
            f"the root element is {root.tag!r}, not an ACORD-CS descriptor's "
            f"{{{NAMESPACE}}}application",
            file=file,
            line=root.sourceline,
            column=column(data, root.sourceline, local_name(root.tag), None),
            hint=f"a descriptor of version 1.0 has the namespace {NAMESPACE}",
        )
    validate(root, data, file)
    return read(root, data, file)
