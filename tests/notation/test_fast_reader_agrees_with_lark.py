"""The fast reader of the notation reads what lark's parser of acord.lark reads, into the same
outline (places included), or declines: on every sample's text and on edited copies of them."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from acordcs.notation.fast_text import read_or_decline, read_outline
from acordcs.notation.syntax import MAX_DEPTH, NotationError, lark_outline, parse_text
from tests.support.toolchain import SAMPLES

TEXTS = sorted(SAMPLES.glob("*/*.acord"))
# Edits that keep a text well formed, or not: each must be read alike, or declined by the fast reader.
EDITS = [
    ("\n", "\n\n"),
    (" {", "{"),
    (", ", ","),
    (" = ", "="),
    ("(", "( "),
    ("\n  ", "\n  // a comment\n  "),
    ("\n  ", "\n  /* a\n comment */ "),
    ("\n  ", "\n  # a comment\n  "),
    ("{\n", "{ /// a doc\n"),
    ("attribute ", "attribute\n"),
    ("model ", "modelX "),
    (": double", ': "double"'),
    ("(", "()"),
    (")", ",)"),
    ("}", ""),
    ("{", ""),
    ("rules {", "rules Extra {"),
    ("\n    ", "\n    // not a rule\n    "),
    ("hosts ", "hosts Deployment::"),
    ("hosts ", 'hosts "x".'),
    ("operation ", "operation id "),
    ("(", '("'),
    ("\n", "\n\t\v"),
    ("= ", "= -.5e3 "),
]


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: p.name)
def test_the_fast_reader_reads_every_sample_as_lark_does(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    fast = read_outline(text, MAX_DEPTH)
    assert fast is not None, "the fast reader declined a text convert wrote"
    assert fast == lark_outline(text)


@pytest.mark.parametrize("path", TEXTS, ids=lambda p: p.name)
def test_the_fast_reader_reads_edited_texts_as_lark_does_or_declines(path: Path) -> None:
    text = path.read_text(encoding="utf-8")
    draw = random.Random(path.name)
    for old, new in EDITS:
        starts = [n for n in range(len(text)) if text.startswith(old, n)]
        for start in draw.sample(starts, min(3, len(starts))):
            edited = text[:start] + new + text[start + len(old) :]
            fast = read_outline(edited, MAX_DEPTH)
            try:
                slow = lark_outline(edited)
            except NotationError as refused:
                assert fast is None, f"the fast reader read what lark refuses: {old!r} -> {new!r}"
                # what lark says of the part the fast reader keeps is what it says of the file:
                # the place and what was found (what it expects after a character it cannot
                # read at all is the lexer's state, whose LALR lookaheads merge other contexts)
                with pytest.raises(NotationError) as found:
                    parse_text(edited.encode())
                got, wanted = found.value, refused
                assert (got.line, got.column) == (wanted.line, wanted.column), (old, new, start)
                if "unexpected character" in wanted.message:
                    assert (
                        got.message.split("; expected")[0] == wanted.message.split("; expected")[0]
                    )
                else:
                    assert got.message == wanted.message, (old, new, start)
                continue
            if fast is not None:
                assert fast == slow, f"{old!r} -> {new!r} at {start}"


def test_lark_reads_only_what_matters_to_an_error_in_a_large_text() -> None:
    """An error at the end of a large text: lark is given the heads of what encloses it and the
    member it is in, the rest blanked, not the whole file (its time is bounded by that part)."""
    weblab = (SAMPLES / "weblab" / "weblab.acord").read_text(encoding="utf-8")
    body = weblab.split("\n", 1)[1]
    text = (
        "model Big\npackage Outer {\n"
        + body * 40
        + "  component Last {\n    attribute x: int =\n  }\n}\n"
    )
    outline, relevant = read_or_decline(text, MAX_DEPTH)
    assert outline is None and relevant is not None
    assert relevant.count("\n") == text[: len(relevant)].count("\n")  # lines stay where they were
    kept = "".join(relevant.split())
    assert len(kept) < 100, kept  # 'packageOuter{componentLast{attributex:int=' and no more
    with pytest.raises(NotationError) as found:
        parse_text(text.encode())
    line = text.count("\n", 0, text.index("  }\n}\n", len(text) - 20)) + 1
    assert found.value.line == line and "unexpected '}'" in found.value.message
