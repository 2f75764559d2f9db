"""An outline written as text in the notation, in one canonical layout: reading the text back
and writing it again gives the same text (``acordcs-gen convert``'s round trip)."""

from __future__ import annotations

import json
import re

from acordcs.notation import outline as o

INDENT = "  "
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_NUMBER = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?")
# Words the grammar reads as keywords where a name may stand (a parameter's direction).
_RESERVED = frozenset(("in", "out", "inout"))


def name(text: str) -> str:
    """``text`` as a name: bare when it is an identifier, else quoted."""
    if _NAME.fullmatch(text) and text not in _RESERVED:
        return text
    return json.dumps(text, ensure_ascii=False)


def value(text: str) -> str:
    """``text`` as a value: bare when it is an identifier or a number, else quoted."""
    if _NAME.fullmatch(text) or _NUMBER.fullmatch(text):
        return text
    return json.dumps(text, ensure_ascii=False)


def text_of(outline: o.Outline) -> str:
    """The text of ``outline``."""
    lines: list[str] = []
    if outline.name or outline.doc or outline.id is not None:
        _doc(lines, outline.doc, "")
        lines.append(f"model {name(outline.name)}{_ident(outline.id)}")
    for item in outline.items:
        if lines:
            lines.append("")
        _item(lines, item, "")
    return "\n".join(lines) + "\n"


def _ident(ident: str | None) -> str:
    return f" id {json.dumps(ident, ensure_ascii=False)}" if ident is not None else ""


def _doc(lines: list[str], doc: list[str], indent: str) -> None:
    lines.extend(f"{indent}/// {d}" if d else f"{indent}///" for d in doc)


def _tags(tags: list[o.Tag]) -> str:
    if not tags:
        return ""
    return " (" + ", ".join(f"{name(t.name)} = {value(t.value)}" for t in tags) + ")"


def _item(lines: list[str], item: o.Package | o.Element, indent: str) -> None:
    _doc(lines, item.doc, indent)
    if isinstance(item, o.Package):
        lines.append(f"{indent}package {name(item.name)}{_ident(item.id)} {{")
        for n, sub in enumerate(item.items):
            if n:
                lines.append("")
            _item(lines, sub, indent + INDENT)
        lines.append(f"{indent}}}")
        return
    head = f"{indent}{item.keyword} {name(item.name)}{_ident(item.id)}{_tags(item.tags)}"
    inner = indent + INDENT
    body: list[str] = []
    for attr in item.attributes:
        _attribute(body, attr, inner)
    for op in item.operations:
        _doc(body, op.doc, inner)
        params = ", ".join(_parameter(p) for p in op.parameters)
        returns = f": {name(op.returns)}" if op.returns is not None else ""
        body.append(f"{inner}operation {name(op.name)}{_ident(op.id)}({params}){returns}")
    for nested in item.nested:
        _item(body, nested, inner)
    for tag, block in item.rules:
        suffix = tag[len(o.RULE_TAG) :]
        _block(body, f"{inner}rules{' ' + name(suffix) if suffix else ''}", block, inner)
    for relation in item.relations:
        targets = ", ".join(".".join(name(n) for n in path) for path, _ in relation.targets)
        body.append(f"{inner}{relation.keyword} {targets}")
    if body:
        lines.append(head + " {")
        lines.extend(body)
        lines.append(f"{indent}}}")
    else:
        lines.append(head)


def _attribute(lines: list[str], attr: o.Attribute, indent: str) -> None:
    _doc(lines, attr.doc, indent)
    text = f"{indent}attribute {name(attr.name)}{_ident(attr.id)}"
    if attr.type is not None:
        text += f": {name(attr.type)}"
    if attr.default is not None:
        text += f" = {value(attr.default)}"
    var = attr.variable
    if var is None:
        lines.append(text)
        return
    text += f" variable{_ident(var.id)}{_tags(var.tags)}"
    if var.terms is None:
        lines.append(text)
    else:
        _block(lines, text, var.terms, indent)


def _block(lines: list[str], head: str, block: o.Block, indent: str) -> None:
    lines.append(head + " {")
    lines.extend(f"{indent}{INDENT}{text}" for text, _ in block.lines)
    lines.append(f"{indent}}}")


def _parameter(p: o.Parameter) -> str:
    direction = f"{p.direction} " if p.direction != "in" else ""
    typed = f": {name(p.type)}" if p.type is not None else ""
    return f"{direction}{name(p.name)}{_ident(p.id)}{typed}"
