"""A recursive-descent reader of well-formed text in the notation, without lark: the outline of
most files in a fraction of lark's time (docs/benchmarks.md), as the rule language's fast reader
(:mod:`acordcs.rules.fast`) does for rules.

It reads exactly what ``acord.lark`` accepts and builds the same outline, places included (a test
holds the two readers equal on every sample and on edited copies); whatever it does not expect it
declines (None), and lark's parser reads the text instead and words the error.
"""

from __future__ import annotations

import bisect
import json
import re

from acordcs.notation.outline import (
    KINDS,
    RELATIONS,
    RULE_TAG,
    Attribute,
    Block,
    Element,
    Operation,
    Outline,
    Package,
    Parameter,
    Place,
    Relation,
    Tag,
    Variable,
)

# The terminals of acord.lark, as it writes them.
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_WORD = re.compile(r"[A-Za-z_]\w*")  # a keyword is a whole word (\b ends it)
_NUMBER = re.compile(r"[+-]?(\d+(\.\d*)?|\.\d+)([eE][+-]?\d+)?")
_STRING = re.compile(r'"(?:[^"\\\n]|\\.)*"')
_LINE = re.compile(r"[^\s}#/][^\n]*")
_DOC = re.compile(r"///[^\n]*")
_SKIP = re.compile(r"(?:[ \t\f\r\n]+|//(?!/)[^\n]*|#[^\n]*|/\*(?:.|\n)*?\*/)+")
_DIRECTIONS = ("in", "out", "inout")


class _Declined(Exception):
    """Not what the fast reader reads: lark reads it."""


def read_outline(text: str, max_depth: int) -> Outline | None:
    """The outline of ``text``, or None when it is not simply well formed (lark reads it)."""
    try:
        return _Reader(text, max_depth).outline()
    except (_Declined, RecursionError):
        return None


class _Reader:
    def __init__(self, text: str, max_depth: int) -> None:
        self.text = text
        self.pos = 0
        self.max_depth = max_depth
        self.line_starts = [0]
        self.line_starts.extend(m.end() for m in re.finditer("\n", text))

    # ------------------------------------------------------------------------------ the tokens
    def place(self, pos: int) -> Place:
        line = bisect.bisect_right(self.line_starts, pos)
        return Place(line, pos - self.line_starts[line - 1] + 1)

    def skip(self) -> None:
        found = _SKIP.match(self.text, self.pos)
        if found:
            self.pos = found.end()

    def peek_word(self) -> str | None:
        self.skip()
        found = _WORD.match(self.text, self.pos)
        return found.group() if found else None

    def at(self, char: str) -> bool:
        self.skip()
        return self.text.startswith(char, self.pos)

    def expect(self, char: str) -> int:
        if not self.at(char):
            raise _Declined
        start = self.pos
        self.pos += len(char)
        return start

    def keyword(self, word: str) -> int:
        if self.peek_word() != word:
            raise _Declined
        start = self.pos
        self.pos += len(word)
        return start

    def docs(self) -> tuple[list[str], int | None]:
        out, first = [], None
        while True:
            self.skip()
            found = _DOC.match(self.text, self.pos)
            if not found:
                return out, first
            first = self.pos if first is None else first
            text = found.group()[3:].rstrip("\r")
            out.append(text[1:] if text.startswith(" ") else text)
            self.pos = found.end()

    def name(self) -> tuple[str, Place]:
        self.skip()
        start = self.pos
        if self.text.startswith('"', start):
            return self.string(), self.place(start)
        found = _NAME.match(self.text, start)
        if not found:
            raise _Declined
        self.pos = found.end()
        return found.group(), self.place(start)

    def string(self) -> str:
        found = _STRING.match(self.text, self.pos)
        if not found:
            raise _Declined
        self.pos = found.end()
        try:
            return json.loads(found.group())
        except ValueError:
            raise _Declined from None

    def value(self) -> str:
        self.skip()
        if self.text.startswith('"', self.pos):
            return self.string()
        for pattern in (_NAME, _NUMBER):
            found = pattern.match(self.text, self.pos)
            if found:
                self.pos = found.end()
                return found.group()
        raise _Declined

    def ident(self) -> str | None:
        if self.peek_word() != "id":
            return None
        self.pos += 2
        self.skip()
        if not self.text.startswith('"', self.pos):
            raise _Declined
        return self.string()

    # ------------------------------------------------------------------------------ the grammar
    def outline(self) -> Outline:
        out = Outline()
        docs, first = self.docs()
        if self.peek_word() == "model":
            start = self.keyword("model")
            out.doc = docs
            out.place = self.place(first if first is not None else start)
            out.name = self.name()[0]
            out.id = self.ident()
            docs, first = self.docs()
        while True:
            self.skip()
            if self.pos == len(self.text):
                if docs:
                    raise _Declined
                return out
            out.items.append(self.item(docs, first, 1))
            docs, first = self.docs()

    def item(self, docs: list[str], first: int | None, depth: int) -> Package | Element:
        if depth > self.max_depth:
            raise _Declined
        word = self.peek_word()
        if word == "package":
            start = self.keyword("package")
            name = self.name()[0]
            pkg = Package(name, doc=docs, id=self.ident())
            pkg.place = self.place(first if first is not None else start)
            self.expect("{")
            while True:
                docs, first = self.docs()
                if not docs and self.at("}"):
                    self.pos += 1
                    return pkg
                pkg.items.append(self.item(docs, first, depth + 1))
        if word in KINDS:
            return self.element(docs, depth)
        raise _Declined

    def element(self, docs: list[str], depth: int) -> Element:
        word = self.peek_word()
        start = self.pos
        self.pos += len(word)
        name = self.name()[0]
        element = Element(word, name, doc=docs, id=self.ident())
        element.place = self.place(start)
        if self.at("("):
            element.tags = self.tags()
        if not self.at("{"):
            return element
        self.pos += 1
        while True:
            docs, _ = self.docs()
            if not docs and self.at("}"):
                self.pos += 1
                return element
            word = self.peek_word()
            if word in KINDS:
                if depth + 1 > self.max_depth:
                    raise _Declined
                element.nested.append(self.element(docs, depth + 1))
            elif word == "attribute":
                element.attributes.append(self.attribute(docs))
            elif word == "operation":
                element.operations.append(self.operation(docs))
            elif docs:
                raise _Declined  # a /// comment before what has none
            elif word in RELATIONS:
                element.relations.append(self.relation())
            elif word == "rules":
                element.rules.append(self.rules())
            else:
                raise _Declined

    def tags(self) -> list[Tag]:
        self.expect("(")
        out: list[Tag] = []
        if self.at(")"):
            self.pos += 1
            return out
        while True:
            name, place = self.name()
            self.expect("=")
            out.append(Tag(name, self.value(), place))
            if self.at(","):
                self.pos += 1
                continue
            self.expect(")")
            return out

    def block(self, at: int | None = None) -> Block:
        """A rules or terms block; its place is ``at`` (a rules block's keyword), else its '{'."""
        start = self.expect("{")
        block = Block(place=self.place(start if at is None else at))
        while True:
            self.skip()
            if self.text.startswith("}", self.pos):
                self.pos += 1
                return block
            found = _LINE.match(self.text, self.pos)
            if not found:
                raise _Declined
            block.lines.append((found.group().rstrip(), self.place(self.pos)))
            self.pos = found.end()

    def rules(self) -> tuple[str, Block]:
        at = self.keyword("rules")
        suffix = ""
        if not self.at("{"):
            self.skip()
            found = _NAME.match(self.text, self.pos)
            if not found:
                raise _Declined
            suffix, self.pos = found.group(), found.end()
        return RULE_TAG + suffix, self.block(at)

    def attribute(self, docs: list[str]) -> Attribute:
        self.keyword("attribute")
        name, place = self.name()
        attr = Attribute(name, doc=docs, id=self.ident(), place=place)
        if self.at(":"):
            self.pos += 1
            attr.type = self.name()[0]
        if self.at("="):
            self.pos += 1
            attr.default = self.value()
        if self.peek_word() == "variable":
            start = self.keyword("variable")
            var = Variable(id=self.ident(), place=self.place(start))
            if self.at("("):
                var.tags = self.tags()
            if self.at("{"):
                var.terms = self.block()
            attr.variable = var
        return attr

    def operation(self, docs: list[str]) -> Operation:
        self.keyword("operation")
        name, place = self.name()
        op = Operation(name, doc=docs, id=self.ident(), place=place)
        self.expect("(")
        if not self.at(")"):
            while True:
                op.parameters.append(self.parameter())
                if not self.at(","):
                    break
                self.pos += 1
        self.expect(")")
        if self.at(":"):
            self.pos += 1
            op.returns = self.name()[0]
        return op

    def parameter(self) -> Parameter:
        direction = "in"
        word = self.peek_word()
        if word in _DIRECTIONS:
            direction = word
            self.pos += len(word)
        name, place = self.name()
        param = Parameter(name, None, direction, self.ident(), place)
        if self.at(":"):
            self.pos += 1
            param.type = self.name()[0]
        return param

    def relation(self) -> Relation:
        word = self.peek_word()
        relation = Relation(word, place=self.place(self.pos))
        self.pos += len(word)
        while True:
            self.skip()
            start = self.pos
            path = [self.name()[0]]
            while True:
                if self.at("::"):
                    self.pos += 2
                elif self.at("."):
                    self.pos += 1
                else:
                    break
                path.append(self.name()[0])
            relation.targets.append((tuple(path), self.place(start)))
            if not self.at(","):
                return relation
            self.pos += 1
