"""What both profile writers share: the checks a declaration must pass and the serialisation."""

from __future__ import annotations

from collections.abc import Sequence

from lxml import etree

from acordcs.profile.declaration import Stereotype, Tag

PRIMITIVE_TYPES = ("String", "Real", "Integer", "Boolean")
XML_DECLARATION = b'<?xml version="1.0" encoding="UTF-8"?>\n'


class ProfileExportError(ValueError):
    """The declaration cannot be written as a UML profile."""


def check(stereotypes: Sequence[Stereotype]) -> None:
    enums: dict[str, tuple[str, ...]] = {}
    for st in stereotypes:
        if not st.metaclasses:
            raise ProfileExportError(
                f"stereotype {st.name!r} extends no UML metaclass: give its EClass a 'metaclasses' "
                "detail in the http://acordcs.org/profile annotation of acordcs.ecore"
            )
        for tag in st.tags:
            if tag.values:
                seen = enums.setdefault(tag.type, tag.values)
                if seen != tag.values:
                    raise ProfileExportError(
                        f"enumeration {tag.type!r} (tag {st.name}.{tag.name}) has values "
                        f"{tag.values} here and {seen} elsewhere: one enumeration needs one list "
                        "of literals"
                    )
                if tag.default is not None and tag.default not in tag.values:
                    raise ProfileExportError(
                        f"tag {st.name}.{tag.name}: default {tag.default!r} is not one of "
                        f"{', '.join(tag.values)}: fix the default in acordcs.ecore"
                    )
            elif tag.type not in PRIMITIVE_TYPES:
                raise ProfileExportError(
                    f"tag {st.name}.{tag.name} has type {tag.type!r}, which is neither a UML "
                    f"primitive type ({', '.join(PRIMITIVE_TYPES)}) nor an enumeration with "
                    "literals: map its EDataType in acordcs.profile.declaration"
                )


def enumerations(stereotypes: Sequence[Stereotype]) -> dict[str, tuple[str, ...]]:
    """Enumeration name -> literals, in the order tags first use them."""
    out: dict[str, tuple[str, ...]] = {}
    for st in stereotypes:
        for tag in st.tags:
            if tag.values:
                out.setdefault(tag.type, tag.values)
    return out


def tag_doc(tag: Tag) -> str:
    doc = tag.doc
    # The metamodel's documentation may already say so; say it once.
    if tag.prefix and "starts with" not in doc:
        extra = f"Any other tag whose name starts with '{tag.name}' also holds these values."
        doc = f"{doc} {extra}".strip()
    return doc


def serialize(root: etree._Element, indent: str) -> bytes:
    etree.indent(root, space=indent)
    # The declaration is written by hand only to get the double quotes both tools write.
    return XML_DECLARATION + etree.tostring(root, encoding="UTF-8", xml_declaration=False) + b"\n"
