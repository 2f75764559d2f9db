"""The text notation parsed into an :class:`~acordcs.notation.outline.Outline`: lark's LALR(1)
parser of ``acord.lark`` through lark's public API, as the rule language is parsed
(:mod:`acordcs.rules.lark_parser`), its analysed grammar cached privately (:mod:`acordcs.cachedir`).

The text is hostile input like XMI: its size, its number of words and its nesting are bounded
before and while it is read, and every error says file:line:col, what was found, what was
expected and, for a misspelt keyword, the keyword meant. Nothing in the text is executed.
"""

from __future__ import annotations

import json
import re
from functools import cache
from importlib import resources

from lark import Lark, Token, Tree, UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from acordcs.cachedir import lark_cache
from acordcs.diagnostics import suggestion
from acordcs.errors import UnreadableInputError
from acordcs.notation.fast_text import TooDeep, read_or_decline
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

MAX_BYTES = 16 * 1024 * 1024  # the 2,000-class benchmark model is under 1 MiB as text
MAX_WORDS = 2_000_000
MAX_DEPTH = 64  # packages and elements inside one another
_WORD = re.compile(rb"\S+")


class NotationError(UnreadableInputError):
    """The text is not in the notation, or over a limit, or not readable (``code`` X101): nothing
    of it can be read."""

    code = "M101"

    def __init__(
        self, message: str, *, code: str | None = None, truncated: bool = False, **where
    ) -> None:
        super().__init__(message, **where)
        if code is not None:
            self.code = code
        self.truncated = truncated  # lark found the end of the text where it wanted more


class NotationLimitError(NotationError):
    code = "M102"


def grammar() -> str:
    """The text of ``acord.lark``."""
    return resources.files("acordcs.notation").joinpath("acord.lark").read_text(encoding="utf-8")


@cache
def parser() -> Lark:
    text = grammar()
    return Lark(
        text,
        parser="lalr",
        lexer="contextual",
        propagate_positions=True,
        maybe_placeholders=True,
        # never cache=True: lark would unpickle a predictable file in the shared temp dir
        cache=lark_cache(text, "notation"),
    )


# ------------------------------------------------------------------------------------ the errors
_EXPECT_WORDS = {
    "KIND": "an element (" + ", ".join(KINDS) + ")",
    "RELATION": "a relation (" + ", ".join(RELATIONS) + ")",
    "NAME": "a name",
    "STRING": "a quoted string",
    "NUMBER": "a number",
    "LINE": "a line of the rule language",
    "DOC": "a /// comment",
    "DIRECTION": "in, out or inout",
    "LBRACE": "'{'",
    "RBRACE": "'}'",
    "LPAR": "'('",
    "RPAR": "')'",
    "COMMA": "','",
    "COLON": "':'",
    "EQUAL": "'='",
    "DOT": "'.'",
    "$END": "the end of the text",
}
_KEYWORDS = [
    "model",
    "package",
    "attribute",
    "operation",
    "variable",
    "rules",
    "id",
    *KINDS,
    *RELATIONS,
]


def _word(terminal: str) -> str:
    """What a terminal of the grammar is called in a message: a keyword (``_MODEL``) as written."""
    if terminal in _EXPECT_WORDS:
        return _EXPECT_WORDS[terminal]
    return repr(terminal.lstrip("_").lower())


def _expected(expected: set[str]) -> str:
    words = sorted({_word(e) for e in expected})
    if len(words) > 8:
        words = [*words[:8], "..."]
    return ", ".join(words) or "something else"


def _keywords(expected: set[str]) -> list[str]:
    """The keywords among the terminals ``expected`` (``_MODEL`` -> ``model``)."""
    return [e.lstrip("_").lower() for e in expected if e.lstrip("_").lower() in _KEYWORDS]


def _syntax_error(err: UnexpectedInput, text: str, path: str) -> NotationError:
    line, column = err.line, err.column
    if isinstance(err, UnexpectedToken):
        token = err.token
        if token.type == "$END":
            found = "the end of the text"
        else:
            found = repr(token.value if len(token.value) <= 40 else token.value[:40] + "...")
        # What the parser's state accepts (lark's interactive parser, public API): err.expected
        # may hold the terminals of the lexer's fallback state instead.
        interactive = getattr(err, "interactive_parser", None)
        expected = set(interactive.accepts()) if interactive is not None else set(err.expected)
        hint = ""
        if token.type == "NAME":
            keywords = _keywords(expected)
            keywords += [k for k in KINDS if "KIND" in expected]
            keywords += [r for r in RELATIONS if "RELATION" in expected]
            hint = suggestion(str(token.value), keywords)
        message = f"unexpected {found}{hint}; expected {_expected(expected)}"
    else:  # UnexpectedCharacters
        char = text[err.pos_in_stream] if 0 <= err.pos_in_stream < len(text) else "?"
        allowed = set(getattr(err, "allowed", None) or ())
        message = f"unexpected character {char!r}"
        if allowed:
            message += f"; expected {_expected(allowed)}"
        if char == '"':
            message += " (a string ends on its line: write a newline as \\n)"
    return NotationError(
        f"{message}; fix the text at this place (docs/notation.md gives the notation)",
        truncated=isinstance(err, UnexpectedToken) and err.token.type == "$END",
        file=path,
        line=line if isinstance(line, int) and line > 0 else None,
        column=column if isinstance(column, int) and column > 0 else None,
    )


# ------------------------------------------------------------------------------------ the reading
def parse_text(data: bytes, path: str = "<input>") -> Outline:
    """``data`` (UTF-8 text in the notation) as an outline; raises :class:`NotationError`. The
    fast reader (:mod:`acordcs.notation.fast_text`) reads it first; what it declines, lark reads
    (:func:`lark_outline`), and words the error when there is one."""
    if len(data) > MAX_BYTES:
        raise NotationLimitError(
            f"the text is {len(data) // 2**20} MiB, over the {MAX_BYTES // 2**20} MiB limit of the "
            "notation: split the model",
            file=path,
        )
    words = sum(1 for _ in _WORD.finditer(data))
    if words > MAX_WORDS:
        raise NotationLimitError(
            f"the text has {words} words, over the limit of {MAX_WORDS}: split the model", file=path
        )
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as err:
        line = data.count(b"\n", 0, err.start) + 1
        raise NotationError(
            f"the bytes are not UTF-8 (byte {data[err.start]:#04x}); save the text as UTF-8",
            file=path,
            line=line,
        ) from None
    if text.startswith("\ufeff"):
        text = text[1:]
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise NotationError("the text holds a NUL character: remove it", file=path, line=line)
    try:  # most texts: without lark, in a fraction of its time
        outline, relevant = read_or_decline(text, MAX_DEPTH)
    except TooDeep as deep:
        raise NotationLimitError(
            f"packages and elements are nested more than {MAX_DEPTH} deep: flatten the model",
            file=path,
            line=deep.place.line,
            column=deep.place.column,
        ) from None
    if outline is not None:
        return outline
    if relevant is not None and len(relevant) < len(text):
        # lark reads what matters to the error the reader stopped at, not the whole file
        try:
            lark_outline(relevant, path)
        except NotationError as err:
            if not err.truncated:
                raise
    return lark_outline(text, path)  # the reader declined what lark reads: lark's outline


def lark_outline(text: str, path: str = "<input>") -> Outline:
    """``text`` parsed by lark's parser of ``acord.lark`` into an outline; raises
    :class:`NotationError` with the place, what was found and what was expected."""
    try:
        tree = parser().parse(text)
    except (UnexpectedToken, UnexpectedCharacters) as err:
        raise _syntax_error(err, text, path) from None
    except UnexpectedInput as err:  # lark's other kinds of unexpected input
        raise NotationError(
            f"cannot read the text: {err}",
            file=path,
            line=getattr(err, "line", None),
            column=getattr(err, "column", None),
        ) from None
    return _Builder(path).outline(tree)


def _place(node: Tree | Token) -> Place:
    if isinstance(node, Token):
        return Place(node.line or 0, node.column or 0)
    meta = node.meta
    return Place(getattr(meta, "line", 0) or 0, getattr(meta, "column", 0) or 0)


def _string(token: Token, path: str) -> str:
    """A STRING token's value: JSON's escapes (``\\"``, ``\\\\``, ``\\n``, ``\\uXXXX``)."""
    try:
        return json.loads(token.value)
    except ValueError:
        raise NotationError(
            f"string {token.value[:40]!r} has an escape JSON does not know; write \\\\ for a "
            "backslash",
            file=path,
            line=token.line,
            column=token.column,
        ) from None


class _Builder:
    """The parse tree walked into an outline (depth bounded: the walk recurses)."""

    def __init__(self, path: str) -> None:
        self.path = path

    def value(self, node: Token) -> str:
        return _string(node, self.path) if node.type == "STRING" else str(node.value)

    def outline(self, tree: Tree) -> Outline:
        out = Outline()
        for child in tree.children:
            if child is None:
                continue
            if child.data == "model":
                out.doc, (name, ident) = self.docs(child.children)
                out.name, out.id, out.place = self.value(name), self.ident(ident), _place(child)
            else:
                out.items.append(self.item(child, 1))
        return out

    def ident(self, node: Tree | None) -> str | None:
        return None if node is None else _string(node.children[0], self.path)

    def docs(self, children: list) -> tuple[list[str], list]:
        docs = [c for c in children if isinstance(c, Token) and c.type == "DOC"]
        return [_doc_text(d) for d in docs], children[len(docs) :]

    def item(self, node: Tree, depth: int) -> Package | Element:
        if depth > MAX_DEPTH:
            raise NotationLimitError(
                f"packages and elements are nested more than {MAX_DEPTH} deep: flatten the model",
                file=self.path,
                line=_place(node).line,
                column=_place(node).column,
            )
        if node.data == "package":
            doc, rest = self.docs(node.children)
            name, ident, *items = rest
            return Package(
                self.value(name),
                [self.item(i, depth + 1) for i in items],
                doc,
                self.ident(ident),
                _place(node),
            )
        return self.element(node, depth)

    def element(self, node: Tree, depth: int) -> Element:
        doc, rest = self.docs(node.children)
        kind, name, ident, tags, body = rest
        element = Element(
            kind.value, self.value(name), self.tags(tags), doc=doc, id=self.ident(ident)
        )
        element.place = Place(kind.line, kind.column)
        for member in body.children if body is not None else ():
            what = member.data
            if what == "element":
                element.nested.append(self.item(member, depth + 1))  # type: ignore[arg-type]
            elif what == "attribute":
                element.attributes.append(self.attribute(member))
            elif what == "operation":
                element.operations.append(self.operation(member))
            elif what == "relation":
                keyword, *paths = member.children
                element.relations.append(
                    Relation(
                        keyword.value,
                        [(self.path_of(p), _place(p)) for p in paths],
                        _place(member),
                    )
                )
            elif what == "rules":
                suffix, *lines = member.children
                tag = RULE_TAG + (self.value(suffix) if suffix is not None else "")
                element.rules.append((tag, self.block(member, lines)))
        return element

    def path_of(self, node: Tree) -> tuple[str, ...]:
        return tuple(self.value(c) for c in node.children if isinstance(c, Token))

    def tags(self, node: Tree | None) -> list[Tag]:
        if node is None:
            return []
        out = []
        for tag in node.children:
            if tag is None:  # "()": maybe_placeholders gives the empty list as one None
                continue
            name, value = tag.children
            out.append(Tag(self.value(name), self.value(value), Place(name.line, name.column)))
        return out

    def block(self, node: Tree, lines: list[Token]) -> Block:
        return Block(
            [(str(t.value).rstrip(), Place(t.line, t.column)) for t in lines], _place(node)
        )

    def attribute(self, node: Tree) -> Attribute:
        doc, rest = self.docs(node.children)
        name, ident, type_, default, variable = rest
        attr = Attribute(
            self.value(name),
            self.value(type_) if type_ is not None else None,
            self.value(default) if default is not None else None,
            doc=doc,
            id=self.ident(ident),
            place=_place(name),
        )
        if variable is not None:
            v_ident, v_tags, terms = variable.children
            attr.variable = Variable(
                self.tags(v_tags),
                self.block(terms, list(terms.children)) if terms is not None else None,
                self.ident(v_ident),
                _place(variable),
            )
        return attr

    def operation(self, node: Tree) -> Operation:
        doc, rest = self.docs(node.children)
        name, ident, *params, returns = rest
        op = Operation(
            self.value(name),
            returns=self.value(returns) if returns is not None else None,
            doc=doc,
            id=self.ident(ident),
            place=_place(name),
        )
        for param in params:
            if param is None:
                continue
            direction, p_name, p_ident, p_type = param.children
            op.parameters.append(
                Parameter(
                    self.value(p_name),
                    self.value(p_type) if p_type is not None else None,
                    str(direction.value) if direction is not None else "in",
                    self.ident(p_ident),
                    _place(p_name),
                )
            )
        return op


def _doc_text(token: Token) -> str:
    """``/// text`` -> ``text`` (one space after the slashes is the comment's, not the text's)."""
    text = str(token.value)[3:].rstrip("\r")
    return text[1:] if text.startswith(" ") else text
