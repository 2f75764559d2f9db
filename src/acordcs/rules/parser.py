"""Parser and syntax tree of the ACORD-CS rule language (grammar: ``rules.lark``).

Two rule syntaxes share keywords and layout:

- fuzzy (the paper's): ``[label:] if V is [not|very|somewhat] T {and|or ...} then V is T {and V is T}
  [with W]``, with parentheses; AND and OR have equal precedence, left to right;
- crisp, for expert-system policy sets: comparisons with and/or/not, then actions that assign a
  variable or call an operation: ``if speed == 0 and retries < 3 then recovery.recover()``.

Variables are ``attribute`` or ``Element.attribute``. Linguistic terms of a variable are written FCL
style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``. One parser serves the validator and the
engines (lark analyses the grammar; :mod:`acordcs.rules.lalr` runs its tables); every error is a
:class:`RuleSyntaxError` with the column in the rule text.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Iterable
from functools import cache

from acordcs.errors import AcordError
from acordcs.rules.lalr import Node, Tables, Tok, Unexpected
from acordcs.rules.tree import (
    MAX_DEPTH,
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
    Rule,
    RuleKind,
    RuleLine,
    TermDef,
    VarRef,
    column_of,
    depth_message,
    names_in,
    rule_too_deep,
)

# The tree (tree.py) is part of this interface: the package re-exports it with the parser.
__all__ = [
    "HEDGES",
    "KEYWORDS",
    "MAX_DEPTH",
    "Arith",
    "Assign",
    "BoolOp",
    "Call",
    "Compare",
    "Consequent",
    "Const",
    "Is",
    "Name",
    "Neg",
    "Not",
    "Rule",
    "RuleKind",
    "RuleLine",
    "RuleSyntaxError",
    "TermDef",
    "VarRef",
    "depth_message",
    "names_in",
    "parse_rule",
    "parse_terms",
    "rule_too_deep",
    "split_rules",
    "syntax_error",
]
HEDGES = ("not", "very", "somewhat")
KEYWORDS = frozenset(
    "if then and or not is with true false very somewhat trape trian gauss gbell sigm".split()
)


class RuleSyntaxError(AcordError):
    """Rule text that does not parse; ``column`` is 1-based in the rule text."""


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
    rule = _assemble(kind, _parse(f"start_{kind}", text), text)
    # Each level of nesting takes an operator, at least one character: a short rule cannot be
    # too deep, and most rules are short (the walk would cost a sixth of their parse).
    if len(text) > MAX_DEPTH and (found := rule_too_deep(rule)):
        raise RuleSyntaxError(depth_message(), column=column_of(found[1]))
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
