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


class TooDeep(Exception):
    """Packages and elements nested deeper than the limit, at ``place``."""

    def __init__(self, place: Place) -> None:
        super().__init__(place)
        self.place = place


def read_outline(text: str, max_depth: int) -> Outline | None:
    """The outline of ``text``, or None when it is not simply well formed (lark reads it)."""
    return read_or_decline(text, max_depth)[0]


def read_or_decline(text: str, max_depth: int) -> tuple[Outline | None, str | None]:
    """The outline of ``text`` and None; or, where the reader declined, None and the text lark
    needs to find the error: the text up to the end of the line where it stopped, in which
    everything the reader had finished is blanked (newlines kept, so that lines and columns stay)
    but the heads of the packages, elements and blocks it was inside and the member it was
    reading. Items, members and block lines are sequences, so what is left is what lark would
    have read up to there, and lark's time is bounded by it, not by the file. Raises
    :class:`TooDeep`."""
    reader = _Reader(text, max_depth)
    try:
        return reader.outline(), None
    except (_Declined, RecursionError):
        return None, reader.relevant()


class _Reader:
    def __init__(self, text: str, max_depth: int) -> None:
        self.text = text
        self.pos = 0
        self.max_depth = max_depth
        self.heads: list[tuple[int, int]] = []  # (start, end) of each open package, element, block
        self.member = 0  # where the member being read in the innermost one starts
        # where the member before it starts, when it ended open (no closing '}'), so that it may
        # still go on (an element's body, an operation's return type): lark's view of what may
        # come next includes it
        self.previous: int | None = None
        self.line_starts = [0]
        self.line_starts.extend(m.end() for m in re.finditer("\n", text))

    def relevant(self) -> str:
        """The text lark needs after a decline at ``self.pos`` (see :func:`read_or_decline`)."""
        end = self.text.find("\n", self.pos)
        end = len(self.text) if end < 0 else end
        last = self.previous if self.previous is not None else self.member
        kept = [*self.heads, (last, end)]
        out, done = [], 0
        for start, stop in kept:
            start = max(start, done)
            out.append(_blank(self.text[done:start]))
            out.append(self.text[start:stop])
            done = max(done, stop)
        return "".join(out)

    def enter(self, start: int) -> None:
        """A package's, element's or block's head, from ``start`` to its '{' (just read)."""
        self.heads.append((start, self.pos))
        self.member, self.previous = self.pos, None

    def leave(self) -> None:
        self.heads.pop()

    def next_member(self) -> None:
        """After a member: the next one starts here."""
        closed = self.pos > 0 and self.text[self.pos - 1] == "}"
        self.previous = None if closed else self.member
        self.skip()
        self.member = self.pos

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
        self.skip()
        self.member = self.pos
        docs, first = self.docs()
        if self.peek_word() == "model":
            start = self.keyword("model")
            out.doc = docs
            out.place = self.place(first if first is not None else start)
            out.name = self.name()[0]
            out.id = self.ident()
            self.next_member()
            docs, first = self.docs()
        while True:
            self.skip()
            if self.pos == len(self.text):
                if docs:
                    raise _Declined
                return out
            out.items.append(self.item(docs, first, 1))
            self.next_member()
            docs, first = self.docs()

    def item(self, docs: list[str], first: int | None, depth: int) -> Package | Element:
        word = self.peek_word()
        if depth > self.max_depth and (word == "package" or word in KINDS):
            raise TooDeep(self.place(self.pos))
        if word == "package":
            start = self.keyword("package")
            name = self.name()[0]
            pkg = Package(name, doc=docs, id=self.ident())
            pkg.place = self.place(first if first is not None else start)
            self.expect("{")
            self.enter(start)
            while True:
                docs, first = self.docs()
                if not docs and self.at("}"):
                    self.pos += 1
                    self.leave()
                    return pkg
                pkg.items.append(self.item(docs, first, depth + 1))
                self.next_member()
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
        self.enter(start)
        while True:
            docs, _ = self.docs()
            if not docs and self.at("}"):
                self.pos += 1
                self.leave()
                return element
            word = self.peek_word()
            if word in KINDS:
                if depth + 1 > self.max_depth:
                    raise TooDeep(self.place(self.pos))
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
            self.next_member()

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

    def block(self, head: int, at: int | None = None) -> Block:
        """A rules or terms block (its head, the member it is in, from ``head``); its place is
        ``at`` (a rules block's keyword), else its '{'."""
        start = self.expect("{")
        block = Block(place=self.place(start if at is None else at))
        self.enter(head)
        while True:
            self.skip()
            self.member = self.pos
            if self.text.startswith("}", self.pos):
                self.pos += 1
                self.leave()
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
        return RULE_TAG + suffix, self.block(at, at)

    def attribute(self, docs: list[str]) -> Attribute:
        head = self.keyword("attribute")
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
                var.terms = self.block(head)
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
                if self.at(":"):  # '::', which may be written ': :'
                    self.pos += 1
                    self.expect(":")
                elif self.at("."):
                    self.pos += 1
                else:
                    break
                path.append(self.name()[0])
            relation.targets.append((tuple(path), self.place(start)))
            if not self.at(","):
                return relation
            self.pos += 1


def _blank(text: str) -> str:
    """``text`` as spaces, its newlines kept."""
    return "\n".join(" " * len(line) for line in text.split("\n"))
