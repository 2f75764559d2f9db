"""Hardened parsing of published documents.

Context documents come from other processes and machines, so they are parsed as hostile input: no DTD
is accepted at all (which refuses XXE and entity bombs before libxml2 sees them), no network, no
``huge_tree`` (libxml2 then limits nesting to 256 levels and text nodes to 10 MB), and explicit size and
node-count limits so that the cost of every subscription per document is bounded.
"""

from __future__ import annotations

import re
import threading
from dataclasses import dataclass

from lxml import etree

from acordcs.runtime.context.errors import PublishError

_COUNT_NODES = etree.XPath("count(//node() | //@*)")
_DECLARED_ENCODING = re.compile(r"\s*<\?xml[^>]*?encoding\s*=\s*[\"']([A-Za-z0-9._\-]+)")


@dataclass(frozen=True)
class Limits:
    """Per-document limits. ``max_nodes`` bounds what any XPath subscription can cost on one document."""

    max_bytes: int = 1 << 20
    max_nodes: int = 20_000
    max_depth: int = 256
    max_expression_chars: int = 4096
    # A fallback (non-indexed) subscription whose evaluation exceeds this many seconds gets a strike;
    # after ``max_strikes`` strikes it is suspended and reported (lxml cannot interrupt an evaluation).
    max_eval_seconds: float = 0.05
    max_strikes: int = 3

    def __post_init__(self) -> None:
        for name in ("max_bytes", "max_nodes", "max_depth", "max_expression_chars", "max_strikes"):
            if getattr(self, name) <= 0:
                raise ValueError(f"Limits.{name} must be positive, got {getattr(self, name)!r}")
        if not self.max_eval_seconds > 0:
            raise ValueError(
                f"Limits.max_eval_seconds must be positive, got {self.max_eval_seconds!r}"
            )
        if self.max_depth > 256:
            raise ValueError(
                "Limits.max_depth above 256 would need libxml2's huge_tree, which is refused"
            )


_PARSER_OPTIONS = {
    "resolve_entities": False,
    "no_network": True,
    "load_dtd": False,
    "dtd_validation": False,
    "huge_tree": False,
    "remove_comments": False,
    "collect_ids": False,
}


_local = threading.local()


def _parser() -> etree.XMLParser:
    # an XMLParser must not be shared between threads; one per thread saves creating one per document
    parser = getattr(_local, "parser", None)
    if parser is None:
        parser = _local.parser = etree.XMLParser(**_PARSER_OPTIONS)
    return parser


def _refuse(
    publisher: str, message: str, hint: str, line: int | None = None, column: int | None = None
):
    return PublishError(
        message, file=f"publisher {publisher!r}", line=line, column=column, hint=hint
    )


def _depth_exceeds(root: etree._Element, limit: int) -> bool:
    stack = [(root, 1)]
    while stack:
        elem, depth = stack.pop()
        if depth > limit:
            return True
        stack.extend((child, depth + 1) for child in elem)
    return False


def to_bytes(publisher: str, document: object) -> bytes:
    """The document as bytes: str is UTF-8 encoded, lxml elements/trees are serialized."""
    if isinstance(document, bytes | bytearray | memoryview):
        return bytes(document)
    if isinstance(document, str):
        declared = _DECLARED_ENCODING.match(document)
        if declared and declared.group(1).lower().replace("_", "-") not in ("utf-8", "utf8"):
            raise _refuse(
                publisher,
                f"a str document declares encoding {declared.group(1)!r}: its text is already decoded",
                "publish the encoded bytes instead, or drop the encoding declaration",
            )
        return document.encode("utf-8")
    if isinstance(document, etree._ElementTree):
        document = document.getroot()
    if isinstance(document, etree._Element):
        # serializing then reparsing applies the same limits and detaches the subscriber's copy
        return etree.tostring(document)
    raise _refuse(
        publisher,
        f"a document must be bytes, str or an lxml element, not {type(document).__name__}",
        "pass the XML text or an lxml.etree element",
    )


def parse_document(publisher: str, data: bytes, limits: Limits) -> etree._ElementTree:
    """Parse ``data`` or raise :class:`PublishError` saying why it is refused."""
    if len(data) > limits.max_bytes:
        raise _refuse(
            publisher,
            f"document of {len(data)} bytes exceeds the limit of {limits.max_bytes} bytes",
            "publish smaller documents or raise Limits.max_bytes",
        )
    if b"<!DOCTYPE" in data or b"<!ENTITY" in data:
        raise _refuse(
            publisher,
            "documents with a DOCTYPE or entity declarations are refused (external entities, entity bombs)",
            "remove the DOCTYPE; context documents need no DTD",
        )
    try:
        root = etree.fromstring(data, _parser())
    except etree.XMLSyntaxError as err:
        line, column = err.position if err.position else (None, None)
        raise _refuse(
            publisher,
            f"not well-formed XML: {err.msg.split(', line ')[0]}",
            "fix the document; it was not published",
            line,
            column,
        ) from None
    except ValueError as err:  # e.g. str with an encoding declaration
        raise _refuse(
            publisher, f"unreadable document: {err}", "publish bytes for encoded XML"
        ) from None
    tree = root.getroottree()
    # the byte scan above misses UTF-16 and friends: check what libxml2 saw as well
    if tree.docinfo.internalDTD is not None:  # set for internal subsets and external ids alike
        raise _refuse(
            publisher,
            "documents with a DOCTYPE are refused (external entities, entity bombs)",
            "remove the DOCTYPE; context documents need no DTD",
        )
    if len(data) > limits.max_nodes:  # fewer bytes than the limit cannot hold more nodes
        nodes = int(_COUNT_NODES(tree))
        if nodes > limits.max_nodes:
            raise _refuse(
                publisher,
                f"document has {nodes} nodes, more than the limit of {limits.max_nodes}",
                "publish smaller documents or raise Limits.max_nodes",
            )
    if (
        limits.max_depth < 256
        and len(data) > 2 * limits.max_depth
        and _depth_exceeds(root, limits.max_depth)
    ):
        raise _refuse(
            publisher,
            f"document nests elements deeper than {limits.max_depth} levels",
            "flatten the document or raise Limits.max_depth",
        )
    return tree
