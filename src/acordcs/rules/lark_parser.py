"""lark's LALR(1) parser of ``rules.lark``, through lark's public API, building the rule tree.

:mod:`acordcs.rules.parser` asks it for what its fast reader declines: so every error is worded
here, from lark's own view of the grammar (the column, what was found, what was expected). The
analysed grammar is cached by lark in the private cache directory (:mod:`acordcs.cachedir`):
analysing it takes about 50 ms, loading it about 3.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from functools import cache
from importlib import resources

from lark import (
    Lark,
    Token,
    Transformer,
    Tree,
    UnexpectedCharacters,
    UnexpectedInput,
    UnexpectedToken,
)

from acordcs.cachedir import lark_cache
from acordcs.rules.errors import RuleSyntaxError
from acordcs.rules.tree import (
    MAX_NUMBER,
    Arith,
    Assign,
    BoolOp,
    Call,
    Compare,
    Consequent,
    Const,
    Is,
    Name,
    Neg,
    Not,
    TermDef,
    VarRef,
    number_value,
)

STARTS = ("start_fuzzy", "start_crisp", "start_terms")


def grammar() -> str:
    """The text of ``rules.lark``."""
    return resources.files("acordcs.rules").joinpath("rules.lark").read_text(encoding="utf-8")


# ------------------------------------------------------------------------------ building the tree
# One method per grammar rule (or alias), called by the parser with the rule's kept children as a
# list, as it reduces (lark's inline transformer: no tree is built and walked afterwards); tokens
# are lark Tokens (keyword tokens such as IF or IS arrive too and are skipped by position).
def _name(tok: Token) -> Name:
    return Name(tok.value, tok.column)


def _number(tok: Token) -> str:
    if len(tok.value) > MAX_NUMBER:
        raise RuleSyntaxError(f"number {tok.value[:12]}... is too long", column=tok.column)
    return tok.value


def _num(tok: Token) -> float:
    return float(_number(tok))


def _mf(shape: str) -> Callable[[object, list], tuple[str, tuple[float, ...]]]:
    return lambda _self, c: (shape, tuple(map(_num, c[1:])))


class RuleTreeBuilder(Transformer):
    """The rule tree's builders, one per rule of ``rules.lark`` (by its alias when it has one)."""

    def label(self, c: list) -> tuple[str, str]:
        return ("label", c[0].value)

    def weight(self, c: list) -> tuple[str, float]:
        return ("weight", _num(c[1]))

    def f_is(self, c: list) -> Is:
        var, _is, *hedges, term = c
        return Is(_name(var), tuple(h.value.lower() for h in hedges), _name(term))

    def f_and(self, c: list) -> BoolOp:
        return BoolOp("and", c[0], c[2])

    def f_or(self, c: list) -> BoolOp:
        return BoolOp("or", c[0], c[2])

    def f_not(self, c: list) -> Not:
        return Not(c[1])

    def consequent(self, c: list) -> Consequent:
        return Consequent(_name(c[0]), _name(c[2]))

    def c_or(self, c: list) -> BoolOp:
        return BoolOp("or", c[0], c[2])

    def c_and(self, c: list) -> BoolOp:
        return BoolOp("and", c[0], c[2])

    def c_not(self, c: list) -> Not:
        return Not(c[1])

    def c_cmp(self, c: list) -> Compare:
        return Compare(c[1].value, c[0], c[2])

    def c_arith(self, c: list) -> Arith:
        return Arith(c[1].value, c[0], c[2])

    def c_neg(self, c: list) -> Neg:
        return Neg(c[0])

    def c_num(self, c: list) -> Const:
        return Const(number_value(_number(c[0])), c[0].column)

    def c_str(self, c: list) -> Const:
        return Const(c[0].value[1:-1], c[0].column)

    def c_true(self, c: list) -> Const:
        return Const(True, c[0].column)

    def c_false(self, c: list) -> Const:
        return Const(False, c[0].column)

    def c_var(self, c: list) -> VarRef:
        return VarRef(_name(c[0]))

    def a_assign(self, c: list) -> Assign:
        return Assign(_name(c[0]), c[1])

    def a_call(self, c: list) -> Call:
        return Call(_name(c[0]), tuple(a for a in c[1:] if a is not None))

    def term_def(self, c: list) -> TermDef:
        return TermDef(_name(c[0]), *c[1])

    mf_trape = _mf("trapezoid")
    mf_trian = _mf("triangle")
    mf_gauss = _mf("gaussian")
    mf_gbell = _mf("bell")
    mf_sigm = _mf("sigmoid")

    def mf_points(self, c: list) -> tuple[str, tuple[float, ...]]:
        return ("points", tuple(v for point in c for v in point))

    def point(self, c: list) -> tuple[float, float]:
        return (_num(c[0]), _num(c[1]))

    def mf_singleton(self, c: list) -> tuple[str, tuple[float]]:
        return ("singleton", (_num(c[0]),))


@cache
def parser() -> Lark:
    """lark's LALR(1) parser of ``rules.lark`` (contextual lexer, ``[optional]`` items as None),
    building the tree with :class:`RuleTreeBuilder`."""
    text = grammar()
    return Lark(
        text,
        start=list(STARTS),
        parser="lalr",
        lexer="contextual",
        maybe_placeholders=True,
        transformer=RuleTreeBuilder(),
        # never cache=True: lark would unpickle a predictable file in the shared temp dir
        cache=lark_cache(text, "rules"),
    )


# ------------------------------------------------------------------------------------- the errors
_EXPECT_WORDS = {
    "IF": "'if'",
    "THEN": "'then'",
    "IS": "'is'",
    "AND": "'and'",
    "OR": "'or'",
    "VAR": "a variable",
    "NAME": "a name",
    "NUMBER": "a number",
    "HEDGE": "a hedge",
    "NOT": "'not'",
    "COMPARE": "a comparison",
    "LPAR": "'('",
    "RPAR": "')'",
    "WITH": "'with'",
    "COLON": "':'",
    "EQUAL": "'='",
    "SEMICOLON": "';'",
    "ADDOP": "'+' or '-'",
    "MULOP": "'*' or '/'",
    "MINUS": "'-'",
    "STRING": "a quoted string",
    "TRUE": "true",
    "FALSE": "false",
    "COMMA": "','",
    "$END": "end of rule",
}


def _describe_expected(expected: Iterable[str]) -> str:
    words = sorted({_EXPECT_WORDS.get(e, e.lower()) for e in expected})
    if len(words) > 6:
        words = [*words[:6], "..."]
    return ", ".join(words)


def syntax_error(err: UnexpectedInput, text: str) -> RuleSyntaxError:
    """The error a parse of ``text`` that stopped at ``err`` (lark's UnexpectedToken or
    UnexpectedCharacters) reports, column 1-based in ``text``."""
    token = getattr(err, "token", None)
    if token is not None:  # a token of the grammar where it does not fit, or the end
        if token.type == "$END":
            found, column = "end of rule", len(text) + 1
        else:
            found, column = repr(token.value), token.column
        return RuleSyntaxError(
            f"unexpected {found}; expected {_describe_expected(err.expected)}", column=column
        )
    column = getattr(err, "column", None)
    return RuleSyntaxError(f"unexpected character {text[column - 1]!r}", column=column or None)


def parse(start: str, text: str) -> Tree:
    """``text`` (one line) parsed from ``start``: the start rule's Tree, its children built by
    :class:`RuleTreeBuilder`. Raises RuleSyntaxError with the column."""
    try:
        return parser().parse(text, start=start)
    except (UnexpectedToken, UnexpectedCharacters) as err:
        raise syntax_error(err, text) from None
