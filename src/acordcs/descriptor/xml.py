"""The descriptor as an XML document: ``to_xml(app) -> bytes`` and ``from_xml(data) -> Application``.

The document (namespace :data:`NAMESPACE`) follows ``acordcs-descriptor.xsd``, shipped beside this
module (:mod:`acordcs.descriptor.schema`); it is what the generator's stylesheets read. ``to_xml``
walks the declaration of the dataclasses (:func:`acordcs.descriptor.xml_form.layout`) and writes
UTF-8, indented, attributes in a fixed order: the same application gives the same bytes. A string
XML 1.0 cannot hold (control characters other than tab, newline and carriage return; U+FFFE,
U+FFFF; lone surrogates) is refused with :class:`DescriptorError` naming the element and field; every other
string, quotes, ``<``, ``&``, ``]]>`` and newlines included, is escaped and read back unchanged:
``from_xml(to_xml(app)) == app``.

``from_xml`` parses only through :func:`acordcs.safexml.parse` (no DTD, no entities, no network)
and validates against the schema before reading; any failure is a :class:`DescriptorError` with the
file, line and column and a hint.
"""

from __future__ import annotations

import math
import re
from typing import Any, cast

from lxml import etree

from acordcs import safexml
from acordcs.descriptor.application import Application, DescriptorError
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
from acordcs.descriptor.xml_form import NS, Layout, Part, layout
from acordcs.typed_values import Value

__all__ = ["NAMESPACE", "SCHEMA_FILE", "from_xml", "schema", "to_xml"]

_DECLARATION = b'<?xml version="1.0" encoding="UTF-8"?>\n'
# what XML 1.0 cannot hold: C0 controls but tab, LF, CR; surrogates; U+FFFE, U+FFFF
_FORBIDDEN = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


# ------------------------------------------------------------------------------------- writing
def to_xml(app: Application) -> bytes:
    """``app`` as a descriptor document (UTF-8, indented, deterministic)."""
    declared = layout(Application)
    root = etree.Element(NS + declared.element.name, nsmap={None: NAMESPACE})
    _write(root, app, declared, declared.element.label, root=True)
    return _DECLARATION + etree.tostring(root, encoding="UTF-8", pretty_print=True)


def _write(el: etree._Element, item: Any, declared: Layout, where: str, root: bool = False) -> None:
    """``item``'s attributes, text and children into ``el``; ``where`` names it in errors.

    Every value that is not a string is formatted (and refused) before any string is checked, as
    the writer always has: of two faults, the one a message names does not change."""
    values: list[tuple[str, str]] = []
    for part in declared.attributes:
        value = getattr(item, part.field)
        if part.codec != "string" or root or part.node.empty_absent:
            value = _formatted(value, item, part, declared, where, root)
        if value is not None:  # a None of a string attribute is left out, as it always was
            values.append((part.xml, value))
    for name, value in values:
        el.set(name, _check(value, name, where))
    text = declared.text
    if text is not None:
        el.text = _check(getattr(item, text.field), local_name(el.tag), where)
    for part in declared.children:
        value = getattr(item, part.field)
        role = part.node.role
        if role == "documentation":
            if value:
                sub = etree.SubElement(el, part.tag)
                sub.text = _check(value, "documentation", where)
        elif role == "child":
            if value is not None or not part.optional:
                _element(el, part.tag, value, part, where)
        elif role == "children":
            for each in value:
                _element(el, part.tag, each, part, where)
        elif role == "names":
            for name in value:
                sub = etree.SubElement(el, part.tag)
                if name is not None:
                    sub.set("name", _check(name, "name", where))
        else:  # a group: the application's lists, where errors name their elements first
            sub = etree.SubElement(el, part.tag)
            for each in value:
                _element(sub, part.item_tag, each, part, "")


def _element(parent: etree._Element, tag: str, item: Any, part: Part, where: str) -> None:
    held = part.layout
    assert held is not None  # a child, children or group part holds a declared dataclass
    label = held.element.label
    if label:
        named = f"{label} {getattr(item, held.element.label_by)!r}"
        where = f"{where}, {named}" if where else named
    _write(etree.SubElement(parent, tag), item, held, where)


def _formatted(
    value: Any, item: Any, part: Part, declared: Layout, where: str, root: bool
) -> str | None:
    """``value``, the attribute's, as written, None to leave it out; a string is checked when set
    (but at the root, whose attributes are always set: a None is refused)."""
    codec = part.codec
    if codec == "string":
        if part.node.empty_absent and value == "":
            return None
        return _check(value, part.xml, where) if root else value
    if value is None and part.optional:
        return None
    if codec == "real":
        return _real(value, part.xml, where)
    if codec == "integer":
        return str(value)
    if codec == "flag":
        return "true" if value else None
    if codec == "reals":
        return " ".join(_real(v, part.node.item, where) for v in value)
    if codec == "names":
        if not value or any(not n or any(c.isspace() for c in n) for n in value):
            raise DescriptorError(
                f"{where}: {part.xml} {value!r} must be one or more names without blanks",
                hint=part.node.hint,
            )
        return " ".join(value)
    # typed: a literal of the kind the field typed_by holds (when that field may be None, "" for
    # none: a bound operation's default, were it set, "is not of kind ")
    kind = getattr(item, part.node.typed_by)
    if declared.part(part.node.typed_by).optional:
        kind = kind or ""
    return _value(kind, value, where)


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
        return _real(cast(float, value), "default", where)
    if kind == "bool" and type(value) is bool:
        return "true" if value else "false"
    if kind == "string" and isinstance(value, str):
        return value
    raise DescriptorError(
        f"{where}: default {value!r} is not of kind {kind}",
        hint="a property's default has the Python type of its kind (int, float, bool, str)",
    )


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
    if root.tag != NS + "application":
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
