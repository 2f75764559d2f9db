"""Parser and syntax tree of the ACORD-CS rule language (grammar: ``rules.lark``).

Two rule syntaxes share keywords and layout:

- fuzzy (the paper's): ``[label:] if V is [not|very|somewhat] T {and|or ...} then V is T {and V is T}
  [with W]``, with parentheses; AND and OR have equal precedence, left to right;
- crisp, for expert-system policy sets: comparisons with and/or/not, then actions that assign a
  variable or call an operation: ``if speed == 0 and retries < 3 then recovery.recover()``.

Variables are ``attribute`` or ``Element.attribute``. Linguistic terms of a variable are written FCL
style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``. One parser serves the validator and the
engines: :mod:`acordcs.rules.standalone_parser`, lark's LALR(1) parser generated from ``rules.lark``
by lark's standalone generator (``tools/generate_rules_parser.py``), so that reading rules needs no
lark; every error is a :class:`RuleSyntaxError` with the column in the rule text.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from functools import cache

from acordcs.errors import AcordError
from acordcs.rules.standalone_parser import (
    Lark,
    Lark_StandAlone,
    Token,
    Transformer,
    Tree,
    UnexpectedCharacters,
    UnexpectedInput,
    UnexpectedToken,
)
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
# One method per grammar rule (or alias), called by the parser with the rule's kept children as a
# list, as it reduces (lark's inline transformer: no tree is built and walked afterwards); tokens
# are lark Tokens (keyword tokens such as IF or IS arrive too and are skipped by position).
def _name(tok: Token) -> Name:
    return Name(tok.value, tok.column)


def _number_text(tok: Token) -> str:
    # int() refuses 4,300+ digits; no rule needs more than a double's range
    if len(tok.value) > 64:
        raise RuleSyntaxError(f"number {tok.value[:12]}... is too long", column=tok.column)
    return tok.value


def _num(tok: Token) -> float:
    return float(_number_text(tok))


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
        # Integer literals stay integers: `retries + 1` must not turn a count into 1.0.
        text = _number_text(c[0])
        return Const(int(text) if text.lstrip("+-").isdigit() else float(text), c[0].column)

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
def _parser() -> Lark:
    """The generated parser (``standalone_parser``, made by lark's standalone generator from
    ``rules.lark``: no lark at run time) building the tree with :class:`RuleTreeBuilder`."""
    return Lark_StandAlone(transformer=RuleTreeBuilder())


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


def _parse(start: str, text: str) -> Tree:
    if "\n" in text or "\r" in text:
        raise RuleSyntaxError(
            "a rule is one line; put each rule on its own line", column=text.find("\n") + 1
        )
    try:
        return _parser().parse(text, start=start)
    except (UnexpectedToken, UnexpectedCharacters) as err:
        raise syntax_error(err, text) from None


def _assemble(kind: RuleKind, tree: Tree, text: str) -> Rule:
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


def forget_parsed_rules() -> None:
    """Empty the cache of parsed rules (:func:`parse_rule` parses each text again: benchmarks)."""
    _PARSED.clear()


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
