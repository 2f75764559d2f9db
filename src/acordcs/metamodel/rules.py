"""Parser and syntax tree of the ACORD-CS rule language (grammar: ``rules.lark``).

Two rule syntaxes share keywords and layout:

- fuzzy (the paper's): ``[label:] if V is [not|very|somewhat] T {and|or ...} then V is T {and V is T}
  [with W]``, with parentheses; AND and OR have equal precedence, left to right;
- crisp, for expert-system policy sets: comparisons with and/or/not, then actions that assign a
  variable or call an operation: ``if speed == 0 and retries < 3 then recovery.recover()``.

Variables are ``attribute`` or ``Element.attribute``. Linguistic terms of a variable are written FCL
style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``. One parser serves the validator and the
engines (lark analyses the grammar; :mod:`acordcs.metamodel.lalr` runs its tables); every error is a
:class:`RuleSyntaxError` with the column in the rule text.
"""

from __future__ import annotations

import os
import re
import zlib
from collections.abc import Callable, Iterable
from dataclasses import FrozenInstanceError, dataclass
from functools import cache
from operator import attrgetter
from reprlib import recursive_repr
from typing import Literal

from acordcs.errors import AcordError
from acordcs.metamodel.lalr import Node, Tables, Tok, Unexpected

RuleKind = Literal["fuzzy", "crisp"]
HEDGES = ("not", "very", "somewhat")
KEYWORDS = frozenset(
    "if then and or not is with true false very somewhat trape trian gauss gbell sigm".split()
)


class RuleSyntaxError(AcordError):
    """Rule text that does not parse; ``column`` is 1-based in the rule text."""


# ---------------------------------------------------------------------------------------- the tree
# The tree classes behave as ``@dataclass(frozen=True, slots=True)`` made them (fields, equality,
# hashing, repr, immutability, copying, ``dataclasses.fields``), but their methods are written
# once, here: generating them cost 10 ms per process (each such class is built twice and exec's
# six functions), a tenth of validating a large model. ``@dataclass`` is still applied, with
# nothing to generate, for ``dataclasses.fields``, ``replace`` and ``asdict``.
_set = object.__setattr__
_TREE: set[type] = set()


def _tree(cls: type) -> type:
    """Register a tree class: its dataclass fields (with the class's ``_defaults``; only the
    ``_compare`` fields, all by default, take part in equality) and ``_key``, their values."""
    cls = dataclass(init=False, repr=False, eq=False)(cls)
    fields = cls.__dataclass_fields__  # type: ignore[attr-defined]
    compared = cls.__dict__.get("_compare", cls.__match_args__)  # type: ignore[attr-defined]
    for name, default in cls.__dict__.get("_defaults", ()):
        fields[name].default = default
    for name, field in fields.items():
        field.compare = name in compared
    if len(compared) == 1:
        cls._key = staticmethod(lambda node, name=compared[0]: (getattr(node, name),))  # type: ignore[attr-defined]
    else:
        cls._key = staticmethod(attrgetter(*compared))  # type: ignore[attr-defined]
    _TREE.add(cls)
    return cls


class _Frozen:
    __slots__ = ()
    __match_args__: tuple[str, ...] = ()  # the fields in order, set by @dataclass
    _key: Callable[[object], tuple]  # the compared fields' values, set by _tree

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self._key(self) == self._key(other)
        return NotImplemented

    def __hash__(self) -> int:
        return hash(self._key(self))

    @recursive_repr()
    def __repr__(self) -> str:
        fields = ", ".join(f"{name}={getattr(self, name)!r}" for name in self.__match_args__)
        return f"{type(self).__qualname__}({fields})"

    def __setattr__(self, name: str, value: object) -> None:
        if type(self) in _TREE or name in self.__match_args__:
            raise FrozenInstanceError(f"cannot assign to field {name!r}")
        _set(self, name, value)

    def __delattr__(self, name: str) -> None:
        if type(self) in _TREE or name in self.__match_args__:
            raise FrozenInstanceError(f"cannot delete field {name!r}")
        object.__delattr__(self, name)

    def __getstate__(self) -> list:  # pickle and copy: slots, and __setattr__ refuses
        return [getattr(self, name) for name in self.__match_args__]

    def __setstate__(self, state: list) -> None:
        for name, value in zip(self.__match_args__, state, strict=False):
            _set(self, name, value)


@_tree
class Name(_Frozen):
    """A variable or operation reference as written, with its column in the rule text."""

    __slots__ = ("column", "text")
    text: str
    column: int

    def __init__(self, text: str, column: int) -> None:
        _set(self, "text", text)
        _set(self, "column", column)

    @property
    def element(self) -> str | None:
        """The qualifying element name (``A.b`` -> ``A``), or None when unqualified."""
        head, dot, _ = self.text.rpartition(".")
        return head if dot else None

    @property
    def member(self) -> str:
        """The attribute or operation name (``A.b`` -> ``b``)."""
        return self.text.rpartition(".")[2]


@_tree
class Is(_Frozen):
    """``var is [hedges] term``; hedges apply innermost last: ``not very high`` = 1 - high**2."""

    __slots__ = ("hedges", "term", "var")
    var: Name
    hedges: tuple[str, ...]
    term: Name

    def __init__(self, var: Name, hedges: tuple[str, ...], term: Name) -> None:
        _set(self, "var", var)
        _set(self, "hedges", hedges)
        _set(self, "term", term)


class _Unary(_Frozen):
    __slots__ = ()

    def __init__(self, operand: object) -> None:
        _set(self, "operand", operand)


@_tree
class Not(_Unary):
    """``not operand``."""

    __slots__ = ("operand",)
    operand: object


@_tree
class Neg(_Unary):
    """``- operand``."""

    __slots__ = ("operand",)
    operand: object


class _Binary(_Frozen):
    __slots__ = ()

    def __init__(self, op: str, left: object, right: object) -> None:
        _set(self, "op", op)
        _set(self, "left", left)
        _set(self, "right", right)


@_tree
class BoolOp(_Binary):
    """``and`` / ``or`` of two operands (left-associative chains nest on the left)."""

    __slots__ = ("left", "op", "right")
    op: Literal["and", "or"]
    left: object
    right: object


@_tree
class Compare(_Binary):
    """``left op right``, op one of ``== != < <= > >=``."""

    __slots__ = ("left", "op", "right")
    op: str
    left: object
    right: object


@_tree
class Arith(_Binary):
    """``left op right``, op one of ``+ - * /``."""

    __slots__ = ("left", "op", "right")
    op: str
    left: object
    right: object


@_tree
class Const(_Frozen):
    """A literal; ``column`` (where it is, for errors) takes no part in equality."""

    __slots__ = ("column", "value")
    value: int | float | str | bool
    column: int | None
    _defaults = (("column", None),)
    _compare = ("value",)

    def __init__(self, value: int | float | str | bool, column: int | None = None) -> None:
        _set(self, "value", value)
        _set(self, "column", column)


@_tree
class VarRef(_Frozen):
    """A variable read in a crisp expression."""

    __slots__ = ("var",)
    var: Name

    def __init__(self, var: Name) -> None:
        _set(self, "var", var)


@_tree
class Consequent(_Frozen):
    """``var is term`` after ``then`` (fuzzy)."""

    __slots__ = ("term", "var")
    var: Name
    term: Name

    def __init__(self, var: Name, term: Name) -> None:
        _set(self, "var", var)
        _set(self, "term", term)


@_tree
class Assign(_Frozen):
    """``var = value`` after ``then`` (crisp)."""

    __slots__ = ("value", "var")
    var: Name
    value: object

    def __init__(self, var: Name, value: object) -> None:
        _set(self, "var", var)
        _set(self, "value", value)


@_tree
class Call(_Frozen):
    """``Element.operation(args)`` after ``then`` (crisp)."""

    __slots__ = ("args", "target")
    target: Name
    args: tuple[object, ...]

    def __init__(self, target: Name, args: tuple[object, ...]) -> None:
        _set(self, "target", target)
        _set(self, "args", args)


@_tree
class Rule(_Frozen):
    """One parsed rule. ``actions`` are Consequents (fuzzy) or Assign/Call (crisp)."""

    __slots__ = ("actions", "condition", "kind", "label", "text", "weight")
    kind: RuleKind
    label: str | None
    condition: object
    actions: tuple[object, ...]
    weight: float
    text: str
    _defaults = (("weight", 1.0), ("text", ""))

    def __init__(
        self,
        kind: RuleKind,
        label: str | None,
        condition: object,
        actions: tuple[object, ...],
        weight: float = 1.0,
        text: str = "",
    ) -> None:
        _set(self, "kind", kind)
        _set(self, "label", label)
        _set(self, "condition", condition)
        _set(self, "actions", actions)
        _set(self, "weight", weight)
        _set(self, "text", text)

    def variables_read(self) -> list[Name]:
        """Variables the condition reads, in order of appearance (for fuzzy: inputs)."""
        return names_in(self.condition)

    def variables_written(self) -> list[Name]:
        """Variables the actions assign (for fuzzy: outputs)."""
        return [a.var for a in self.actions if isinstance(a, Consequent | Assign)]

    def calls(self) -> list[Call]:
        return [a for a in self.actions if isinstance(a, Call)]


@_tree
class TermDef(_Frozen):
    """A linguistic term: its name, shape and parameters (FCL order; points as x1 y1 x2 y2 ...)."""

    __slots__ = ("name", "parameters", "shape")
    name: Name
    shape: str
    parameters: tuple[float, ...]

    def __init__(self, name: Name, shape: str, parameters: tuple[float, ...]) -> None:
        _set(self, "name", name)
        _set(self, "shape", shape)
        _set(self, "parameters", parameters)


@dataclass(init=False, repr=False, eq=False)
class RuleLine:
    """One rule of a tag value: its text and where it sits in the tag (1-based line)."""

    __slots__ = ("label", "line", "text")
    text: str
    line: int
    label: str | None

    def __init__(self, text: str, line: int, label: str | None = None) -> None:
        self.text = text
        self.line = line
        self.label = label

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return _rule_line(self) == _rule_line(other)
        return NotImplemented

    __hash__ = None  # type: ignore[assignment]  # mutable: unhashable, as the dataclass was
    __repr__ = _Frozen.__repr__  # type: ignore[assignment]


_rule_line = attrgetter("text", "line", "label")
RuleLine.__dataclass_fields__["label"].default = None  # type: ignore[attr-defined]


def names_in(node: object) -> list[Name]:
    """Variables an expression or condition reads, in order of appearance."""
    out: list[Name] = []
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, Is | VarRef):
            out.append(n.var)
        elif isinstance(n, BoolOp | Compare | Arith):
            stack.extend((n.right, n.left))
        elif isinstance(n, Not | Neg):
            stack.append(n.operand)
    return out


# ------------------------------------------------------------------------------ building the tree
# One function per grammar rule (or alias), called with the rule's kept children; tokens are
# lalr.Tok (keyword tokens such as IF or IS arrive too and are skipped).
def _name(tok: Tok) -> Name:
    return Name(tok.text, tok.column)


def _number_text(tok: Tok) -> str:
    # int() refuses 4,300+ digits; no rule needs more than a double's range
    if len(tok.text) > 64:
        raise RuleSyntaxError(f"number {tok.text[:12]}... is too long", column=tok.column)
    return tok.text


def _num(tok: Tok) -> float:
    return float(_number_text(tok))


def _c_num(tok: Tok) -> Const:
    # Integer literals stay integers: `retries + 1` must not turn a count into 1.0.
    text = _number_text(tok)
    value = int(text) if text.lstrip("+-").isdigit() else float(text)
    return Const(value, tok.column)


def _f_is(var: Tok, _is: Tok, *rest: Tok) -> Is:
    *hedges, term = rest
    return Is(_name(var), tuple(h.text.lower() for h in hedges), _name(term))


def _mf(shape: str) -> Callable[..., tuple[str, tuple[float, ...]]]:
    return lambda _kw, *nums: (shape, tuple(map(_num, nums)))


_BUILDERS: dict[str, Callable] = {
    "label": lambda name, *_colon: ("label", name.text),
    "weight": lambda _with, number: ("weight", _num(number)),
    "f_is": _f_is,
    "f_and": lambda left, _kw, right: BoolOp("and", left, right),
    "f_or": lambda left, _kw, right: BoolOp("or", left, right),
    "f_not": lambda _kw, operand: Not(operand),
    "consequent": lambda var, _is, term: Consequent(_name(var), _name(term)),
    "c_or": lambda left, _kw, right: BoolOp("or", left, right),
    "c_and": lambda left, _kw, right: BoolOp("and", left, right),
    "c_not": lambda _kw, operand: Not(operand),
    "c_cmp": lambda left, op, right: Compare(op.text, left, right),
    "c_arith": lambda left, op, right: Arith(op.text, left, right),
    "c_neg": lambda operand: Neg(operand),
    "c_num": _c_num,
    "c_str": lambda tok: Const(tok.text[1:-1], tok.column),
    "c_true": lambda tok: Const(True, tok.column),
    "c_false": lambda tok: Const(False, tok.column),
    "c_var": lambda tok: VarRef(_name(tok)),
    "a_assign": lambda var, value: Assign(_name(var), value),
    "a_call": lambda target, *args: Call(_name(target), tuple(a for a in args if a is not None)),
    "term_def": lambda name, mf: TermDef(_name(name), *mf),
    "mf_trape": _mf("trapezoid"),
    "mf_trian": _mf("triangle"),
    "mf_gauss": _mf("gaussian"),
    "mf_gbell": _mf("bell"),
    "mf_sigm": _mf("sigmoid"),
    "mf_points": lambda *points: ("points", tuple(v for p in points for v in p)),
    "point": lambda x, y: (_num(x), _num(y)),
    "mf_singleton": lambda tok: ("singleton", (_num(tok),)),
}

_STARTS = ("start_fuzzy", "start_crisp", "start_terms")


@cache
def _grammar() -> str:
    with open(os.path.join(os.path.dirname(__file__), "rules.lark"), encoding="utf-8") as handle:
        return handle.read()


@cache
def _tables() -> Tables:
    return Tables.for_grammar(_grammar(), _STARTS, "rules")


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


def syntax_error(err: Unexpected, text: str) -> RuleSyntaxError:
    """The error a parse that stopped at ``err`` reports (column 1-based in ``text``)."""
    if err.expected is None:
        return RuleSyntaxError(
            f"unexpected character {text[err.column - 1]!r}", column=err.column or None
        )
    found = "end of rule" if err.found is None else repr(err.found)
    return RuleSyntaxError(
        f"unexpected {found}; expected {_describe_expected(err.expected)}",
        column=err.column or None,
    )


def _parse(start: str, text: str):
    if "\n" in text or "\r" in text:
        raise RuleSyntaxError(
            "a rule is one line; put each rule on its own line", column=text.find("\n") + 1
        )
    try:
        return _tables().parse(text, start, _BUILDERS)
    except Unexpected as err:
        raise syntax_error(err, text) from None


def _assemble(kind: RuleKind, tree: Node, text: str) -> Rule:
    label = None
    weight = 1.0
    condition = None
    actions = []
    for child in tree.children:
        if isinstance(child, tuple) and child[0] == "label":
            label = child[1]
        elif isinstance(child, tuple) and child[0] == "weight":
            weight = child[1]
        elif isinstance(child, Tok):
            continue
        elif condition is None:
            condition = child
        else:
            actions.append(child)
    return Rule(kind, label, condition, tuple(actions), weight, text)


_PARSED: dict[tuple[str, str], Rule] = {}  # trees are immutable: one per (text, kind) is shared
_PARSED_MAX = 20_000


def parse_rule(text: str, kind: RuleKind = "fuzzy") -> Rule:
    """Parse one rule of the given syntax. Raises RuleSyntaxError with the column."""
    rule = _PARSED.get((text, kind))
    if rule is None:
        rule = _parse_rule(text, kind)
        if len(_PARSED) >= _PARSED_MAX:
            _PARSED.clear()
        _PARSED[text, kind] = rule
    return rule


def _parse_rule(text: str, kind: str) -> Rule:
    if kind not in ("fuzzy", "crisp"):
        raise ValueError(f"rule kind must be 'fuzzy' or 'crisp', not {kind!r}")
    rule = None
    if kind == "fuzzy" and "\n" not in text and "\r" not in text:
        rule = _plain_fuzzy(text)
    if rule is None:
        rule = _assemble(kind, _parse(f"start_{kind}", text), text)
    if kind == "fuzzy" and not 0.0 <= rule.weight <= 1.0:
        col = text.lower().rfind("with") + 1
        raise RuleSyntaxError(f"weight {rule.weight:g} is outside 0..1", column=col or None)
    return rule


# ------------------------------------------------------------------- the common fuzzy rule, fast
# Most fuzzy rules have no parentheses: ``[label:] if V is [hedges] T {and|or V is [hedges] T}
# then V is T {and V is T} [with W]``. _plain_fuzzy reads those three times faster than the LALR
# driver (a large model has thousands of rules) and gives up (None) on anything else, errors
# included: the driver then reads the rule and says what is wrong. It splits the text into words,
# colons and numbers, then takes each word as the grammar's scanner for that place would (see
# rules.lark: keywords are case-insensitive and end at a word boundary; VAR and NAME refuse a
# word that starts with a keyword of _RESERVED; NAME has no dots). tests/test_rules_speedups.py
# holds it to the driver on generated rules; _GRAMMAR_CHECK turns it off if rules.lark changes.
_RESERVED = frozenset(("if", "then", "and", "or", "not", "is", "with"))
_HEDGE_WORDS = frozenset(("very", "somewhat", "not"))
_GRAMMAR_CHECK = 0x514A514A  # zlib.crc32 of the rules.lark this reader was written against
# Words, colons and numbers, ASCII only: any other character (a non-ASCII digit after "with"
# would end neither the word nor the keyword the same way) is caught by the last group, and the
# rule left to the driver. Every position matches (blanks are possessive, the end matches
# empty), so findall never skips text: linear time, even on a long run of blanks.
_WORDS = (
    r"([ \t]*+)(?:([A-Za-z_][A-Za-z0-9_]*(?:\.[A-Za-z_][A-Za-z0-9_]*)*)|(:)"
    r"|([+-]?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?)|\Z|((?s:.)))"
)


@cache
def _words() -> Callable[[str], list] | None:
    if zlib.crc32(_grammar().encode("utf-8")) != _GRAMMAR_CHECK:
        return None
    return re.compile(_WORDS).findall


def _plain_fuzzy(text: str) -> Rule | None:
    """``text`` as parse_rule(text, "fuzzy") reads it, if it is a plain rule; else None."""
    findall = _words()
    if findall is None:
        return None
    tokens = []  # (text, column, lower-case text if a word else None)
    pos = 0
    for blanks, word, colon, number, other in findall(text):
        if other:
            return None
        pos += len(blanks)
        token = word or colon or number
        if token:
            tokens.append((token, pos + 1, word.lower() if word else None))
            pos += len(token)
    count = len(tokens)
    if count < 8:  # if V is T then V is T
        return None
    label = None
    i = 0
    if tokens[1][0] == ":":  # NAME ':' (a keyword-like word is not a NAME)
        low = tokens[0][2]
        if low is None or "." in low or low in _RESERVED:
            return None
        label = tokens[0][0]
        i = 2
    if tokens[i][2] != "if":
        return None
    i += 1
    condition = op = None
    while True:  # VAR IS (HEDGE | NOT)* NAME, joined by AND and OR from the left
        if i + 3 >= count or tokens[i + 1][2] != "is":
            return None
        var, var_column, low = tokens[i]
        if low is None or low.partition(".")[0] in _RESERVED:
            return None
        i += 2
        hedges = []
        while tokens[i][2] in _HEDGE_WORDS:
            hedges.append(tokens[i][2])
            i += 1
            if i + 1 >= count:
                return None
        term, term_column, low = tokens[i]
        if low is None or "." in low or low in _RESERVED:
            return None
        atom = Is(Name(var, var_column), tuple(hedges), Name(term, term_column))
        condition = atom if op is None else BoolOp(op, condition, atom)
        op = tokens[i + 1][2]
        i += 2
        if op == "then":
            break
        if op != "and" and op != "or":
            return None
    actions = []
    weight = 1.0
    while True:  # VAR IS NAME, joined by AND, then maybe WITH NUMBER
        if i + 2 >= count or tokens[i + 1][2] != "is":
            return None
        var, var_column, low = tokens[i]
        if low is None or low.partition(".")[0] in _RESERVED:
            return None
        term, term_column, low = tokens[i + 2]
        if low is None or "." in low or low in _RESERVED:
            return None
        actions.append(Consequent(Name(var, var_column), Name(term, term_column)))
        i += 3
        if i == count:
            break
        if tokens[i][2] == "and":
            i += 1
            continue
        number, column, low = tokens[i + 1] if i + 2 == count else ("", 0, "")
        if tokens[i][2] != "with" or low is not None or number == ":":
            return None
        weight = _num(Tok("NUMBER", number, column))  # the driver's builder, and its error
        break
    return Rule("fuzzy", label, condition, tuple(actions), weight, text)


def parse_terms(text: str) -> list[TermDef]:
    """Parse a term list ``name := mf; ...``. Raises RuleSyntaxError with the column."""
    flat = " ".join(text.splitlines())
    return list(_parse("start_terms", flat).children)


def split_rules(tag_value: str) -> list[RuleLine]:
    """The rules of a Rule tag value: one per non-blank line; ``#`` or ``//`` starts a comment line."""
    out = []
    for number, raw in enumerate(tag_value.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(("#", "//")):
            continue
        out.append(RuleLine(line, number))
    return out
