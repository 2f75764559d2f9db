"""Parser and syntax tree of the ACORD-CS rule language (grammar: ``rules.lark``).

Two rule syntaxes share keywords and layout:

- fuzzy (the paper's): ``[label:] if V is [not|very|somewhat] T {and|or ...} then V is T {and V is T}
  [with W]``, with parentheses; AND and OR have equal precedence, left to right;
- crisp, for expert-system policy sets: comparisons with and/or/not, then actions that assign a
  variable or call an operation: ``if speed == 0 and retries < 3 then recovery.recover()``.

Variables are ``attribute`` or ``Element.attribute``. Linguistic terms of a variable are written FCL
style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``. One parser serves the validator and the
engines; every error is a :class:`RuleSyntaxError` with the column in the rule text.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from functools import cache
from typing import Literal

from lark import Lark, Token, Transformer, v_args
from lark.exceptions import LarkError, UnexpectedCharacters, UnexpectedInput, UnexpectedToken

from acordcs.cachedir import lark_cache
from acordcs.errors import AcordError

RuleKind = Literal["fuzzy", "crisp"]
HEDGES = ("not", "very", "somewhat")
KEYWORDS = frozenset(
    [
        "if",
        "then",
        "and",
        "or",
        "not",
        "is",
        "with",
        "true",
        "false",
        "very",
        "somewhat",
        "trape",
        "trian",
        "gauss",
        "gbell",
        "sigm",
    ]
)


class RuleSyntaxError(AcordError):
    """Rule text that does not parse; ``column`` is 1-based in the rule text."""


# ---------------------------------------------------------------------------------------- the tree
@dataclass(frozen=True, slots=True)
class Name:
    """A variable or operation reference as written, with its column in the rule text."""

    text: str
    column: int

    @property
    def element(self) -> str | None:
        """The qualifying element name (``A.b`` -> ``A``), or None when unqualified."""
        head, dot, _ = self.text.rpartition(".")
        return head if dot else None

    @property
    def member(self) -> str:
        """The attribute or operation name (``A.b`` -> ``b``)."""
        return self.text.rpartition(".")[2]


@dataclass(frozen=True, slots=True)
class Is:
    """``var is [hedges] term``; hedges apply innermost last: ``not very high`` = 1 - high**2."""

    var: Name
    hedges: tuple[str, ...]
    term: Name


@dataclass(frozen=True, slots=True)
class Not:
    operand: object


@dataclass(frozen=True, slots=True)
class BoolOp:
    """``and`` / ``or`` of two operands (left-associative chains nest on the left)."""

    op: Literal["and", "or"]
    left: object
    right: object


@dataclass(frozen=True, slots=True)
class Compare:
    op: str
    left: object
    right: object


@dataclass(frozen=True, slots=True)
class Arith:
    op: str
    left: object
    right: object


@dataclass(frozen=True, slots=True)
class Neg:
    operand: object


@dataclass(frozen=True, slots=True)
class Const:
    value: int | float | str | bool
    column: int | None = field(default=None, compare=False)  # where the literal is, for errors


@dataclass(frozen=True, slots=True)
class VarRef:
    var: Name


@dataclass(frozen=True, slots=True)
class Consequent:
    var: Name
    term: Name


@dataclass(frozen=True, slots=True)
class Assign:
    var: Name
    value: object


@dataclass(frozen=True, slots=True)
class Call:
    target: Name
    args: tuple[object, ...]


@dataclass(frozen=True, slots=True)
class Rule:
    """One parsed rule. ``actions`` are Consequents (fuzzy) or Assign/Call (crisp)."""

    kind: RuleKind
    label: str | None
    condition: object
    actions: tuple[object, ...]
    weight: float = 1.0
    text: str = ""

    def variables_read(self) -> list[Name]:
        """Variables the condition reads, in order of appearance (for fuzzy: inputs)."""
        return names_in(self.condition)

    def variables_written(self) -> list[Name]:
        """Variables the actions assign (for fuzzy: outputs)."""
        return [a.var for a in self.actions if isinstance(a, Consequent | Assign)]

    def calls(self) -> list[Call]:
        return [a for a in self.actions if isinstance(a, Call)]


@dataclass(frozen=True, slots=True)
class TermDef:
    """A linguistic term: its name, shape and parameters (FCL order; points as x1 y1 x2 y2 ...)."""

    name: Name
    shape: str
    parameters: tuple[float, ...]


@dataclass(slots=True)
class RuleLine:
    """One rule of a tag value: its text and where it sits in the tag (1-based line)."""

    text: str
    line: int
    label: str | None = field(default=None)


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
def _name(tok: Token) -> Name:
    return Name(str(tok), tok.column or 0)


def _num(tok: Token) -> float:
    if len(tok) > 64:
        raise RuleSyntaxError(f"number {str(tok)[:12]}... is too long", column=tok.column)
    return float(tok)


@v_args(inline=True)
class _ToTree(Transformer):
    def label(self, name):
        return ("label", str(name))

    def weight(self, _with, number):
        return ("weight", _num(number))

    def f_is(self, var, _is, *rest):
        *hedges, term = rest
        return Is(_name(var), tuple(str(h).lower() for h in hedges), _name(term))

    def f_and(self, left, _kw, right):
        return BoolOp("and", left, right)

    def f_or(self, left, _kw, right):
        return BoolOp("or", left, right)

    def f_not(self, _kw, operand):
        return Not(operand)

    def consequent(self, var, _is, term):
        return Consequent(_name(var), _name(term))

    def c_or(self, left, _kw, right):
        return BoolOp("or", left, right)

    def c_and(self, left, _kw, right):
        return BoolOp("and", left, right)

    def c_not(self, _kw, operand):
        return Not(operand)

    def c_cmp(self, left, op, right):
        return Compare(str(op), left, right)

    def c_arith(self, left, op, right):
        return Arith(str(op), left, right)

    def c_neg(self, operand):
        return Neg(operand)

    def c_num(self, tok):
        # Integer literals stay integers: `retries + 1` must not turn a count into 1.0.
        text = str(tok)
        if len(text) > 64:  # int() refuses 4,300+ digits; no rule needs more than a double's range
            raise RuleSyntaxError(f"number {text[:12]}... is too long", column=tok.column)
        value = int(text) if text.lstrip("+-").isdigit() else float(text)
        return Const(value, tok.column)

    def c_str(self, tok):
        return Const(str(tok)[1:-1], tok.column)

    def c_true(self, tok):
        return Const(True, tok.column)

    def c_false(self, tok):
        return Const(False, tok.column)

    def c_var(self, tok):
        return VarRef(_name(tok))

    def a_assign(self, var, value):
        return Assign(_name(var), value)

    def a_call(self, target, *args):
        return Call(_name(target), tuple(a for a in args if a is not None))

    def term_def(self, name, mf):
        shape, params = mf
        return TermDef(_name(name), shape, params)

    def mf_trape(self, _kw, *nums):
        return ("trapezoid", tuple(map(_num, nums)))

    def mf_trian(self, _kw, *nums):
        return ("triangle", tuple(map(_num, nums)))

    def mf_gauss(self, _kw, *nums):
        return ("gaussian", tuple(map(_num, nums)))

    def mf_gbell(self, _kw, *nums):
        return ("bell", tuple(map(_num, nums)))

    def mf_sigm(self, _kw, *nums):
        return ("sigmoid", tuple(map(_num, nums)))

    def mf_points(self, *points):
        return ("points", tuple(v for p in points for v in p))

    def point(self, x, y):
        return (_num(x), _num(y))

    def mf_singleton(self, tok):
        return ("singleton", (_num(tok),))


@cache
def _parser(start: str) -> Lark:
    with open(os.path.join(os.path.dirname(__file__), "rules.lark"), encoding="utf-8") as handle:
        grammar = handle.read()
    # A cached analysis halves start-up of `acordcs-gen`; it lives in a private directory only,
    # never lark's cache=True (a predictable pickle in the shared temp dir: see acordcs.cachedir).
    return Lark(
        grammar,
        start=start,
        parser="lalr",
        transformer=_ToTree(),
        maybe_placeholders=True,
        cache=lark_cache(grammar, f"rules-{start}"),
    )


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


def _describe_expected(expected: set[str]) -> str:
    words = sorted({_EXPECT_WORDS.get(e, e.lower()) for e in expected})
    if len(words) > 6:
        words = [*words[:6], "..."]
    return ", ".join(words)


def _syntax_error(err: UnexpectedInput, text: str) -> RuleSyntaxError:
    column = getattr(err, "column", None) or 0
    if isinstance(err, UnexpectedToken):
        found = "end of rule" if err.token.type == "$END" else repr(str(err.token))
        if err.token.type == "$END":
            column = len(text) + 1
        msg = f"unexpected {found}; expected {_describe_expected(set(err.expected))}"
    elif isinstance(err, UnexpectedCharacters):
        msg = (
            f"unexpected character {text[err.pos_in_stream]!r}"
            if err.pos_in_stream < len(text)
            else "unexpected end"
        )
    else:
        msg = "syntax error"
    return RuleSyntaxError(msg, column=column or None)


def _parse(start: str, text: str):
    if "\n" in text or "\r" in text:
        raise RuleSyntaxError(
            "a rule is one line; put each rule on its own line", column=text.find("\n") + 1
        )
    try:
        return _parser(start).parse(text)
    except UnexpectedInput as err:
        raise _syntax_error(err, text) from None
    except LarkError as err:  # grammar-level surprises must still come out as our error
        raise RuleSyntaxError(f"cannot parse: {err}") from None


def _assemble(kind: RuleKind, tree, text: str) -> Rule:
    label = None
    weight = 1.0
    condition = None
    actions = []
    for child in tree.children:
        if isinstance(child, tuple) and child[0] == "label":
            label = child[1]
        elif isinstance(child, tuple) and child[0] == "weight":
            weight = child[1]
        elif isinstance(child, Token):
            continue
        elif condition is None:
            condition = child
        else:
            actions.append(child)
    return Rule(kind, label, condition, tuple(actions), weight, text)


def parse_rule(text: str, kind: RuleKind = "fuzzy") -> Rule:
    """Parse one rule of the given syntax. Raises RuleSyntaxError with the column."""
    if kind not in ("fuzzy", "crisp"):
        raise ValueError(f"rule kind must be 'fuzzy' or 'crisp', not {kind!r}")
    rule = _assemble(kind, _parse(f"start_{kind}", text), text)
    if kind == "fuzzy" and not 0.0 <= rule.weight <= 1.0:
        col = text.lower().rfind("with") + 1
        raise RuleSyntaxError(f"weight {rule.weight:g} is outside 0..1", column=col or None)
    return rule


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
