"""Hardened XML parsing: the one place where acordcs turns untrusted bytes into an lxml tree.

Three kinds of documents come from outside: model files (``acordcs.xmi.source``), context documents
published by other processes (``acordcs.runtime.context.xmlparse``) and component descriptions
(``acordcs.runtime.repository.description``). All three are parsed here, with one set of libxml2 options
and one refusal of document type declarations; each caller keeps its own limits, error type and
messages.

The options (:data:`OPTIONS`):

- ``resolve_entities=False``, ``load_dtd=False``, ``dtd_validation=False``: no entity is substituted and
  no DTD is read, so no external entity (XXE: ``<!ENTITY x SYSTEM "file:///etc/passwd">``) is ever
  opened;
- ``no_network=True``: nothing is fetched, whatever a document names;
- ``huge_tree=False``: libxml2 keeps its safety limits, which then mean: elements nested at most
  :data:`MAX_DEPTH` (256) levels deep ("Excessive depth in document"), a text node or attribute value of
  at most 10 MB, a name of at most 50,000 characters, and entity expansion bounded by an amplification
  factor ("Maximum entity amplification factor exceeded"). Past a limit the parse fails with an
  ``XMLSyntaxError``, it is not cut short;
- ``collect_ids=False``: acordcs looks nothing up by ``xml:id`` (XMI identifiers are ``xmi:id``), so
  the table is not built; building it would also put validity errors about ``xml:id`` values in front
  of the real error in the parser's log.

Before libxml2 sees the bytes, :func:`parse` refuses any ``<!DOCTYPE`` or ``<!ENTITY`` (in any letter
case, also in UTF-16 and UTF-32 text) outside a comment: none of these documents needs one, and
refusing it closes XXE and entity bombs (billion laughs) whatever libxml2 would do with them. The byte
scan stops at ``scan_end`` when a caller gives one, so the parsed tree is checked for a document type
as well; a caller that then parses again in recover mode (which drops a misplaced declaration) scans
all the bytes first (:func:`find_declaration`).

One exception, for model files only (``external_doctype=True``): old XMI 1.x exports (Rational Rose,
early Enterprise Architect) begin with ``<!DOCTYPE XMI SYSTEM 'UML13.dtd'>``, an external identifier
and no internal subset. That declaration is accepted and never acted on: libxml2 (2.14, through lxml
6.1) still tries to open the DTD an external identifier names, whatever ``load_dtd`` says, so every
parser made here carries a resolver that answers every request with an empty document: no file is
opened and nothing is fetched. Without an internal subset there is nothing to expand. A declaration
with an internal subset (``[...]``) stays refused.
"""

from __future__ import annotations

import re
import threading

from lxml import etree

MAX_DEPTH = 256
"""libxml2's nesting limit without ``huge_tree``: deeper documents fail to parse."""

OPTIONS = {
    "resolve_entities": False,
    "no_network": True,
    "load_dtd": False,
    "dtd_validation": False,
    "huge_tree": False,
    "collect_ids": False,
}

_DECLARATION = re.compile(rb"<!(?:DOCTYPE|ENTITY)", re.IGNORECASE)
# ``<!DOCTYPE Name SYSTEM "uri">`` or ``PUBLIC "id" "uri"`` and nothing else: no internal subset.
_EXTERNAL_ONLY = re.compile(
    rb"""<!DOCTYPE\s+[^\s\[>]+(?:\s+(?:SYSTEM\s+("[^"]*"|'[^']*')|PUBLIC\s+("[^"]*"|'[^']*')"""
    rb"""\s+("[^"]*"|'[^']*')))\s*>""",
)


def _wide(width: int, big_endian: bool) -> re.Pattern[bytes]:
    """:data:`_DECLARATION` for text in UTF-16 or UTF-32 (ASCII characters padded with NULs)."""

    def char(c: str) -> bytes:
        pad = b"\x00" * (width - 1)
        options = {c.lower(), c.upper()}
        alts = b"|".join(
            re.escape(pad + o.encode() if big_endian else o.encode() + pad) for o in sorted(options)
        )
        return b"(?:" + alts + b")"

    def word(w: str) -> bytes:
        return b"".join(char(c) for c in w)

    return re.compile(word("<!") + b"(?:" + word("DOCTYPE") + b"|" + word("ENTITY") + b")")


_WIDE_DECLARATIONS = [_wide(w, be) for w in (2, 4) for be in (False, True)]
_WIDE_ENCODINGS = ["utf-16-le", "utf-16-be", "utf-32-le", "utf-32-be"]


class Refused(Exception):
    """The document has a document type or entity declaration.

    Found by the byte scan, ``offset`` is where the declaration starts in the bytes and ``line`` and
    ``column`` (1-based) where it is in the text; found by libxml2 (UTF-16 text, or past ``scan_end``),
    all three are None.
    """

    def __init__(
        self, offset: int | None = None, line: int | None = None, column: int | None = None
    ) -> None:
        where = f" at line {line}, column {column}" if line is not None else ""
        super().__init__(f"document type or entity declaration{where}")
        self.offset = offset
        self.line = line
        self.column = column


class _NothingExternal(etree.Resolver):
    """Answers every external resource libxml2 asks for (a DTD named by a DOCTYPE) with nothing,
    before libxml2's own loader could open a file or a URL."""

    def resolve(self, system_url, _public_id, context):
        return self.resolve_string("", context)


def parser(*, recover: bool = False, remove_blank_text: bool = False) -> etree.XMLParser:
    """A new parser with :data:`OPTIONS`, for one thread at a time. The two variants:

    ``recover``: only for model files. BOUML writes names unescaped (``<``, ``&`` in a name), which
    recovery repairs locally; the toolchain reports that it recovered and goes on to find every other
    problem. A context document or a description is refused instead: a repaired tree would be a
    different document from the one sent.

    ``remove_blank_text``: only for model files, whose exports are indented (60,000 fewer nodes in a
    4 MB export: a faster parse and walk). Context documents and descriptions are kept as sent: a
    subscriber's XPath may read their whitespace.
    """
    made = etree.XMLParser(recover=recover, remove_blank_text=remove_blank_text, **OPTIONS)
    made.resolvers.add(_NothingExternal())
    return made


_local = threading.local()


def thread_parser() -> etree.XMLParser:
    """This thread's default parser (made by :func:`parser` on the thread's first use).

    For the context provider's hot path: thousands of small documents a second, from several threads.
    Making a parser costs about 1.3 us, a fifth of parsing a 300-byte document, and one parser shared
    by the threads would serialise them on lxml's per-parser lock.
    """
    found = getattr(_local, "parser", None)
    if found is None:
        found = _local.parser = parser()
    return found


def line_column(data: bytes, offset: int) -> tuple[int, int]:
    """The 1-based line and column of byte ``offset`` in ``data``."""
    line = data.count(b"\n", 0, offset) + 1
    return line, offset - (data.rfind(b"\n", 0, offset) + 1) + 1


def _declaration(data: bytes, start: int, end: int, external_doctype: bool) -> int | None:
    """Offset of the first refused declaration in ``data[start:end]``, None if there is none.
    Declarations inside comments are text, not declarations."""
    while True:
        found = _DECLARATION.search(data, start, end)
        if found is None:
            return None
        at = found.start()
        opened = data.rfind(b"<!--", 0, at)
        if opened >= 0 and data.find(b"-->", opened + 4, at) < 0:  # inside a comment
            start = at + 2
            continue
        if external_doctype:
            allowed = _EXTERNAL_ONLY.match(data, at)
            if allowed is not None:
                start = allowed.end()
                continue
        return at


def _refused_tree(root: etree._Element, external_doctype: bool) -> bool:
    """Whether libxml2 saw a refused document type (the byte scan misses UTF-16 and friends)."""
    dtd = root.getroottree().docinfo.internalDTD
    if dtd is None:
        return False
    if not external_doctype:
        return True  # set for internal subsets and external identifiers alike
    external = dtd.system_url is not None or dtd.external_id is not None
    # An ATTLIST-only subset is not visible here; without DTD attribute defaults it changes nothing.
    return not external or next(dtd.iterentities(), None) is not None


def parse(
    data: bytes,
    parser: etree.XMLParser | None = None,
    *,
    scan_end: int | None = None,
    external_doctype: bool = False,
) -> etree._Element | None:
    """Parse ``data`` with ``parser`` (default: :func:`thread_parser`).

    Raises :class:`Refused` for a document type or entity declaration (the bytes up to ``scan_end``, by
    default all of them, are scanned before parsing; the tree is checked after), and lets lxml's
    ``XMLSyntaxError`` (malformed, or past a libxml2 limit) and ``ValueError`` / ``LookupError`` (an
    unusable encoding declaration) through for the caller to word. None only from a recovering parser
    that found nothing to keep. ``external_doctype``: accept a document type declaration that is an
    external identifier alone (never loaded; see the module's docstring).
    """
    found = find_declaration(data, scan_end, external_doctype=external_doctype)
    if found is not None:
        raise found
    if parser is None:
        parser = getattr(_local, "parser", None)
        if parser is None:
            parser = thread_parser()
    root = etree.fromstring(data, parser)
    # the byte scan misses UTF-16 and friends: check what libxml2 saw as well
    if root is not None and _refused_tree(root, external_doctype):
        raise Refused()
    return root


def find_declaration(
    data: bytes, scan_end: int | None = None, *, external_doctype: bool = False
) -> Refused | None:
    """The :class:`Refused` for the first refused ``<!DOCTYPE`` or ``<!ENTITY`` in
    ``data[:scan_end]`` (any letter case; by default all of it; outside comments; with
    ``external_doctype``, an external identifier alone is not refused), or None."""
    end = len(data) if scan_end is None else scan_end
    start = data.find(b"<!", 0, end)  # a fast no for documents without comments or CDATA
    if start >= 0:
        found = _declaration(data, start, end, external_doctype)
        if found is not None:
            return Refused(found, *line_column(data, found))
    if b"\x00" in data[:4]:  # UTF-16 or UTF-32: '<' (or a BOM) is padded with NULs
        for pattern, encoding in zip(_WIDE_DECLARATIONS, _WIDE_ENCODINGS, strict=True):
            wide = pattern.search(data, 0, end)
            if wide and not (external_doctype and _external_only(data[:end], encoding)):
                return Refused(wide.start())  # no line: the bytes are not the text's lines
    return None


def _external_only(data: bytes, encoding: str) -> bool:
    """Whether wide text holds no refused declaration once decoded (an external identifier alone
    is not refused); text that does not decode is refused."""
    try:
        narrow = data.decode(encoding).encode("utf-8")
    except UnicodeError:
        return False
    return _declaration(narrow, 0, len(narrow), True) is None


def exceeded_limit(message: str) -> str | None:
    """What a libxml2 error message says was exceeded, in words for a user; None for other errors."""
    if "Excessive depth" in message:
        return f"elements nested deeper than {MAX_DEPTH} levels"
    if "amplification" in message:
        return "entity expansion beyond the safety limit"
    return None
