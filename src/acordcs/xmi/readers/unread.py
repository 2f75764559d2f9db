"""What an XMI 2.x file defines outside the structure the walk reads: tool extensions and elements
that are no classifier, feature or relation.

Two tools make this matter. Enterprise Architect and MagicDraw restate model ids inside their
``xmi:Extension`` blocks (EA's element table, MagicDraw's diagrams): those are not definitions, so not
duplicate ids. And some references point outside the walk: EA types attributes with its own primitive
types, defined in its extension (``<type xmi:idref="EAJava_int"/>``); stereotype applications apply to
elements the walk keeps no object for (a MagicDraw diagram, an EA message or include). Those are
looked up here, by one pass over the tree, only when there are any.
"""

from __future__ import annotations

from lxml import etree

from acordcs.xmi.uml import Element


def ids_outside_extensions(root: etree._Element, xid: str, extension: str) -> list[tuple[str, int]]:
    """Every (id, line) defined outside ``extension`` elements, for the duplicate-id check."""
    found = []
    stack = [root]
    while stack:
        el = stack.pop()
        ident = el.get(xid)
        if ident is not None:
            found.append((ident, el.sourceline or 0))
        stack.extend(c for c in el if isinstance(c.tag, str) and c.tag != extension)
    return found


def elements_by_id(
    root: etree._Element, xid: str, xtype: str, wanted: set[str]
) -> dict[str, Element]:
    """Plain elements (metaclass, name, line) for the ids in ``wanted``; the first definition wins."""
    found: dict[str, Element] = {}
    if not wanted:
        return found
    for el in root.iter(etree.Element):
        ident = el.get(xid)
        if ident in wanted and ident not in found:
            kind = (el.get(xtype) or el.tag).rpartition(":")[2].rpartition("}")[2]
            found[ident] = Element(ident, kind, el.get("name", ""), el.sourceline or 0)
    return found
