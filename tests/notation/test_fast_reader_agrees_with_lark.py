"""The fast reader of the notation reads what lark's parser of acord.lark reads, into the same
outline (places included), or declines: on every sample's text and on edited copies of them."""

from __future__ import annotations

import random
from pathlib import Path

import pytest

from acordcs.notation.fast_text import read_outline
from acordcs.notation.syntax import MAX_DEPTH, NotationError, lark_outline
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
            except NotationError:
                assert fast is None, f"the fast reader read what lark refuses: {old!r} -> {new!r}"
                continue
            if fast is not None:
                assert fast == slow, f"{old!r} -> {new!r} at {start}"
