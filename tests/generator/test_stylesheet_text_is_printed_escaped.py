"""What a stylesheet says is printed escaped, as the model's names are: an ``xsl:message`` (or a
terminating one's text in the error) holding a newline, U+202E or C1 control characters cannot
forge a line of the build's output (a fake "up to date"), reorder it or move the cursor."""

from __future__ import annotations

from pathlib import Path

from tests.support.generator import build
from tests.support.toolchain import WEBLAB, no_crash

FORGED = "\nbuild/x: up to date (config; model unchanged, nothing written)\n\u202eevil\u0085\u009b2J\rend"


def _sheet(tmp_path: Path, terminate: str) -> Path:
    path = tmp_path / "sheet" / "talk.xsl"
    path.parent.mkdir()
    text = "".join(f"&#x{ord(c):x};" if ord(c) < 32 or ord(c) > 126 else c for c in FORGED)
    path.write_text(
        '<xsl:stylesheet version="3.0" xmlns:xsl="http://www.w3.org/1999/XSL/Transform">\n'
        '  <xsl:template match="/">\n'
        f'    <xsl:message terminate="{terminate}">said:{text}</xsl:message>\n'
        '    <xsl:result-document href="t.txt" method="text">t</xsl:result-document>\n'
        "  </xsl:template>\n"
        "</xsl:stylesheet>\n",
        encoding="utf-8",
    )
    return path


def _no_forged_line(output: str) -> None:
    for line in output.splitlines():
        assert not line.startswith("build/x:"), output
    for character in ("\u202e", "\u0085", "\u009b", "\r"):
        assert character not in output, output


def test_a_message_cannot_forge_a_line(tmp_path: Path):
    done = build(WEBLAB, tmp_path / "out", "-t", str(_sheet(tmp_path, "no")))
    assert done.code == 0, done.both
    _no_forged_line(done.both)
    assert "acordcs-gen: target talk.xsl: said:\\u000abuild/x: up to date" in done.err
    assert "\\u202eevil\\u0085\\u009b2J\\u000dend" in done.err


def test_a_terminating_message_cannot_forge_a_line(tmp_path: Path):
    failed = build(WEBLAB, tmp_path / "out", "-t", str(_sheet(tmp_path, "yes")))
    no_crash(failed)
    assert failed.code == 1, failed.both
    _no_forged_line(failed.both)
    assert "\\u202eevil" in failed.err
    assert not (tmp_path / "out").exists()
