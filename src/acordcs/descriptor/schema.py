"""The descriptor's schema: the shipped ``acordcs-descriptor.xsd`` (written from the declaration by
:mod:`acordcs.descriptor.xsd`) compiled once per thread, and validation that reports the first
fault with a line and a column (libxml2 gives schema errors a line only: the column is found in
the start tag the error names).
"""

from __future__ import annotations

import re
import threading
from importlib import resources

from lxml import etree

from acordcs import safexml
from acordcs.descriptor.application import DescriptorError
from acordcs.descriptor.xml_form import NAMESPACE, NS

__all__ = ["HINT", "NAMESPACE", "NS", "SCHEMA_FILE", "column", "local_name", "schema", "validate"]

SCHEMA_FILE = "acordcs-descriptor.xsd"
HINT = (
    f"a descriptor follows {SCHEMA_FILE} (shipped in acordcs/descriptor); write it with "
    "acordcs.descriptor.to_xml from the model rather than by hand"
)

_local = threading.local()


def schema() -> etree.XMLSchema:
    """The descriptor schema, compiled once per thread (lxml validators are not shared)."""
    found = getattr(_local, "schema", None)
    if found is None:
        data = resources.files("acordcs.descriptor").joinpath(SCHEMA_FILE).read_bytes()
        found = _local.schema = etree.XMLSchema(safexml.parse(data, safexml.parser()))
    return found


def validate(root: etree._Element, data: bytes, file: str | None) -> None:
    """Raise :class:`DescriptorError` at the first fault if ``root`` (parsed from ``data``) does
    not validate against the schema."""
    validator = schema()
    if validator.validate(root):
        return
    errors = list(validator.error_log)
    first = errors[0]
    message = first.message.replace(NS, "")
    attribute = re.search(r"attribute '([^']+)'", message)
    element = re.search(r"^Element '([^']+)'", message)
    more = f" (and {len(errors) - 1} more)" if len(errors) > 1 else ""
    raise DescriptorError(
        f"does not validate against {SCHEMA_FILE}: {message}{more}",
        file=file,
        line=first.line,
        column=column(
            data,
            first.line,
            element.group(1) if element else None,
            attribute.group(1) if attribute else None,
        ),
        hint=HINT,
    )


def local_name(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def column(data: bytes, line: int, element: str | None, attribute: str | None) -> int:
    """The column (1-based, in bytes) of ``attribute`` in the start tag of ``element`` that begins
    on ``line``, else of that start tag, else of the line's first character: libxml2 gives schema
    errors a line but no column."""
    start = 0
    for _ in range(max(line, 1) - 1):
        start = data.find(b"\n", start) + 1
        if start == 0:
            return 1
    tag = None
    if element:
        found = re.compile(rb"<(?:[\w.-]+:)?" + re.escape(element.encode()) + rb"[\s/>]").search(
            data, start
        )
        tag = found.start() if found else None
    if tag is None:
        text = data[start:].split(b"\n", 1)[0]
        return 1 + len(text) - len(text.lstrip())
    if attribute:
        end = data.find(b">", tag)
        found = re.compile(rb"\s(" + re.escape(attribute.encode()) + rb")\s*=").search(
            data, tag, end if end >= 0 else len(data)
        )
        if found:
            return safexml.line_column(data, found.start(1))[1]
    return safexml.line_column(data, tag)[1]
