"""The rule language's parse tables (acordcs.rules.lalr) are cached as JSON under a cheap checksum
name in the private cache directory, verified when read and analysed again when damaged or made for
another grammar; once stored, reading a model needs no lark."""

from __future__ import annotations

import json
from pathlib import Path

from acordcs.rules import lalr
from acordcs.rules import parser as rules
from tests.support.rules import plain
from tests.support.toolchain import ROOT

GRAMMAR = rules._grammar()
STARTS = list(rules._STARTS)


def _stored(tmp_path: Path) -> Path:
    (path,) = (tmp_path / "acordcs").glob("rules-*.lalr.json")
    return path


def test_stored_tables_are_json_with_a_checksum(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    stored = json.loads(_stored(tmp_path).read_text())
    assert stored["format"] == lalr.TABLE_FORMAT and isinstance(stored["check"], int)
    assert stored["tables"]["grammar"] == GRAMMAR and stored["tables"]["starts"] == STARTS
    tables = lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")  # read back
    assert (
        tables.parse("if a is b then c is d", "start_fuzzy", rules._BUILDERS).data == "start_fuzzy"
    )


def test_a_file_whose_checksum_fails_is_analysed_again(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    path = _stored(tmp_path)
    good = path.read_text()
    # A valid JSON file, with one pattern changed: only the checksum tells.
    damaged = good.replace("(?i:if\\\\b)", "(?i:iff\\\\b)", 1)
    assert damaged != good
    path.write_text(damaged)
    tables = lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    assert (
        tables.parse("if a is b then c is d", "start_fuzzy", rules._BUILDERS).data == "start_fuzzy"
    )
    stored = path.read_text()  # analysed and stored again (lark numbers states anew each time)
    assert "(?i:iff" not in stored and lalr._load(stored)["grammar"] == GRAMMAR


def test_tables_of_another_grammar_under_this_name_are_not_used(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    other = GRAMMAR.replace(
        "HEDGE.2: /(very|somewhat)\\b/i", "HEDGE.2: /(very|somewhat|quite)\\b/i"
    )
    assert other != GRAMMAR
    lalr.Tables.for_grammar(other, STARTS, "rules")
    (path,) = (tmp_path / "acordcs").glob("rules-*.lalr.json")
    # As if the two grammars' names collided: this grammar finds the other's tables.
    lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    mine = sorted((tmp_path / "acordcs").glob("rules-*.lalr.json"))
    mine.remove(path)
    (mine,) = mine
    mine.write_text(path.read_text())
    tables = lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    # "quite" is a hedge only in the other grammar: here it is the term.
    tree = tables.parse("if a is quite then c is d", "start_fuzzy", rules._BUILDERS)
    assert tree.children[1].term.text == "quite"
    assert json.loads(mine.read_text())["tables"]["grammar"] == GRAMMAR


def test_a_damaged_cache_file_is_analysed_again(tmp_path, monkeypatch):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    (stored,) = (tmp_path / "acordcs").glob("rules-*.lalr.json")
    stored.write_text('{"format": 1, "actions": "garbage"')
    tables = lalr.Tables.for_grammar(GRAMMAR, STARTS, "rules")
    assert plain(tables.parse("if a is b then c is d", "start_fuzzy", rules._BUILDERS))[0] == "node"
    assert json.loads(stored.read_text())["format"] == lalr.TABLE_FORMAT


def test_validate_never_imports_lark():
    """Once the tables are stored, reading and checking a model runs without lark."""
    import subprocess
    import sys

    from acordcs.cachedir import private_dir

    assert private_dir() is not None, "no private cache directory: lark would run every time"
    rules._tables()  # analysed and stored, if this is the first parse on this machine
    code = (
        "import sys; from acordcs.model.reading import read_model; "
        "read_model('samples/weblab/weblab.xmi'); "
        "print(sorted(m for m in sys.modules if m == 'lark' or m.startswith('lark.')))"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True
    )
    assert done.stdout.strip() == "[]"
