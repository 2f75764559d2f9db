"""The FCL reader's fast path: the lark tree of ``fcl.lark`` built by one regular expression and a
recursive-descent walk, for the forms files are made of (about 1 µs a token; lark's own parse loop
takes about 8, and a 1 MB file has about 280,000 tokens).

It builds exactly the tree lark builds (the same ``Tree``/``Token`` objects, names, children and
positions; ``tests/engines/test_fcl_fast_reader.py`` holds the two together on every fixture and on
generated files) or declines: anything unusual (an error, a name spelled like a keyword, a comment
between tokens of one statement is fine but a pragma outside a RULEBLOCK is not, ...) raises
:class:`Decline`, and lark reads the text, so errors and rare forms are exactly lark's.
"""

from __future__ import annotations

import re
from collections.abc import Iterator

from lark import Token, Tree
from lark.tree import Meta

from acordcs.rules import MAX_DEPTH

KEYWORDS = frozenset(
    "FUNCTION_BLOCK END_FUNCTION_BLOCK VAR_INPUT VAR_OUTPUT END_VAR FUZZIFY END_FUZZIFY DEFUZZIFY "
    "END_DEFUZZIFY RULEBLOCK END_RULEBLOCK TERM RANGE METHOD DEFAULT ACCU ACT RULE IF THEN IS AND "
    "OR NOT WITH VERY SOMEWHAT FUNCTION".split()
)
# Blanks and comments (but not the pragma, a token of its own) are skipped by the same match that
# reads the token after them: one match per token. Atomic, so that a run of blanks before a bad
# character is not split every possible way (2**n steps).
_SCAN = re.compile(
    r"(?>(?:\s+|\(\*(?!@acordcs)[\s\S]*?\*\)|/\*[\s\S]*?\*/|//[^\n]*)*)"
    r"(?:(?P<PRAGMA>\(\*@acordcs[^*]*\*\))"
    r"|(?P<WORD>[A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)"
    r"|(?P<NUMBER>[+-]?(?:\d+(?:\.\d+)?|\.\d+)(?:[eE][+-]?\d+)?)"
    r"|(?P<PUNCT>:=|\.\.|[:;(),])"
    r"|(?P<END>\Z))"
)


class Decline(Exception):
    """The fast path is not sure of this text: lark reads it."""


# A raw token: (kind, text, start offset, line, column); kind is a keyword, NAME, NUMBER, PRAGMA
# or the punctuation itself.
def _tokens(text: str) -> Iterator[tuple[str, str, int, int, int]]:
    line, line_start, pos = 1, 0, 0
    scan = _SCAN.match
    count, rfind = text.count, text.rfind
    while True:
        found = scan(text, pos)
        if found is None:
            raise Decline
        kind = found.lastgroup
        start, pos = found.span(kind)
        breaks = count("\n", found.start(), start)
        if breaks:
            line += breaks
            line_start = rfind("\n", 0, start) + 1
        if kind == "END":
            yield ("$END", "", start, line, start - line_start + 1)
            return
        value = text[start:pos]
        if kind == "WORD":
            upper = value.upper()
            if upper in KEYWORDS:
                yield (upper, value, start, line, start - line_start + 1)
                continue
            if "." in value and value.split(".", 1)[0].upper() in KEYWORDS:
                raise Decline  # lark's keyword patterns would split it
            kind = "NAME"
        elif kind == "PUNCT":
            kind = value
        yield (kind, value, start, line, start - line_start + 1)


def _token(raw: tuple, kind: str | None = None) -> Token:
    k, value, start, line, column = raw
    n = len(value)
    return Token(kind or k, value, start, line, column, line, column + n, start + n)


def _tree(data: str, children: list, first, last) -> Tree:
    """A tree with positions as lark's propagate_positions sets them: from the first raw child to the last
    (punctuation included); a subtree counts by its container (itself, or the parentheses that
    grouped it)."""
    meta = Meta()
    if isinstance(first, Tree):
        fm = first.meta
        line, column, start = fm.container_line, fm.container_column, fm.container_start_pos
    else:
        line, column, start = first[3], first[4], first[2]
    if isinstance(last, Tree):
        lm = last.meta
        end_line, end_column, end = (
            lm.container_end_line,
            lm.container_end_column,
            lm.container_end_pos,
        )
    else:
        n = len(last[1])
        end_line, end_column, end = last[3], last[4] + n, last[2] + n
    meta.line = meta.container_line = line
    meta.column = meta.container_column = column
    meta.start_pos = meta.container_start_pos = start
    meta.end_line = meta.container_end_line = end_line
    meta.end_column = meta.container_end_column = end_column
    meta.end_pos = meta.container_end_pos = end
    meta.empty = False
    return Tree(data, children, meta)


def _contain(tree: Tree, first: tuple, last: tuple) -> Tree:
    """A group in parentheses: the tree keeps its positions, its container spans the parentheses."""
    meta = tree.meta
    meta.container_line, meta.container_column, meta.container_start_pos = (
        first[3],
        first[4],
        first[2],
    )
    meta.container_end_line, meta.container_end_column = last[3], last[4] + 1
    meta.container_end_pos = last[2] + 1
    return tree


def parse(text: str) -> Tree:
    """The lark tree of ``text`` (a ``start`` tree), or :class:`Decline`."""
    return _Parser(_tokens(text)).start()


class _Parser:
    """One token of lookahead over the scanner: the raw tokens are never all in memory."""

    def __init__(self, toks: Iterator[tuple]) -> None:
        self.next = toks.__next__
        self.cur = self.next()
        self.depth = 0  # groups and NOTs open: deeper than the rule language allows, lark reads it

    # ---------------------------------------------------------------------------------- helpers
    def peek(self) -> str:
        return self.cur[0]

    def advance(self) -> tuple:
        raw = self.cur
        if raw[0] != "$END":
            self.cur = self.next()
        return raw

    def take(self, kind: str) -> tuple:
        raw = self.cur
        if raw[0] != kind:
            raise Decline
        if kind != "$END":
            self.cur = self.next()
        return raw

    def name(self) -> tuple:
        return self.take("NAME")

    # ---------------------------------------------------------------------------------- blocks
    def start(self) -> Tree:
        blocks = [self.function_block()]
        while self.peek() != "$END":
            blocks.append(self.function_block())
        return _tree("start", blocks, blocks[0], blocks[-1])

    def function_block(self) -> Tree:
        first = self.take("FUNCTION_BLOCK")
        kids: list = [_token(first)]
        if self.peek() == "NAME":
            kids.append(_token(self.name()))
        items = {
            "VAR_INPUT": self.var_block,
            "VAR_OUTPUT": self.var_block,
            "FUZZIFY": self.fuzzify,
            "DEFUZZIFY": self.fuzzify,
            "RULEBLOCK": self.ruleblock,
        }
        while (read := items.get(self.peek())) is not None:
            kids.append(read())
        last = self.take("END_FUNCTION_BLOCK")
        kids.append(_token(last))
        return _tree("function_block", kids, first, last)

    def var_block(self) -> Tree:
        first = self.advance()
        kids: list = [_token(first)]
        while self.peek() == "NAME":
            name = self.name()
            self.take(":")
            vtype = self.name()
            semi = self.take(";")
            d = [_token(name), _token(vtype)]
            last = semi
            if self.peek() == "RANGE":
                last = self.range()
                d.append(last)
            kids.append(_tree("var_def", d, name, last))
        last = self.take("END_VAR")
        kids.append(_token(last))
        return _tree(first[0].lower(), kids, first, last)

    def range(self) -> Tree:
        first = self.take("RANGE")
        self.take(":=")
        self.take("(")
        lo = self.take("NUMBER")
        self.take("..")
        hi = self.take("NUMBER")
        self.take(")")
        last = self.take(";")
        return _tree("range", [_token(first), _token(lo), _token(hi)], first, last)

    def fuzzify(self) -> Tree:
        first = self.advance()
        out = first[0] == "DEFUZZIFY"
        kids: list = [_token(first), _token(self.name())]
        while True:
            kind = self.peek()
            if kind == "TERM":
                kids.append(self.term())
            elif kind == "RANGE":
                kids.append(self.range())
            elif out and kind in ("METHOD", "DEFAULT", "ACCU"):
                kids.append(self.setting(kind))
            else:
                break
        last = self.take("END_DEFUZZIFY" if out else "END_FUZZIFY")
        kids.append(_token(last))
        return _tree("defuzzify" if out else "fuzzify", kids, first, last)

    def setting(self, kind: str) -> Tree:
        first = self.take(kind)
        self.take(":=" if kind == "DEFAULT" else ":")
        value = self.cur
        if value[0] not in ("NAME", "NUMBER") or (value[0] == "NUMBER" and kind != "DEFAULT"):
            raise Decline
        self.advance()
        last = self.take(";")
        return _tree(kind.lower(), [_token(first), _token(value)], first, last)

    def term(self) -> Tree:
        first = self.take("TERM")
        name = self.name()
        self.take(":=")
        mf = self.mf()
        last = self.take(";")
        return _tree("term", [_token(first), _token(name), mf], first, last)

    def mf(self) -> Tree:
        kind = self.peek()
        if kind == "(":
            points = [self.point()]
            while self.peek() == "(":
                points.append(self.point())
            return _tree("mf_points", points, points[0], points[-1])
        if kind == "NUMBER":
            raw = self.take("NUMBER")
            return _tree("mf_singleton", [_token(raw)], raw, raw)
        first = self.name()
        kids: list = [_token(first)]
        last: object = first
        while True:
            kind = self.peek()
            if kind == "NUMBER":
                last = self.take("NUMBER")
                kids.append(_token(last))
            elif kind == "(":
                last = self.point()
                kids.append(last)
            else:
                return _tree("mf_named", kids, first, last)

    def point(self) -> Tree:
        first = self.take("(")
        x = self.take("NUMBER")
        self.take(",")
        y = self.take("NUMBER")
        last = self.take(")")
        return _tree("point", [_token(x), _token(y)], first, last)

    # ---------------------------------------------------------------------------------- rules
    def ruleblock(self) -> Tree:
        first = self.take("RULEBLOCK")
        kids: list = [_token(first), _token(self.name())]
        while True:
            kind = self.peek()
            if kind == "RULE":
                kids.append(self.rule())
            elif kind in ("AND", "OR", "ACT", "ACCU"):
                op = self.take(kind)
                self.take(":")
                value = self.name()
                last = self.take(";")
                kids.append(_tree("operator", [_token(op), _token(value)], op, last))
            elif kind == "PRAGMA":
                kids.append(_token(self.take("PRAGMA")))
            else:
                break
        last = self.take("END_RULEBLOCK")
        kids.append(_token(last))
        return _tree("ruleblock", kids, first, last)

    def rule(self) -> Tree:
        first = self.take("RULE")
        label = self.cur
        if label[0] not in ("NAME", "NUMBER"):
            raise Decline
        self.advance()
        self.take(":")
        kids: list = [_token(first), _token(label), _token(self.take("IF")), self.cond()]
        kids.append(_token(self.take("THEN")))
        kids.append(self.conclusion())
        while self.peek() == ",":
            self.advance()
            kids.append(self.conclusion())
        if self.peek() == "WITH":
            w = self.take("WITH")
            number = self.take("NUMBER")
            kids.append(_tree("weight", [_token(w), _token(number)], w, number))
        last = self.take(";")
        return _tree("rule", kids, first, last)

    def cond(self) -> Tree:
        # left to right, AND and OR of equal precedence: built as a loop, not a recursion
        left = self.atom()
        while (kind := self.peek()) in ("AND", "OR"):
            op = _token(self.take(kind))
            right = self.atom()
            left = _tree("c_and" if kind == "AND" else "c_or", [left, op, right], left, right)
        return left

    def atom(self) -> Tree:
        kind = self.peek()
        if kind == "NAME":
            var = self.name()
            kids: list = [_token(var), _token(self.take("IS"))]
            while (k := self.peek()) in ("NOT", "VERY", "SOMEWHAT"):
                kids.append(_token(self.take(k), "NOT" if k == "NOT" else "HEDGE"))
            term = self.name()
            kids.append(_token(term))
            return _tree("c_is", kids, var, term)
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise Decline
        if kind == "NOT":
            first = self.take("NOT")
            inner = self.atom()
            self.depth -= 1
            return _tree("c_not", [_token(first), inner], first, inner)
        if kind == "(":
            # a group: the condition inside, with its own positions (as lark's ?atom gives it)
            first = self.advance()
            inner = self.cond()
            last = self.take(")")
            self.depth -= 1
            return _contain(inner, first, last)
        raise Decline

    def conclusion(self) -> Tree:
        var = self.name()
        is_, term = self.take("IS"), self.name()
        return _tree("conclusion", [_token(var), _token(is_), _token(term)], var, term)
