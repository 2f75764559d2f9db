"""Model files: reading a UML/XMI export into an lxml tree, with what was wrong with it as diagnostics.

The parse itself is :mod:`acordcs.safexml`'s (no DTD, no entities, no network, libxml2's depth and size
limits); this module adds the model-file policy: a 256 MiB size limit, the X101-X110 diagnostics, and
the encoding checks. UML exports contain no internal DTD subset, so one is refused outright (X102); old
XMI 1.x exports (Rational Rose) name an external DTD (``<!DOCTYPE XMI SYSTEM 'UML13.dtd'>``), which is
accepted and never loaded. A strict parse comes first; only a file that fails it for a reason recovery can repair (BOUML's
unescaped ``<`` in names) is read again in recover mode, with a warning saying so (X107). Truncated
files, wrong encodings and undeclared prefixes are errors: recovery would silently drop or garble model
elements.
"""

from __future__ import annotations

import os
import re
import stat

from lxml import etree

from acordcs import safexml
from acordcs.diagnostics import Diagnostic, diagnostic

MAX_BYTES = 256 * 1024 * 1024
_WIDE_DECLARATION = re.compile(
    rb"""^\s*<\?xml[^>]*encoding\s*=\s*["'](utf-?16|utf-?32|ucs)""", re.IGNORECASE
)
_SCAN_BYTES = 64 * 1024
_KINDS = {
    stat.S_IFIFO: "a named pipe",
    stat.S_IFCHR: "a character device",
    stat.S_IFBLK: "a block device",
    stat.S_IFSOCK: "a socket",
    stat.S_IFDIR: "a directory",
}


class XmlInput:
    """A parsed file: its root (None when unreadable) and what reading it found."""

    __slots__ = ("_ids", "diagnostics", "encoding", "path", "recovered", "root")

    def __init__(
        self,
        path: str,
        root: etree._Element | None,
        diagnostics: list[Diagnostic] | None = None,
        recovered: bool = False,
        encoding: str | None = None,
    ) -> None:
        self.path = path
        self.root = root
        self.diagnostics = diagnostics if diagnostics is not None else []
        self.recovered = recovered
        self.encoding = encoding
        self._ids: dict[str, list[str]] = {}

    def ids(self, namespace: str) -> list[str]:
        """Every value of an ``id`` attribute in ``namespace`` (XMI's ``xmi:id``), in document
        order, duplicates included."""
        found = self._ids.get(namespace)
        if found is None:
            found = self._ids[namespace] = self.root.xpath(
                "//@x:id", namespaces={"x": namespace}, smart_strings=False
            )
        return found


# libxml2 error type -> (our code, what to do)
_FATAL = {
    "ERR_RESOURCE_LIMIT": (
        "X103",
        f"the file exceeds a safety limit (nesting deeper than {safexml.MAX_DEPTH} levels, a text or attribute "
        "value over 10 MB, or entity amplification); UML exports stay well inside these limits",
    ),
    "ERR_TAG_NOT_FINISHED": ("X104", "the file ends in the middle of an element: export it again"),
    "ERR_DOCUMENT_END": ("X104", "the file ends in the middle of an element: export it again"),
    # Blank input never gets this far (see parse_bytes): here it means content that is not XML.
    "ERR_DOCUMENT_EMPTY": ("X108", "the content is not XML (it does not start with '<')"),
    "ERR_INVALID_ENCODING": (
        "X105",
        "the bytes do not match the declared encoding: fix the encoding declaration or re-export",
    ),
    "ERR_INVALID_CHAR": (
        "X108",
        "a character XML does not allow (a control character or NUL): remove it from the model",
    ),
    "ERR_UNSUPPORTED_ENCODING": (
        "X105",
        "the declared encoding is not supported: re-export as UTF-8",
    ),
    "NS_ERR_UNDEFINED_NAMESPACE": (
        "X106",
        "declare the prefix with xmlns:PREFIX on the root element",
    ),
    "ERR_ENTITY_IS_EXTERNAL": ("X102", "UML exports contain no entities: remove them"),
    "ERR_UNDECLARED_ENTITY": ("X102", "UML exports contain no entities: remove them"),
}


# What BOUML's unescaped names break (`<`, `&`, `"` in a name), which recovery repairs locally.
# Any other error (a missing end tag, ...) would make recovery rebuild the tree wrongly: refused.
_RECOVERABLE = frozenset(
    (
        "ERR_LT_IN_ATTRIBUTE",
        "ERR_ENTITYREF_SEMICOL_MISSING",
        "ERR_NAME_REQUIRED",
        "ERR_ATTRIBUTE_WITHOUT_VALUE",
        "ERR_SPACE_REQUIRED",
        "ERR_GT_REQUIRED",
        "ERR_ATTRIBUTE_REDEFINED",
    )
)


def read_xml(path: str) -> XmlInput:
    """Parse ``path``; never raises for bad input. Only a regular file is read: a named pipe
    would block (no writer) or never end, a device (``/dev/zero``) never ends."""
    try:
        # O_NONBLOCK: opening a named pipe without a writer returns at once instead of waiting
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
        with open(fd, "rb") as handle:
            status = os.fstat(handle.fileno())
            if not stat.S_ISREG(status.st_mode):
                what = _KINDS.get(stat.S_IFMT(status.st_mode), "not a regular file")
                msg = f"cannot read file: it is {what}, not a regular file; give the path of a model file"
                return XmlInput(path, None, [diagnostic("X101", msg, file=path)])
            size = status.st_size
            if size > MAX_BYTES:
                msg = f"file is {size // 2**20} MiB, over the {MAX_BYTES // 2**20} MiB limit; split the model"
                return XmlInput(path, None, [diagnostic("X103", msg, file=path)])
            # Sized by the file: read(MAX_BYTES + 1) would allocate 256 MiB and copy (3 ms).
            data = handle.read(size + 1)
            if len(data) > size:  # it grew meanwhile
                data += handle.read(MAX_BYTES + 1 - len(data))
    except OSError as err:
        reason = err.strerror or str(err)
        return XmlInput(path, None, [diagnostic("X101", f"cannot read file: {reason}", file=path)])
    return parse_bytes(data, path)


def parse_bytes(data: bytes, path: str = "<input>") -> XmlInput:
    """Parse a model file's bytes; never raises for bad input."""
    if len(data) > MAX_BYTES:
        msg = f"file is larger than {MAX_BYTES // 2**20} MiB; split the model"
        return XmlInput(path, None, [diagnostic("X103", msg, file=path)])
    if not data or data.isspace():  # not strip(): that would copy the whole file
        return XmlInput(
            path, None, [diagnostic("X104", "file is empty: export it again", file=path)]
        )
    if _WIDE_DECLARATION.match(data) and b"\x00" not in data[:_SCAN_BYTES]:
        msg = (
            "the file declares a 16- or 32-bit encoding but its bytes are single-byte text: fix the "
            "encoding declaration or re-export"
        )
        return XmlInput(path, None, [diagnostic("X105", msg, file=path, line=1)])
    strict = safexml.parser(remove_blank_text=True)
    try:
        # Only a prefix is scanned: a 4 MB export is not searched twice; the tree check sees the rest.
        root = safexml.parse(data, strict, scan_end=_SCAN_BYTES, external_doctype=True)
    except safexml.Refused as refused:  # found in the tree: past the prefix, where?
        located = safexml.find_declaration(data, external_doctype=True)
        return _refused(path, located or refused)
    except etree.XMLSyntaxError as err:
        return _after_strict_failure(data, path, err, strict)
    except (ValueError, LookupError) as err:  # e.g. an unknown encoding name in the declaration
        return XmlInput(path, None, [diagnostic("X105", f"cannot decode: {err}", file=path)])
    result = XmlInput(path, root, encoding=root.getroottree().docinfo.encoding)
    result.diagnostics += _utf8_declared_single_byte(data, result.encoding, path)
    return result


def _refused(path: str, refused: safexml.Refused) -> XmlInput:
    if refused.line is None:  # a DOCTYPE past the scanned prefix, or in UTF-16
        msg = "document type declaration refused: it has an internal subset or entities, which UML exports never have"
        return XmlInput(path, None, [diagnostic("X102", msg, file=path)])
    msg = (
        "document type or entity declaration refused: UML exports have no internal DTD subset, and one "
        "can read local files (XXE) or expand entities without bound; remove it (an external identifier "
        "alone, <!DOCTYPE XMI SYSTEM 'UML13.dtd'>, is accepted and never loaded)"
    )
    where = {"line": refused.line, "column": refused.column}
    return XmlInput(path, None, [diagnostic("X102", msg, file=path, **where)])


_NON_ASCII = re.compile(r"[^\x00-\x7f]")
# Encodings in which every byte is a character: UTF-8 bytes decode without error, as mojibake.
_SINGLE_BYTE = re.compile(r"^(iso-?8859-\d+|latin-?\d|(windows|cp)-?125\d|us-ascii|ascii)$", re.I)


def _utf8_declared_single_byte(data: bytes, encoding: str | None, path: str) -> list[Diagnostic]:
    """X110 when a file declared ISO-8859-1 (or similar) is really UTF-8: its accented names
    would read as 'ConfiguraÃ§Ã£o'. BOUML writes the declaration from an export option, not from
    the bytes, so the two can disagree."""
    if not encoding or not _SINGLE_BYTE.match(encoding) or data.isascii():
        return []
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:
        return []  # really single-byte text
    first = _NON_ASCII.search(text).start()
    line = text.count("\n", 0, first) + 1
    sample = text[first : first + 1]
    msg = (
        f"the file declares encoding {encoding} but its bytes are UTF-8 (first at line {line}: "
        f"{sample!r} would read as {sample.encode('utf-8').decode('latin-1')!r}): names are read "
        "garbled; change the declaration to UTF-8, or export again with the encoding option UTF-8"
    )
    return [diagnostic("X110", msg, file=path, line=1)]


def _at_end(data: bytes, line: int, col: int) -> bool:
    """Whether a parse error sits at the very end of the data (the mark of a truncated file)."""
    end_line, end_col = safexml.line_column(data, len(data.rstrip()))
    return line > end_line or (line == end_line and col >= end_col - 1)


_BOUML = re.compile(rb'exporter\s*=\s*"Bouml"|<XMI\.exporter>\s*Bouml', re.I)
_OPEN_VALUE = re.compile(r"""([\w:.-]+)\s*=\s*(?:"[^"]*|'[^']*)\Z""")


def _unescaped_hint(data: bytes, line: int, col: int, message: str) -> str:
    """What to do about a '<' or '&' the strict parse stopped at: BOUML writes names unescaped (so
    a name is renamed in BOUML); anywhere else (another tool's file, a hand-written one, a tag's
    value or a rule's text) the character is written as XML writes it, ``&lt;`` or ``&amp;``."""
    char = "&" if "EntityRef" in message or "'&'" in message else "<" if "<" in message else None
    lines = data.split(b"\n", line)
    text = lines[line - 1].decode("utf-8", "replace") if 0 < line <= len(lines) else ""
    opened = _OPEN_VALUE.search(text[: max(col - 1, 0)])
    attribute = opened.group(1) if opened else None
    recovered = "the rest was read in recovery mode so that every other check could run, but"
    if _BOUML.search(data[:8192]) and attribute == "name":
        return (
            f"{recovered} names near this place may be cut short (BOUML writes names unescaped: "
            "rename the element, e.g. no '<' or '&', and export again)"
        )
    escaped = {"<": "'<' as &lt;", "&": "'&' as &amp;"}
    how = escaped[char] if char else "'<' as &lt; and '&' as &amp;"
    where = f"in the value of {attribute!r}" if attribute else "in the text of an element"
    example = " (a rule's 'a < b' as 'a &lt; b')" if char != "&" else ""
    return f"{where}, write {how}{example}; {recovered} what is near this place may be cut short"


def _after_strict_failure(
    data: bytes, path: str, err: etree.XMLSyntaxError, parser: etree.XMLParser
) -> XmlInput:
    # The strict parse scanned only a prefix for declarations, and failed before checking the tree.
    # A file that failed is rare: scan all of it, so that a declaration past the prefix is refused
    # (X102) whatever else is wrong, and recovery, which drops a misplaced one, never hides it.
    found = safexml.find_declaration(data, external_doctype=True)
    if found is not None:
        return _refused(path, found)
    first = parser.error_log[0] if len(parser.error_log) else None
    kind = first.type_name if first is not None else ""
    line = first.line if first is not None else (err.lineno or 0)
    col = first.column if first is not None else 0
    message = (first.message if first is not None else str(err)).strip()
    limit = safexml.exceeded_limit(message)
    if limit is not None:
        kind, message = "ERR_RESOURCE_LIMIT", limit
    if kind not in _FATAL and _at_end(data, line, col):
        kind = "ERR_DOCUMENT_END"  # cut inside a tag or attribute: libxml2 names the symptom
    if kind not in _RECOVERABLE and kind not in _FATAL:
        msg = f"not well-formed XML: {message}; fix the file at this place or export it again"
        return XmlInput(path, None, [diagnostic("X108", msg, file=path, line=line, column=col)])
    if kind in _FATAL:
        code, todo = _FATAL[kind]
        return XmlInput(
            path, None, [diagnostic(code, f"{message}: {todo}", file=path, line=line, column=col)]
        )
    recovering = safexml.parser(recover=True, remove_blank_text=True)
    try:
        # scanned whole again (cheap beside a recovery): recovery drops a misplaced declaration
        root = safexml.parse(data, recovering, external_doctype=True)
    except safexml.Refused as refused:
        return _refused(path, refused)
    except etree.XMLSyntaxError:
        root = None
    if root is None:
        msg = f"not well-formed XML: {message}; fix the file at this place"
        return XmlInput(path, None, [diagnostic("X108", msg, file=path, line=line, column=col)])
    msg = f"not well-formed XML: {message}; {_unescaped_hint(data, line, col, message)}"
    return XmlInput(
        path,
        root,
        [diagnostic("X107", msg, file=path, line=line, column=col)],
        recovered=True,
        encoding=root.getroottree().docinfo.encoding,
    )
