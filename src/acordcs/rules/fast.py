"""The rule reader's fast path: the rule tree of ``rules.lark`` built by one regular expression and a
recursive descent, without lark: about 20 µs a rule, against about 90 for lark's LALR parser, and a
large model's check was mostly its rules' parse (docs/benchmarks.md).

It builds exactly what lark's parser builds with :class:`~acordcs.rules.lark_parser.RuleTreeBuilder`
(the same nodes, names and columns) or declines: anything it is not sure of (an error, a keyword
where a name could be, a number too long, a non-ASCII letter next to a word, nesting deeper than
:data:`MAX_NESTING`) raises :class:`Decline`, and lark reads the text, so every error is lark's.
``tests/rules/test_rule_parser_agrees_with_lark.py`` holds the two together on generated input.

How lark reads ``rules.lark``, and so what this reader follows: the lexer is contextual, trying in
each parser state only the terminals that state accepts, keywords (``IF.2`` ...) first. So a word
is a keyword only where the keyword fits (``very`` is a hedge after ``is`` but a variable after
``if``, and a term name after ``then v is``); ``if then and or not is with`` are never names
(``VAR`` and ``NAME`` refuse them); a ``-`` or ``+`` is part of a number where a number may start
(``x == -1`` compares with the constant -1, ``x -1`` subtracts 1).
"""

from __future__ import annotations

import re

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

# Parentheses, nots and minus signs nest by recursion here, a few frames a level; deeper texts are
# lark's (its parser does not recurse), which also reports those beyond the tree's MAX_DEPTH.
MAX_NESTING = 40

# One match per token, the blanks before it skipped atomically (a run of blanks before a bad
# character is not split every possible way). A word must not run on into a non-ASCII letter or
# digit: lark's keyword patterns end at a word boundary and its names at ASCII.
_SCAN = re.compile(
    r"[ \t]*+(?:"
    r"(?P<WORD>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*+)(?!\w)"
    r"|(?P<NUMBER>(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<STRING>\"[^\"\n]*\"|'[^'\n]*')"
    r"|(?P<PUNCT>:=|==|!=|<=|>=|[<>=:;,()+\-*/])"
    r"|(?P<END>\Z))"
)
RESERVED = frozenset("if then and or not is with".split())  # never a variable or a name
_HEDGES = frozenset(("very", "somewhat", "not"))
_COMPARE = frozenset(("==", "!=", "<", "<=", ">", ">="))
_SHAPES = {
    "trape": ("trapezoid", 4),
    "trian": ("triangle", 3),
    "gauss": ("gaussian", 2),
    "gbell": ("bell", 3),
    "sigm": ("sigmoid", 2),
}


class Decline(Exception):
    """The fast reader is not sure of this text: lark reads it."""


def _tokens(text: str) -> list[tuple[str, str, int, str]]:
    """(kind, text, offset, key): kind WORD, NUMBER, STRING, the punctuation itself or $END; key
    is a word's lower-cased first part (before any dot), else the token's text."""
    out = []
    pos = 0
    scan = _SCAN.match
    while True:
        found = scan(text, pos)
        if found is None:
            raise Decline
        kind = found.lastgroup
        start, pos = found.span(kind)
        if kind == "END":
            out.append(("$END", "", start, ""))
            return out
        value = text[start:pos]
        if kind == "WORD":
            out.append(("WORD", value, start, value.partition(".")[0].lower()))
        elif kind == "PUNCT":
            out.append((value, value, start, value))
        else:
            out.append((kind, value, start, value))


class _Reader:
    """A recursive descent over one text's tokens, one method per rule of ``rules.lark``."""

    __slots__ = ("at", "tokens")

    def __init__(self, text: str) -> None:
        self.tokens = _tokens(text)
        self.at = 0

    # ---------------------------------------------------------------------------------- tokens
    def keyword(self, word: str) -> bool:
        """Take the keyword ``word`` if it is next."""
        kind, value, _, key = self.tokens[self.at]
        if kind == "WORD" and key == word and "." not in value:
            self.at += 1
            return True
        return False

    def expect(self, kind: str) -> tuple[str, str, int, str]:
        token = self.tokens[self.at]
        if token[0] != kind:
            raise Decline
        self.at += 1
        return token

    def var(self) -> Name:
        """A VAR where no keyword but those of RESERVED could be (a ``true`` is a variable)."""
        kind, value, start, key = self.tokens[self.at]
        if kind != "WORD" or key in RESERVED:
            raise Decline
        self.at += 1
        return Name(value, start + 1)

    def name(self) -> Name:
        """A NAME where no keyword but those of RESERVED could be."""
        kind, value, start, key = self.tokens[self.at]
        if kind != "WORD" or key in RESERVED or "." in value:
            raise Decline
        self.at += 1
        return Name(value, start + 1)

    def signs_a_number(self) -> bool:
        """Whether the ``+`` or ``-`` next is right before a number's digits."""
        kind, _, start, _ = self.tokens[self.at + 1]
        return kind == "NUMBER" and start == self.tokens[self.at][2] + 1

    def number(self) -> str:
        """A NUMBER's text, its sign included: where a number may start, lark's NUMBER pattern
        takes a ``+`` or ``-`` right before the digits."""
        tokens, at = self.tokens, self.at
        kind, value, _, _ = tokens[at]
        if kind in ("-", "+"):
            if not self.signs_a_number():
                raise Decline
            value = kind + tokens[at + 1][1]
            at += 1
        elif kind != "NUMBER":
            raise Decline
        if len(value) > MAX_NUMBER:  # lark's builders report it
            raise Decline
        self.at = at + 1
        return value

    def label(self) -> list:
        """``label: NAME ":"`` at the start of a rule, where IF could be."""
        kind, value, _, key = self.tokens[self.at]
        if kind == "WORD" and key != "if" and self.tokens[self.at + 1][0] == ":":
            self.name()
            self.at += 1
            return [("label", value)]
        return []

    # ----------------------------------------------------------------------------------- fuzzy
    def fuzzy(self) -> list:
        children = self.label()
        if not self.keyword("if"):
            raise Decline
        children.append(self.fcond(0))
        if not self.keyword("then"):
            raise Decline
        children.append(self.consequent())
        while self.keyword("and"):
            children.append(self.consequent())
        if self.keyword("with"):
            children.append(("weight", float(self.number())))
        self.expect("$END")
        return children

    def fcond(self, depth: int) -> object:
        left = self.fatom(depth)
        while True:
            if self.keyword("and"):
                left = BoolOp("and", left, self.fatom(depth))
            elif self.keyword("or"):
                left = BoolOp("or", left, self.fatom(depth))
            else:
                return left

    def fatom(self, depth: int) -> object:
        if depth > MAX_NESTING:
            raise Decline
        if self.keyword("not"):
            self.expect("(")
            inner = self.fcond(depth + 1)
            self.expect(")")
            return Not(inner)
        if self.tokens[self.at][0] == "(":
            self.at += 1
            inner = self.fcond(depth + 1)
            self.expect(")")
            return inner
        var = self.var()
        if not self.keyword("is"):
            raise Decline
        hedges = []
        tokens = self.tokens
        while True:  # (HEDGE | NOT)* before the term: there, very, somewhat and not are keywords
            kind, value, _, key = tokens[self.at]
            if kind != "WORD" or key not in _HEDGES or "." in value:
                break
            hedges.append(key)
            self.at += 1
        return Is(var, tuple(hedges), self.name())

    def consequent(self) -> Consequent:
        var = self.var()
        if not self.keyword("is"):
            raise Decline
        return Consequent(var, self.name())  # no hedge here: ``very`` is a term's name

    # ----------------------------------------------------------------------------------- crisp
    def crisp(self) -> list:
        children = self.label()
        if not self.keyword("if"):
            raise Decline
        children.append(self.cexpr(0))
        if not self.keyword("then"):
            raise Decline
        children.append(self.action())
        while self.keyword("and"):
            children.append(self.action())
        self.expect("$END")
        return children

    def cexpr(self, depth: int) -> object:
        left = self.cand(depth)
        while self.keyword("or"):
            left = BoolOp("or", left, self.cand(depth))
        return left

    def cand(self, depth: int) -> object:
        left = self.cnot(depth)
        while self.keyword("and"):
            left = BoolOp("and", left, self.cnot(depth))
        return left

    def cnot(self, depth: int) -> object:
        if self.keyword("not"):
            if depth > MAX_NESTING:
                raise Decline
            return Not(self.cnot(depth + 1))
        left = self.arith(depth)
        op = self.tokens[self.at][0]
        if op in _COMPARE:
            self.at += 1
            return Compare(op, left, self.arith(depth))
        return left

    def arith(self, depth: int) -> object:
        left = self.product(depth)
        while (op := self.tokens[self.at][0]) in ("+", "-"):
            self.at += 1
            left = Arith(op, left, self.product(depth))
        return left

    def product(self, depth: int) -> object:
        left = self.unary(depth)
        while (op := self.tokens[self.at][0]) in ("*", "/"):
            self.at += 1
            left = Arith(op, left, self.unary(depth))
        return left

    def unary(self, depth: int) -> object:
        if depth > MAX_NESTING:
            raise Decline
        tokens = self.tokens
        kind, value, start, key = tokens[self.at]
        if kind == "NUMBER" or (kind in ("-", "+") and self.signs_a_number()):
            return Const(number_value(self.number()), start + 1)
        if kind == "-":
            self.at += 1
            return Neg(self.unary(depth + 1))
        if kind == "STRING":
            self.at += 1
            return Const(value[1:-1], start + 1)
        if kind == "(":
            self.at += 1
            inner = self.cexpr(depth + 1)
            self.expect(")")
            return inner
        if kind == "WORD" and key in ("true", "false"):
            if "." in value:
                raise Decline
            self.at += 1
            return Const(key == "true", start + 1)
        return VarRef(self.var())

    def action(self) -> object:
        target = self.var()  # nothing but a variable fits here: ``true = 1`` assigns to true
        kind = self.tokens[self.at][0]
        self.at += 1
        if kind == "=":
            return Assign(target, self.arith(0))
        if kind != "(":
            raise Decline
        args = []
        if self.tokens[self.at][0] != ")":
            args.append(self.arith(0))
            while self.tokens[self.at][0] == ",":
                self.at += 1
                args.append(self.arith(0))
        self.expect(")")
        return Call(target, tuple(args))

    # ----------------------------------------------------------------------------------- terms
    def terms(self) -> list:
        out = []
        tokens = self.tokens
        while True:
            name = self.name()
            self.expect(":=")
            kind, value, _, key = tokens[self.at]
            if kind == "WORD" and key in _SHAPES and "." not in value:
                self.at += 1
                shape, count = _SHAPES[key]
                parameters = tuple(float(self.number()) for _ in range(count))
            elif kind == "(":
                shape, points = "points", []
                while tokens[self.at][0] == "(":
                    self.at += 1
                    points.append(float(self.number()))
                    self.expect(",")
                    points.append(float(self.number()))
                    self.expect(")")
                parameters = tuple(points)
            else:
                shape, parameters = "singleton", (float(self.number()),)
            out.append(TermDef(name, shape, parameters))
            if tokens[self.at][0] == ";":
                self.at += 1
            if tokens[self.at][0] == "$END":
                return out
            if tokens[self.at - 1][0] != ";":
                raise Decline


_STARTS = {"start_fuzzy": _Reader.fuzzy, "start_crisp": _Reader.crisp, "start_terms": _Reader.terms}


def read(start: str, text: str) -> list:
    """What lark's parser of ``rules.lark`` builds from ``text`` (one line) for ``start``: the
    start rule's children, the keywords' tokens left out. Raises :class:`Decline`."""
    try:
        return _STARTS[start](_Reader(text))
    except RecursionError:  # called deep in someone's stack: lark's parser does not recurse
        raise Decline from None
