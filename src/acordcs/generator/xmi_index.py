"""Whole-document facts about an XMI 2.x file, found with XPath on the thread that parsed it.

libxml2 evaluates XPath without holding the GIL, so when ``acordcs-gen`` prefetches a model
(:func:`acordcs.generator.xmlsafe.prefetch`) these queries run on the second core while the main
thread walks the model. The XMI 2 reader (:mod:`acordcs.generator.readers.xmi2`) needs them to
defer reading plain attributes and operations until something asks for them: every id (to find
ids defined twice, R203) and whether every reference in the file names a known id (a deferred
member must not hold a dangling one, R202).

This module imports nothing but lxml and ``re``: ``acordcs-gen`` loads it before starting the
parse, and every millisecond here delays the parse.
"""

from __future__ import annotations

import re

from lxml import etree

# Eclipse profile schemas (http://www.eclipse.org/uml2/schemas/Ecore/5) share the prefix: match only
# the UML metamodel's own URI.
_UML_NS = re.compile(
    r"^https?://(schema\.omg\.org|www\.omg\.org)/spec/UML/"
    r"|^http://www\.eclipse\.org/uml2/\d+(\.\d+)*/UML$"
)
_XMI_NS = re.compile(r"^https?://(schema\.omg\.org|www\.omg\.org)/(spec/)?XMI")
DEFAULT_XMI_NS = "http://schema.omg.org/spec/XMI/2.1"


def namespaces(root: etree._Element) -> tuple[str | None, str | None]:
    """The UML and XMI namespace URIs declared on ``root`` (None when absent)."""
    uml = xmi = None
    for uri in (root.nsmap or {}).values():
        if uri and _UML_NS.match(uri):
            uml = uri
        elif uri and (_XMI_NS.match(uri) or uri == "http://www.omg.org/XMI"):
            xmi = uri
    return uml, xmi


class XmiIndex:
    """What the reader needs to know about the whole file before deferring members."""

    __slots__ = ("ids", "known", "refs_known", "xmi_ns")

    def __init__(self, root: etree._Element, xmi_ns: str) -> None:
        ns = {"x": xmi_ns}
        self.xmi_ns = xmi_ns
        # Every xmi:id in document order, duplicates included (R203 finds them).
        self.ids: list[str] = root.xpath("//@x:id", namespaces=ns, smart_strings=False)
        self.known = set(self.ids)
        # A deferred member's type reference is an xmi:idref or a type attribute: when every one
        # in the file names a known id, no deferred member holds a dangling reference (R202).
        refs = root.xpath("//@x:idref", namespaces=ns, smart_strings=False)
        refs += root.xpath("//@type", smart_strings=False)
        known = self.known
        self.refs_known = all(token in known for ref in refs for token in ref.split())


def index(root: etree._Element) -> XmiIndex | None:
    """The index of an XMI 2.x / Eclipse UML2 document; None for anything else."""
    uml, xmi = namespaces(root)
    if uml is None:
        return None
    return XmiIndex(root, xmi or DEFAULT_XMI_NS)
