"""Reading a descriptor tree that validated against the schema back into the dataclasses of
:mod:`acordcs.descriptor.application`, by their declaration (:func:`acordcs.descriptor.xml_form.layout`).

The structure is the schema's, so the reader only converts values; a property's default, a string
in the schema, is checked against its kind here. Each dataclass's reader is made once from its
layout: one function per field, called in the constructor's order (which is also the order faults
are found in). It is on a generated application's start path, so it does no more per element
than reading by hand did: the functions take the element alone (what an error needs besides, the
document's bytes and file name, :func:`read` adds) and select children with ``iterchildren``,
which lxml runs in C, where ``find`` and ``findall`` go through its ElementPath in Python.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from functools import cache
from operator import methodcaller
from typing import Any, TypeAlias

from lxml import etree

from acordcs.descriptor.application import Application, DescriptorError
from acordcs.descriptor.schema import column, local_name
from acordcs.descriptor.xml_form import Layout, Part, layout
from acordcs.typed_values import Value, parse_real

_INT = re.compile(r"[+-]?[0-9]+")

_Element: TypeAlias = etree._Element
_Read = Callable[[_Element], Any]
_NAME = methodcaller("get", "name")


class _NotALiteral(Exception):
    """A default that is not a literal of its kind, at ``el``'s attribute ``name``."""

    def __init__(self, el: _Element, name: str, text: str | None, kind: str | None) -> None:
        super().__init__(name)
        self.el, self.name, self.text, self.kind = el, name, text, kind


def read(root: _Element, data: bytes, file: str | None) -> Application:
    """The application of a descriptor ``root`` that validated (``data`` and ``file`` for errors)."""
    try:
        application: Application = _reader(Application)(root)
    except _NotALiteral as bad:
        el = bad.el
        raise DescriptorError(
            f"property {el.get('name')!r}: {bad.name} {bad.text!r} is not a valid {bad.kind} literal",
            file=file,
            line=el.sourceline,
            column=column(data, el.sourceline, local_name(el.tag), bad.name),
            hint="int: digits; double: a finite number (1, 0.5, 2e3); bool: true or false",
        ) from None
    return application


@cache
def _reader(cls: type) -> _Read:
    """The reader of dataclass ``cls``'s element: each field read, then the constructor called."""
    declared = layout(cls)
    fields = tuple(_field(part, declared) for part in declared.fields)
    make = declared.cls
    return lambda el: make(*[read(el) for read in fields])


def _field(part: Part, declared: Layout) -> _Read:
    role, tag = part.node.role, part.tag
    if role == "attribute":
        return _attribute(part, declared)
    if role == "text":
        return lambda el: el.text or ""
    if role == "documentation":
        return lambda el: "" if (doc := _first(el, tag)) is None else doc.text or ""
    if role == "names":
        return lambda el: tuple(map(_NAME, el.iterchildren(tag)))
    assert part.layout is not None  # a child, children or group part holds a declared dataclass
    sub = _reader(part.layout.cls)
    if role == "child" and part.optional:
        return lambda el: None if (c := _first(el, tag)) is None else sub(c)
    if role == "child":
        return lambda el: sub(_first(el, tag))
    if role == "children":
        return lambda el: tuple([sub(c) for c in el.iterchildren(tag)])
    assert role == "group", role
    item = part.item_tag
    return lambda el: tuple([sub(c) for c in next(el.iterchildren(tag)).iterchildren(item)])


def _first(el: _Element, tag: str) -> _Element | None:
    """``el.find(tag)`` for a tag: its first child ``tag``."""
    return next(el.iterchildren(tag), None)


def _attribute(part: Part, declared: Layout) -> _Read:
    name, codec, optional = part.xml, part.codec, part.optional
    if codec == "string":
        if part.node.empty_absent:
            return lambda el: el.get(name) or ""
        return lambda el: el.get(name)
    if codec == "typed":
        kind = declared.part(part.node.typed_by).xml
        if optional:
            return lambda el: None if el.get(name) is None else _literal(name, kind, el)
        return lambda el: _literal(name, kind, el)
    if codec == "flag":
        return lambda el: el.get(name) in ("true", "1")
    if codec == "names":
        return lambda el: tuple(el.get(name).split())
    if codec == "reals":
        return lambda el: tuple(map(parse_real, el.get(name).split()))
    convert: Callable[[str], Any] = parse_real if codec == "real" else int
    if optional:
        return lambda el: None if (text := el.get(name)) is None else convert(text)
    return lambda el: convert(el.get(name))


def _literal(name: str, kind_attribute: str, el: _Element) -> Value:
    """Attribute ``name`` of ``el`` read as a literal of the kind in ``kind_attribute``."""
    kind: str | None = el.get(kind_attribute)
    text: str | None = el.get(name)
    if text is not None:  # always, after the schema (default is required) or the caller
        if kind == "string":
            return text
        if kind == "bool" and text in ("true", "false"):
            return text == "true"
        if kind == "int" and _INT.fullmatch(text):
            return int(text)
        number = parse_real(text) if kind == "double" else None
        if number is not None:
            return number
    raise _NotALiteral(el, name, text, kind)
