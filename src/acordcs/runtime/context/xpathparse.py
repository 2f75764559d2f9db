"""XPath 1.0 expressions read into a tree, for the cost check of untrusted subscriptions.

lxml compiles expressions but does not show their structure, and the cost of an expression depends
on it: which axis a step walks, whether it sits inside a predicate, what a function is given. This
is a recursive-descent reader of the XPath 1.0 grammar (W3C XPath 1.0, section 3), with the lexical
disambiguation rules of its section 3.7 (``*`` and ``and``/``or``/``div``/``mod`` are operators
after an operand; a name followed by ``(`` is a function or node type, by ``::`` an axis).
Abbreviations are expanded as the specification defines them: ``//`` is
``/descendant-or-self::node()/``, ``.`` is ``self::node()``, ``..`` is ``parent::node()``, ``@`` is
``attribute::``.

Every node keeps the 0-based offset where it starts, so a refusal can name its column. Expressions
reach this module already compiled by lxml; anything it cannot read is refused by the caller.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field


class XPathSyntax(ValueError):
    """The expression is not XPath 1.0 as this reader knows it; ``position`` is 0-based."""

    def __init__(self, message: str, position: int) -> None:
        super().__init__(message)
        self.position = position


@dataclass
class Literal:
    pos: int
    value: str


@dataclass
class Number:
    pos: int
    text: str


@dataclass
class Variable:
    pos: int
    name: str


@dataclass
class Call:
    pos: int
    name: str
    args: list[Expr]


@dataclass
class Step:
    pos: int
    axis: str
    test: str  # a name test (``*``, ``p:*``, ``name``) or a node type with "()": ``node()``
    predicates: list[Expr] = field(default_factory=list)

    @property
    def named(self) -> bool:
        """Whether the test names one name (not ``*``, ``p:*`` or a node type)."""
        return not self.test.endswith(("*", "()"))


@dataclass
class Path:
    """``start`` (a filter expression) or the root (``absolute``) or the context node, then steps."""

    pos: int
    absolute: bool
    steps: list[Step]
    start: Expr | None = None


@dataclass
class Filter:
    pos: int
    primary: Expr
    predicates: list[Expr]


@dataclass
class Binary:
    pos: int
    op: str
    left: Expr
    right: Expr


@dataclass
class Negate:
    pos: int
    operand: Expr


Expr = Literal | Number | Variable | Call | Path | Filter | Binary | Negate

AXES = frozenset(
    (
        "ancestor",
        "ancestor-or-self",
        "attribute",
        "child",
        "descendant",
        "descendant-or-self",
        "following",
        "following-sibling",
        "namespace",
        "parent",
        "preceding",
        "preceding-sibling",
        "self",
    )
)
NODE_TYPES = frozenset(("comment", "text", "processing-instruction", "node"))
OPERATOR_NAMES = frozenset(("and", "or", "mod", "div"))

_NCNAME = r"[A-Za-z_\u00c0-\uffff][\w.\-\u00b7\u00c0-\uffff]*"
_TOKEN = re.compile(
    rf"""(?P<literal>"[^"]*"|'[^']*')
    | (?P<number>[0-9]+(?:\.[0-9]*)?|\.[0-9]+)
    | (?P<op>//|::|\.\.|!=|<=|>=|[/()\[\].@,|+\-=<>*$])
    | (?P<name>{_NCNAME}(?::(?:{_NCNAME}|\*))?)
    """,
    re.VERBOSE,
)
# after these tokens an operand starts: '*' is a name test and a name is not an operator
_OPERAND_FOLLOWS = frozenset(
    ("@", "::", "(", "[", ",", "and", "or", "mod", "div", "*op", "/", "//", "|", "+", "-")
) | {"=", "!=", "<", "<=", ">", ">="}


_PRECEDENCE = {"or": 1, "and": 2, "=": 3, "!=": 3, "<": 4, "<=": 4, ">": 4, ">=": 4, "+": 5, "-": 5}
_PRECEDENCE |= {"*op": 6, "div": 6, "mod": 6}


@dataclass
class _Token:
    kind: str  # literal, number, name, operator (an OperatorName or '*' as multiply), or the text
    text: str
    pos: int


def _tokens(text: str) -> list[_Token]:
    found: list[_Token] = []
    pos = 0
    while True:
        while pos < len(text) and text[pos] in " \t\r\n":
            pos += 1
        if pos == len(text):
            break
        match = _TOKEN.match(text, pos)
        if match is None:
            raise XPathSyntax(f"unexpected character {text[pos]!r}", pos)
        kind = match.lastgroup or ""
        word = match.group(kind)
        after_operand = bool(found) and found[-1].kind not in _OPERAND_FOLLOWS
        if kind == "op" and word == "*" and after_operand:
            found.append(_Token("*op", "*", pos))
        elif kind == "op" or (kind == "name" and after_operand and word in OPERATOR_NAMES):
            found.append(_Token(word, word, pos))
        else:
            found.append(_Token(kind, word, pos))
        pos = match.end()
    found += [_Token("end", "", len(text))] * 3  # peeking two ahead never runs off the end
    return found


class _Parser:
    def __init__(self, text: str) -> None:
        self.tokens = _tokens(text)
        self.at = 0

    # -- tokens -----------------------------------------------------------------------------------
    def peek(self, ahead: int = 0) -> _Token:
        return self.tokens[self.at + ahead]

    def take(self, *kinds: str) -> _Token:
        token = self.peek()
        if kinds and token.kind not in kinds:
            wanted = " or ".join(repr(k) for k in kinds)
            raise XPathSyntax(f"expected {wanted}, found {token.text or 'the end'!r}", token.pos)
        self.at += 1
        return token

    def accept(self, kind: str) -> _Token | None:
        return self.take() if self.peek().kind == kind else None

    # -- expressions (lowest precedence first) ----------------------------------------------------
    def expression(self) -> Expr:
        return self.binary(1)

    def binary(self, lowest: int) -> Expr:
        """Operators of precedence ``lowest`` or higher, left-associative (precedence climbing)."""
        left = self.unary()
        while True:
            token = self.tokens[self.at]
            level = _PRECEDENCE.get(token.kind, 0)
            if level < lowest:
                return left
            self.at += 1
            right = self.binary(level + 1)
            left = Binary(token.pos, "*" if token.kind == "*op" else token.kind, left, right)

    def unary(self) -> Expr:
        if self.peek().kind == "-":
            token = self.take()
            return Negate(token.pos, self.unary())
        return self.union()

    def union(self) -> Expr:
        left = self.path()
        while self.peek().kind == "|":
            token = self.take()
            left = Binary(token.pos, "|", left, self.path())
        return left

    def path(self) -> Expr:
        token = self.peek()
        if token.kind in ("/", "//"):
            return self.location(absolute=True)
        if self.starts_primary():
            primary = self.primary()
            predicates = self.predicates()
            start: Expr = Filter(token.pos, primary, predicates) if predicates else primary
            if self.peek().kind not in ("/", "//"):
                return start
            return Path(token.pos, False, self.relative(), start)
        return self.location(absolute=False)

    def starts_primary(self) -> bool:
        token = self.peek()
        if token.kind in ("$", "(", "literal", "number"):
            return True
        return token.kind == "name" and self.peek(1).kind == "(" and token.text not in NODE_TYPES

    def primary(self) -> Expr:
        token = self.take()
        if token.kind == "$":
            name = self.take("name")
            return Variable(token.pos, name.text)
        if token.kind == "(":
            inner = self.expression()
            self.take(")")
            return inner
        if token.kind == "literal":
            return Literal(token.pos, token.text[1:-1])
        if token.kind == "number":
            return Number(token.pos, token.text)
        self.take("(")
        args: list[Expr] = []
        if self.peek().kind != ")":
            args.append(self.expression())
            while self.accept(","):
                args.append(self.expression())
        self.take(")")
        return Call(token.pos, token.text, args)

    def location(self, absolute: bool) -> Path:
        token = self.peek()
        if not absolute:
            return Path(token.pos, False, self.relative())
        self.take()
        steps: list[Step] = []
        if token.kind == "//":
            steps.append(Step(token.pos, "descendant-or-self", "node()"))
        elif not self.starts_step():  # "/" alone: the root
            return Path(token.pos, True, steps)
        return Path(token.pos, True, steps + self.relative())

    def starts_step(self) -> bool:
        return self.peek().kind in ("name", "*", ".", "..", "@")

    def relative(self) -> list[Step]:
        # called at the start of a relative path, or after the '/' or '//' that continues a
        # filter expression (not consumed yet in that case)
        steps: list[Step] = []
        if self.peek().kind in ("/", "//"):
            token = self.take()
            if token.kind == "//":
                steps.append(Step(token.pos, "descendant-or-self", "node()"))
        steps.append(self.step())
        while self.peek().kind in ("/", "//"):
            token = self.take()
            if token.kind == "//":
                steps.append(Step(token.pos, "descendant-or-self", "node()"))
            steps.append(self.step())
        return steps

    def step(self) -> Step:
        token = self.peek()
        if token.kind == ".":
            self.take()
            return Step(token.pos, "self", "node()")
        if token.kind == "..":
            self.take()
            return Step(token.pos, "parent", "node()")
        axis = "child"
        if token.kind == "@":
            self.take()
            axis = "attribute"
        elif token.kind == "name" and self.peek(1).kind == "::":
            if token.text not in AXES:
                raise XPathSyntax(f"unknown axis {token.text!r}", token.pos)
            axis = self.take().text
            self.take("::")
        test_token = self.peek()
        if test_token.kind == "*":
            self.take()
            test = "*"
        else:
            test = self.take("name").text
            if test in NODE_TYPES and self.peek().kind == "(":
                self.take("(")
                if test == "processing-instruction" and self.peek().kind == "literal":
                    self.take()
                self.take(")")
                test += "()"
        return Step(token.pos, axis, test, self.predicates())

    def predicates(self) -> list[Expr]:
        found: list[Expr] = []
        while self.accept("["):
            found.append(self.expression())
            self.take("]")
        return found


def parse(text: str) -> Expr:
    """The tree of ``text``, or :class:`XPathSyntax` naming the position it could not read."""
    parser = _Parser(text)
    tree = parser.expression()
    end = parser.peek()
    if end.kind != "end":
        raise XPathSyntax(f"unexpected {end.text!r}", end.pos)
    return tree
