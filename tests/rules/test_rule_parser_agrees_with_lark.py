"""The rule parser reads rules as lark itself reads rules.lark. lark is the oracle, through its public
``Lark(..., transformer=...)`` with the parser's builders and no cache: for every input, the parser
(its fast reader, or lark where the reader declines) builds the same tree, columns included, or stops
at the same place with the same message; the fast reader reads every well-formed rule itself. Inputs
are generated: token soup from the grammar's vocabulary (mostly errors, at every position) and
well-formed rules (mostly successes). And lark's analysed grammar is cached only where nobody else
can write, and a cache file that cannot be loaded changes nothing.
"""

from __future__ import annotations

import os
import pickle
import subprocess
import sys
from pathlib import Path

import lark
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.cachedir import lark_cache
from acordcs.rules import fast, lark_parser
from acordcs.rules import parser as rules
from tests.support.toolchain import ROOT

STARTS = list(lark_parser.STARTS)


# ------------------------------------------------------------------------ lark as the oracle
@pytest.fixture(scope="module")
def oracle() -> lark.Lark:
    """lark's own parser of rules.lark, with the parser's builders, analysed afresh."""
    return lark.Lark(
        lark_parser.grammar(),
        start=STARTS,
        parser="lalr",
        lexer="contextual",
        maybe_placeholders=True,
        transformer=lark_parser.RuleTreeBuilder(),
    )


def plain(children: list) -> list[str]:
    """What a parse built, by repr (a Const's column takes no part in equality, but is in its
    repr), the keywords' tokens left out."""
    return [repr(c) for c in children if not isinstance(c, lark.Token)]


def _outcome_ours(text: str, start: str):
    try:
        return ("ok", plain(rules._parse(start, text)))
    except rules.RuleSyntaxError as err:
        return ("error", err.column, err.message)


def _outcome_fast(text: str, start: str):
    """What the fast reader alone builds, or None where it declines."""
    try:
        return ("ok", plain(fast.read(start, text)))
    except fast.Decline:
        return None


def _outcome_lark(parser: lark.Lark, text: str, start: str):
    try:
        return ("ok", plain(parser.parse(text, start=start).children))
    except (lark.exceptions.UnexpectedToken, lark.exceptions.UnexpectedCharacters) as err:
        error = lark_parser.syntax_error(err, text)
        return ("error", error.column, error.message)
    except rules.RuleSyntaxError as err:  # a builder's own check (a number too long)
        return ("error", err.column, err.message)


WORDS = [
    "if", "IF", "then", "and", "Or", "not", "is", "with", "true", "false", "very", "somewhat",
    "trape", "trian", "gauss", "gbell", "sigm", "speed", "Robot.speed", "a.b.c", "x1", "_y",
    "ifx", "isn", "0", "12", "-3", "+4.5", "1e3", ".5", "2.", "(", ")", ",", ":", ";", ":=", "=",
    "==", "!=", "<=", ">=", "<", ">", "+", "-", "*", "/", '"s"', "'t'", "?", "#", "&", "é", "",
    # what lark's contextual lexer reads by where it is: keywords beside dots, digits and letters
    # beyond ASCII (a \\b ends a keyword, ASCII a name), signs before digits
    "Very.x", "true.x", "is.x", "then2", "a.", "1.2.3", "1e", "--1", "-x", "+", "iſ", "ifé", "1٣",
]  # fmt: skip
SEPARATORS = ["", " ", "  ", "\t", " \t "]


@st.composite
def token_soup(draw) -> str:
    words = draw(st.lists(st.sampled_from(WORDS), max_size=14))
    out = draw(st.sampled_from(SEPARATORS))
    for word in words:
        out += word + draw(st.sampled_from(SEPARATORS))
    return out


# Names spelled like the keywords that are keywords only where they fit (true, very, trape, ...).
VARS = st.sampled_from(
    ["speed", "Robot.speed", "angle", "Camera.rate", "cycleRate", "true", "very", "trape", "If2"]
)
TERMS = st.sampled_from(["slow", "fast", "narrow", "small", "Idle_2", "true", "trape", "FALSE"])
OUTPUT_TERMS = st.one_of(TERMS, st.sampled_from(["very", "somewhat"]))  # no hedge after then


@st.composite
def fuzzy_rule(draw) -> str:
    def atom(depth: int) -> str:
        choice = draw(st.integers(0, 3 if depth < 3 else 0))
        if choice == 0:
            hedges = " ".join(
                draw(st.lists(st.sampled_from(["not", "very", "somewhat"]), max_size=2))
            )
            return f"{draw(VARS)} is {hedges} {draw(TERMS)}".replace("  ", " ")
        if choice == 1:
            return f"({cond(depth + 1)})"
        if choice == 2:
            return f"not ({cond(depth + 1)})"
        return f"{atom(depth + 1)} {draw(st.sampled_from(['and', 'or', 'AND']))} {atom(depth + 1)}"

    def cond(depth: int) -> str:
        return atom(depth)

    label = draw(st.sampled_from(["", "r1: ", "Slow_down : ", "very:"]))
    outs = " and ".join(
        f"{draw(VARS)} is {draw(OUTPUT_TERMS)}" for _ in range(draw(st.integers(1, 3)))
    )
    weight = draw(
        st.sampled_from(["", " with 0.5", " with 1", " WITH .25", " with +1", " with 1e-1"])
    )
    return f"{label}if {cond(0)} then {outs}{weight}"


@st.composite
def crisp_rule(draw) -> str:
    def operand(depth: int) -> str:
        choice = draw(st.integers(0, 5 if depth < 3 else 2))
        if choice == 0:
            return draw(VARS)
        if choice == 1:
            literals = ["0", "3", "-1", "2.5", "1e2", '"on"', "'a b'", "true", "FALSE", "+4", "-.5"]
            return draw(st.sampled_from([*literals, "007", "1.", "2.e3", "- 1"]))
        if choice == 2:
            return f"-{draw(VARS)}"
        if choice == 3:
            return f"({expr(depth + 1)})"
        op = draw(st.sampled_from(["+", "-", "*", "/"]))
        space = draw(st.sampled_from(["", " "]))  # 1-2 subtracts, where 1 -2 would not
        return f"{operand(depth + 1)}{space}{op}{space}{operand(depth + 1)}"

    def comparison(depth: int) -> str:
        op = draw(st.sampled_from(["==", "!=", "<", "<=", ">", ">="]))
        return f"{operand(depth)} {op} {operand(depth)}"

    def expr(depth: int) -> str:
        choice = draw(st.integers(0, 3 if depth < 3 else 0))
        if choice == 0:
            return comparison(depth + 1)
        if choice == 1:
            return f"not {expr(depth + 1)}"
        return f"{expr(depth + 1)} {draw(st.sampled_from(['and', 'or']))} {expr(depth + 1)}"

    def action() -> str:
        if draw(st.booleans()):
            return f"{draw(VARS)} = {operand(2)}"
        args = ", ".join(operand(2) for _ in range(draw(st.integers(0, 3))))
        return f"recovery.recover({args})"

    actions = " and ".join(action() for _ in range(draw(st.integers(1, 3))))
    return f"if {expr(0)} then {actions}"


@st.composite
def term_list(draw) -> str:
    shapes = [
        "trape 0 0 40 80",
        "trian -10 0 10",
        "gauss 5 2",
        "gbell 1 2 3",
        "sigm 2 -1",
        "(0, 0) (5, 1) (10, 0)",
        "42",
        "TRIAN 1-2 3",
        "(0,-1)(+2,1)",
        "-.5e3",
    ]
    names = st.sampled_from(["t", "trape", "very", "true"])
    count = draw(st.integers(1, 4))
    parts = [f"{draw(names)}{i} := {draw(st.sampled_from(shapes))}" for i in range(count)]
    return "; ".join(parts) + draw(st.sampled_from(["", ";", " ; "]))


ORACLE_SETTINGS = settings(
    max_examples=300, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)


@ORACLE_SETTINGS
@given(text=token_soup(), start=st.sampled_from(STARTS))
def test_token_soup_stops_where_lark_stops(oracle, text, start):
    outcome = _outcome_lark(oracle, text, start)
    assert _outcome_ours(text, start) == outcome
    assert _outcome_fast(text, start) in (None, outcome)


@ORACLE_SETTINGS
@given(text=fuzzy_rule())
def test_fuzzy_rules_build_what_lark_builds(oracle, text):
    outcome = _outcome_ours(text, "start_fuzzy")
    assert outcome[0] == "ok", (text, outcome)
    assert outcome == _outcome_lark(oracle, text, "start_fuzzy")
    assert _outcome_fast(text, "start_fuzzy") == outcome  # read without lark


@ORACLE_SETTINGS
@given(text=crisp_rule())
def test_crisp_rules_build_what_lark_builds(oracle, text):
    outcome = _outcome_ours(text, "start_crisp")
    assert outcome[0] == "ok", (text, outcome)
    assert outcome == _outcome_lark(oracle, text, "start_crisp")
    assert _outcome_fast(text, "start_crisp") == outcome


@ORACLE_SETTINGS
@given(text=term_list())
def test_term_lists_build_what_lark_builds(oracle, text):
    outcome = _outcome_ours(text, "start_terms")
    assert outcome[0] == "ok", (text, outcome)
    assert outcome == _outcome_lark(oracle, text, "start_terms")
    assert _outcome_fast(text, "start_terms") == outcome


@pytest.mark.parametrize(
    ("text", "start"),
    [
        ("if x == -1 then y = 1", "start_crisp"),  # the constant -1
        ("if x -1 > 0 then y = 1", "start_crisp"),  # x minus 1
        ("if x == - 1 then y = 1 --2", "start_crisp"),  # - (1), and 1 minus -2
        ("if x == --1 then y = +2", "start_crisp"),
        ("if (a > 1 and b) + 1 then f() and g(1, -x, (b or not c))", "start_crisp"),
        ("true: if true == TRUE then true = false", "start_crisp"),
        ("very: if very is not very slow then true is very", "start_fuzzy"),
        ("IF A IS NOT B THEN C IS D WITH .5", "start_fuzzy"),
        ("if If2 is x or (a is b) and not (c is d) then then2 is y with +1", "start_fuzzy"),
        (
            "trape := trape 1 2 3 4; x := trian 1-2 3; p := (0,-1)(+2, 1); s := -.5e3;",
            "start_terms",
        ),
        ("t := trian 1.2.3 4", "start_terms"),  # 1.2, .3 and 4, as lark reads them
    ],
)
def test_what_lark_reads_by_where_it_is_the_fast_reader_reads_alike(oracle, text, start):
    outcome = _outcome_lark(oracle, text, start)
    assert outcome[0] == "ok"
    assert _outcome_fast(text, start) == outcome


@pytest.mark.parametrize(
    ("text", "start"),
    [
        ("if a iſ b then c is d", "start_fuzzy"),  # lark's /is\\b/i matches iſ (a long s)
        ("if " + "not (" * 50 + "x is low" + ")" * 50 + " then y is high", "start_fuzzy"),
        ("if x > " + "-" * 50 + "1 then y = 1", "start_crisp"),
        ("if x > 1 then y = 1" + "0" * 70, "start_crisp"),  # lark's builder words it
    ],
)
def test_what_the_fast_reader_declines_lark_reads(oracle, text, start):
    assert _outcome_fast(text, start) is None
    assert _outcome_ours(text, start) == _outcome_lark(oracle, text, start)


def test_reading_well_formed_rules_never_imports_lark():
    """The fast reader reads every rule of the samples; lark comes in for a rule it declines (an
    error here, which lark words)."""
    code = (
        "import sys\n"
        "from acordcs.model.reading import read_model\n"
        "from acordcs.rules import RuleSyntaxError, parse_rule\n"
        "print(len(read_model('samples/weblab/weblab.xmi').diagnostics), 'lark' in sys.modules)\n"
        "try:\n"
        "    parse_rule('if a is then')\n"
        "except RuleSyntaxError as err:\n"
        "    print(err.column, err.message)\n"
        "print('lark' in sys.modules)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True
    )
    assert done.stdout.splitlines() == [
        "0 False",
        "9 unexpected 'then'; expected 'not', a hedge, a name",
        "True",
    ]


@pytest.mark.parametrize(
    ("text", "start", "expected"),
    [
        ("", "start_fuzzy", (1, "unexpected end of rule; expected 'if', a name")),
        ("   ", "start_crisp", (4, "unexpected end of rule; expected 'if', a name")),
        (
            "if speed is slow then",
            "start_fuzzy",
            (22, "unexpected end of rule; expected a variable"),
        ),
        (
            "if x == 1 then y = 9" + "9" * 70,
            "start_crisp",
            (20, "number 999999999999... is too long"),
        ),
        ("if a is b then c is d with 0.5 ?", "start_fuzzy", (32, "unexpected character '?'")),
        ("if a is then", "start_fuzzy", (9, "unexpected 'then'; expected 'not', a hedge, a name")),
        ("t := trian 1 2", "start_terms", (15, "unexpected end of rule; expected a number")),
        (
            "if 1a is b then c is d",
            "start_fuzzy",
            (4, "unexpected '1'; expected '(', 'not', a variable"),
        ),
    ],
)
def test_edge_cases_agree(oracle, text, start, expected):
    assert _outcome_ours(text, start) == ("error", *expected)
    assert _outcome_lark(oracle, text, start) == ("error", *expected)


def test_long_runs_of_blanks_cost_linear_time():
    """Blanks are skipped atomically: a backtracking skip would need 2**n steps before a bad
    character (n = 40 would not finish today). Run apart, with a bound a hang cannot pass."""
    code = (
        "from acordcs.rules import parse_rule, RuleSyntaxError\n"
        "for text in ('if' + ' ' * 100000 + '?', 'if' + ' \\t' * 50000 + 'a is b then c is d'):\n"
        "    try:\n"
        "        parse_rule(text)\n"
        "        print('ok')\n"
        "    except RuleSyntaxError as err:\n"
        "        print(err.column)\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True
    )
    assert done.stdout.split() == ["100003", "ok"]


# ------------------------------------------------------------------------ lark's cache
BAD_RULE = (
    "if a is then",
    "start_fuzzy",
    (9, "unexpected 'then'; expected 'not', a hedge, a name"),
)


@pytest.fixture
def fresh_parser(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    """lark's parser built again, its cache in ``tmp_path``; the next user builds it once more."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    lark_parser.parser.cache_clear()
    yield tmp_path / "acordcs"
    lark_parser.parser.cache_clear()


def _error(text: str, start: str) -> tuple[int | None, str]:
    with pytest.raises(rules.RuleSyntaxError) as caught:
        lark_parser.parse(start, text)
    return (caught.value.column, caught.value.message)


def test_the_parser_is_built_from_rules_lark_and_cached_privately(fresh_parser: Path) -> None:
    text, start, expected = BAD_RULE
    assert _error(text, start) == expected
    (cached,) = fresh_parser.glob("rules-*.lark-cache")
    assert cached == Path(lark_cache(lark_parser.grammar(), "rules"))
    assert os.stat(fresh_parser).st_mode & 0o777 == 0o700
    lark_parser.parser.cache_clear()  # loaded from the file this time
    assert _error(text, start) == expected
    tree = lark_parser.parse("start_terms", "slow := trape 0 0 40 80")
    assert plain(tree.children) == [
        "TermDef(name=Name(text='slow', column=1), shape='trapezoid', "
        "parameters=(0.0, 0.0, 40.0, 80.0))"
    ]


def test_a_cache_file_that_cannot_be_loaded_is_rebuilt(fresh_parser: Path) -> None:
    path = Path(lark_cache(lark_parser.grammar(), "rules"))
    for damaged in (b"", b"not a pickle", pickle.dumps({"parser": None})[:20]):
        path.write_bytes(damaged)
        lark_parser.parser.cache_clear()
        text, start, expected = BAD_RULE
        assert _error(text, start) == expected
        assert path.stat().st_size > 1000  # lark wrote it again, whole


def test_a_cache_that_cannot_be_written_changes_nothing(
    fresh_parser: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(
        lark_parser, "lark_cache", lambda *_: str(fresh_parser / "missing" / "rules.lark-cache")
    )
    text, start, expected = BAD_RULE
    assert _error(text, start) == expected
    assert not (fresh_parser / "missing").exists()


def test_an_unusable_cache_directory_changes_nothing(tmp_path: Path, monkeypatch) -> None:
    blocked = tmp_path / "a-file"
    blocked.write_text("")
    monkeypatch.setenv("XDG_CACHE_HOME", str(blocked))  # acordcs/ cannot be made under a file
    lark_parser.parser.cache_clear()
    try:
        assert lark_cache(lark_parser.grammar(), "rules") is False
        text, start, expected = BAD_RULE
        assert _error(text, start) == expected
    finally:
        lark_parser.parser.cache_clear()


class _Planted:
    """A pickle that, when loaded, leaves a mark: the code another user's file would run."""

    def __init__(self, mark: Path) -> None:
        self.mark = mark

    def __reduce__(self):
        return (Path.write_text, (self.mark, "loaded"))


@pytest.mark.parametrize("how", ["ours", "writable by others", "owned by another user"])
def test_a_cache_file_another_user_could_have_written_is_never_loaded(
    fresh_parser: Path, tmp_path: Path, how: str
) -> None:
    path = Path(lark_cache(lark_parser.grammar(), "rules"))
    mark = tmp_path / "mark"
    path.write_bytes(b"x\n" + pickle.dumps(_Planted(mark)))
    if how == "writable by others":
        os.chmod(path, 0o666)
    elif how == "owned by another user":
        if os.getuid() != 0:
            pytest.skip("only root can give a file to another user")
        os.chown(path, 65534, 65534)
    text, start, expected = BAD_RULE
    assert _error(text, start) == expected
    # The control: a file of ours is unpickled (lark reads it before it checks anything), so the
    # others would have run had they been loaded.
    assert mark.exists() == (how == "ours")
    if how != "ours":
        assert lark_cache(lark_parser.grammar(), "rules") is False  # lark was given no cache
