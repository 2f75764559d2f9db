"""Published context documents: turning what a publisher passes into a parsed tree, or a PublishError.

Context documents come from other processes and machines, so they are parsed as hostile input, by
:mod:`acordcs.safexml` (no DTD accepted at all, no entities, no network, libxml2's limits: nesting at most
256 levels, text nodes at most 10 MB), on each thread's own parser. This module adds the provider's
policy: :class:`Limits` on bytes, nodes, depth and evaluation cost, so that the cost of every
subscription per document is bounded, and PublishError messages naming the publisher.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from lxml import etree

from acordcs import safexml
from acordcs.runtime.context.errors import PublishError
from acordcs.runtime.context.xpathcost import document_cost

_COUNT_NODES = etree.XPath("count(//node() | //@*)")
_DECLARED_ENCODING = re.compile(r"\s*<\?xml[^>]*?encoding\s*=\s*[\"']([A-Za-z0-9._\-]+)")


@dataclass(frozen=True)
class Limits:
    """Per-document limits. ``max_nodes`` bounds what any XPath subscription can cost on one document."""

    max_bytes: int = 1 << 20
    max_nodes: int = 20_000
    max_depth: int = 256
    max_expression_chars: int = 4096
    # What evaluating string-values and relative paths from every node may cost on one document
    # (acordcs.runtime.context.xpathcost.document_cost): a costlier document is refused.
    max_cost: int = 4_000_000
    # False: the subscriptions the index does not evaluate must pass the cost check
    # (xpathcost.check_cost) and cost at most max_xpath_cost units (8 units: one pass over the
    # document); True only when every subscriber is trusted code.
    trusted_subscribers: bool = False
    max_xpath_cost: int = 128
    # A fallback (non-indexed) subscription whose evaluation uses more than this many seconds of
    # CPU time (not wall time: a busy host does not make an expression costly) gets a strike;
    # after ``max_strikes`` strikes within ``strike_window`` seconds it is suspended, reported and its
    # subscriber told (lxml cannot interrupt an evaluation); older strikes are forgotten.
    max_eval_seconds: float = 0.05
    max_strikes: int = 3
    strike_window: float = 60.0

    def __post_init__(self) -> None:
        for name in (
            "max_bytes",
            "max_nodes",
            "max_depth",
            "max_expression_chars",
            "max_strikes",
            "max_cost",
            "max_xpath_cost",
        ):
            if getattr(self, name) <= 0:
                raise ValueError(f"Limits.{name} must be positive, got {getattr(self, name)!r}")
        for name in ("max_eval_seconds", "strike_window"):
            if not getattr(self, name) > 0:
                raise ValueError(f"Limits.{name} must be positive, got {getattr(self, name)!r}")
        if self.max_depth > safexml.MAX_DEPTH:
            raise ValueError(
                f"Limits.max_depth above {safexml.MAX_DEPTH} would need libxml2's huge_tree, which is refused"
            )


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
    try:
        root = safexml.parse(data)  # this thread's parser
    except safexml.Refused as refused:
        if refused.line is None:  # seen by libxml2: the byte scan misses UTF-16 and friends
            message = "documents with a DOCTYPE are refused (external entities, entity bombs)"
        else:
            message = "documents with a DOCTYPE or entity declarations are refused (external entities, entity bombs)"
        raise _refuse(
            publisher, message, "remove the DOCTYPE; context documents need no DTD"
        ) from None
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
    if len(data) > limits.max_nodes:  # fewer bytes than the limit cannot hold more nodes
        nodes = int(_COUNT_NODES(tree))
        if nodes > limits.max_nodes:
            raise _refuse(
                publisher,
                f"document has {nodes} nodes, more than the limit of {limits.max_nodes}",
                "publish smaller documents or raise Limits.max_nodes",
            )
    if (
        limits.max_depth < safexml.MAX_DEPTH
        and len(data) > 2 * limits.max_depth
        and _depth_exceeds(root, limits.max_depth)
    ):
        raise _refuse(
            publisher,
            f"document nests elements deeper than {limits.max_depth} levels",
            "flatten the document or raise Limits.max_depth",
        )
    # each character counts at most once per enclosing element: a short document cannot exceed
    if len(data) * limits.max_depth > limits.max_cost:
        cost = document_cost(root)
        if cost > limits.max_cost:
            raise _refuse(
                publisher,
                f"document costs {cost:,} to evaluate XPath on (text length times depth), more "
                f"than the limit of {limits.max_cost:,}",
                "publish flatter or smaller documents, or raise Limits.max_cost",
            )
    return tree
