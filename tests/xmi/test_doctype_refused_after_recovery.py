"""A DOCTYPE past the 64 KB prefix the strict parse scans, together with an error recovery repairs,
is refused (X102), wherever it sits and in whatever encoding (issue 14): recovery drops a misplaced
declaration, so the bytes are scanned whole before recovering."""

from __future__ import annotations

import pytest
from lxml import etree

from acordcs import safexml
from acordcs.xmi.source import parse_bytes

HEAD = (
    '<xmi:XMI xmi:version="2.1" xmlns:uml="http://schema.omg.org/spec/UML/2.1" '
    'xmlns:xmi="http://schema.omg.org/spec/XMI/2.1">'
)
PAD = "<!--" + "x" * 70_000 + "-->"
BROKEN_NAME = '<uml:Model xmi:type="uml:Model" xmi:id="m" name="a<b">&e;</uml:Model>'
DOCTYPE = '<!DocType x [<!ENTITY e "boom">]>'

SHAPES = {
    # inside the root, where recovery skips it and the tree then has no document type
    "inside the root": f"{HEAD}{PAD}{DOCTYPE}{BROKEN_NAME}</xmi:XMI>",
    "before the root": f'<?xml version="1.0"?>\n{PAD}{DOCTYPE}\n{HEAD}{BROKEN_NAME}</xmi:XMI>',
    "system identifier with a subset": (
        f'<?xml version="1.0"?>\n{PAD}<!DOCTYPE x SYSTEM "file:///etc/passwd" [<!ENTITY e "b">]>\n'
        f"{HEAD}{BROKEN_NAME}</xmi:XMI>"
    ),
    "entity alone": f'{HEAD}{PAD}<!ENTITY e "boom">{BROKEN_NAME}</xmi:XMI>',
}


@pytest.mark.parametrize("shape", sorted(SHAPES))
def test_a_late_declaration_with_a_recoverable_error_is_refused(shape: str) -> None:
    text = SHAPES[shape]
    result = parse_bytes(text.encode(), "late.xmi")
    assert result.root is None
    codes = [d.code for d in result.diagnostics]
    assert codes == ["X102"], [(d.code, d.message) for d in result.diagnostics]
    line = text[: text.upper().find("<!" + ("ENTITY" if shape == "entity alone" else "DOCTYPE"))]
    assert result.diagnostics[0].line == line.count("\n") + 1


def test_a_late_external_identifier_alone_is_accepted_and_never_opened(tmp_path) -> None:
    # issue 16: an external identifier alone (old XMI 1.x exports) is read as usual, never loaded
    secret = tmp_path / "secret.dtd"
    secret.write_text('<!ENTITY e "from the file">', encoding="utf-8")
    text = (
        f'<?xml version="1.0"?>\n{PAD}<!DOCTYPE x SYSTEM "{secret.as_uri()}">\n'
        f'{HEAD}<uml:Model xmi:type="uml:Model" xmi:id="m" name="a<b"/></xmi:XMI>'
    )
    result = parse_bytes(text.encode(), "late.xmi")
    assert result.root is not None
    assert "X102" not in [d.code for d in result.diagnostics]
    assert b"from the file" not in etree.tostring(result.root)


@pytest.mark.parametrize("encoding", ["utf-16", "utf-16-be", "utf-16-le", "utf-32", "utf-32-be"])
def test_a_late_declaration_in_wide_text_is_refused(encoding: str) -> None:
    result = parse_bytes(SHAPES["inside the root"].encode(encoding), "wide.xmi")
    assert result.root is None
    assert [d.code for d in result.diagnostics] == ["X102"]


def test_the_wide_scan_finds_declarations_only() -> None:
    for encoding in ("utf-16", "utf-32"):
        plain = f'<?xml version="1.0" encoding="{encoding}"?><r><!-- <!DOC --><![CDATA[x]]></r>'
        assert safexml.find_declaration(plain.encode(encoding)) is None
        assert safexml.find_declaration("<r><!doctype r></r>".encode(encoding)) is not None


def test_a_late_declaration_in_a_well_formed_file_says_where() -> None:
    text = f'<?xml version="1.0"?>\n{PAD}\n{DOCTYPE}\n{HEAD}</xmi:XMI>'
    result = parse_bytes(text.encode(), "late.xmi")
    assert [(d.code, d.line, d.column) for d in result.diagnostics] == [("X102", 3, 1)]
