"""The text is hostile input like XMI: every error says file:line:col and what to do, limits hold,
no traceback, and a finding about a rule points at the rule's own line and column in the text."""

from __future__ import annotations

from pathlib import Path

import pytest

from acordcs.model.reading import read_model
from acordcs.notation import syntax
from tests.support.toolchain import SAMPLES, run_main

GREENHOUSE = (SAMPLES / "tutorial" / "greenhouse.acord").read_text(encoding="utf-8")


def _validate(tmp_path: Path, text: str | bytes, name: str = "model.acord"):
    path = tmp_path / name
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return path, run_main(["validate", str(path)])


def test_a_misspelt_keyword_is_named_with_the_keyword_meant(tmp_path: Path) -> None:
    path, result = _validate(tmp_path, "model M\n\ncomponnt Fan\n")
    assert result.code == 2
    assert (
        f"{path}:3:1: error: M101 unexpected 'componnt' (did you mean 'component'?)" in result.out
    )
    assert "expected" in result.out and "Traceback" not in result.both


def test_a_missing_parenthesis_says_what_was_expected(tmp_path: Path) -> None:
    path, result = _validate(tmp_path, "model M\ncomponent Fan (language = python {\n}\n")
    assert result.code == 2
    assert f"{path}:2:34: error: M101 unexpected '{{'; expected ')', ','" in result.out


def test_a_rule_finding_points_at_the_rule_in_the_text(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("if temperature is warm", "if temperatur is warm")
    line = next(n for n, t in enumerate(text.splitlines(), 1) if "temperatur is warm" in t)
    rule_column = text.splitlines()[line - 1].index("warm:") + 1
    path, result = _validate(tmp_path, text)
    assert result.code == 1
    # 'temperatur' is at column 10 of the rule 'warm: if temperatur ...'
    assert f"{path}:{line}:{rule_column + 9}: error: L402 rule 2 of tag 'Rule'" in result.out
    assert "column 10: variable 'temperatur'" in result.out


def test_a_rule_syntax_error_points_at_the_word_in_the_text(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("warm then Vent", "warm thn Vent")
    line = next(n for n, t in enumerate(text.splitlines(), 1) if " thn " in t)
    column = text.splitlines()[line - 1].index("thn") + 1
    path, result = _validate(tmp_path, text)
    assert f"{path}:{line}:{column}: error: L401" in result.out


def test_a_term_syntax_error_points_at_the_word_in_the_text(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("warm := trian 20 26 32", "warm := trian 20 26 32; wet := trap 1")
    line = next(n for n, t in enumerate(text.splitlines(), 1) if "trap 1" in t)
    column = text.splitlines()[line - 1].index("trap 1") + 1
    path, result = _validate(tmp_path, text)
    assert f"{path}:{line}:{column}: error: T307 terms of 'temperature'" in result.out


def test_a_relation_to_no_element_says_the_name_meant(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("adapts Vent", "adapts Vnt")
    path, result = _validate(tmp_path, text)
    assert result.code == 1
    assert f"{path}:" in result.out
    assert "M103 adapts 'Vnt' names no element of the model (did you mean 'Vent'?)" in result.out


def test_two_elements_with_one_id_are_reported(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("component Sensor", 'component Sensor id "_Vent"')
    _, result = _validate(tmp_path, text)
    assert "M104 id '_Vent'" in result.out


def test_an_unknown_tag_is_reported_by_the_same_check_as_in_xmi_at_the_tag(tmp_path: Path) -> None:
    text = GREENHOUSE.replace("(engine = fuzzy", "(engin = fuzzy")
    line = next(n for n, t in enumerate(text.splitlines(), 1) if "engin =" in t)
    column = text.splitlines()[line - 1].index("engin") + 1
    path, result = _validate(tmp_path, text)
    assert f"{path}:{line}:{column}: error: T320 <<CtxPolicySet>> has no tag 'engin'" in result.out
    assert "did you mean 'engine'" in result.out


@pytest.mark.parametrize(
    "data",
    [
        b"\xff\xfe\x00garbage",
        b"model M\ncomponent F {\x00}\n",
        b'model M\ncomponent F (language = "unterminated)\n',
        b"model M\n" + b"package P {\n" * 70 + b"}\n" * 70,
        b"{" * 100_000,
        b"model " + b"x" * 5000 + b"\n" + b"rules {" * 3,
        b"<<<>>>",
        b"",
    ],
    ids=["not-utf8", "nul", "open-string", "deep", "braces", "long-name", "xml-ish", "empty"],
)
def test_hostile_text_is_refused_or_read_without_a_traceback(tmp_path: Path, data: bytes) -> None:
    path, result = _validate(tmp_path, data)
    assert "Traceback" not in result.both and "internal error" not in result.both
    assert result.code in (0, 1, 2)
    if data.strip() and result.code == 2:
        assert f"{path}:" in result.out


def test_nesting_deeper_than_the_limit_is_refused(tmp_path: Path) -> None:
    deep = "model M\n" + "package P {\n" * (syntax.MAX_DEPTH + 1) + "}\n" * (syntax.MAX_DEPTH + 1)
    _, result = _validate(tmp_path, deep)
    assert result.code == 2 and "M102" in result.out and "nested more than" in result.out


def test_a_text_over_the_size_limit_is_refused_before_it_is_parsed(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(syntax, "MAX_BYTES", 1000)
    _, result = _validate(tmp_path, GREENHOUSE + "//" + "x" * 1000)
    assert result.code == 2 and "M102" in result.out and "limit" in result.out


def test_a_named_pipe_is_not_opened_for_reading(tmp_path: Path) -> None:
    import os

    fifo = tmp_path / "pipe.acord"
    os.mkfifo(fifo)
    reading = read_model(str(fifo))
    assert [d.code for d in reading.diagnostics] == ["X101"] and reading.unreadable


def test_rules_are_written_without_escaping(tmp_path: Path) -> None:
    """A crisp rule's '<' and '&&'-free text as in a Rule tag, no &lt; (the XMI form escapes it)."""
    text = (SAMPLES / "papyrus" / "ventilation.acord").read_text(encoding="utf-8")
    assert "Fan.speed > 10 then Fan.setSpeed(10)" in text
    assert "&gt;" not in text and "&lt;" not in text
