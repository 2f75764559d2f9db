"""Parser and syntax tree of the ACORD-CS rule language (grammar: ``rules.lark``).

Two rule syntaxes share keywords and layout:

- fuzzy (the paper's): ``[label:] if V is [not|very|somewhat] T {and|or ...} then V is T {and V is T}
  [with W]``, with parentheses; AND and OR have equal precedence, left to right;
- crisp, for expert-system policy sets: comparisons with and/or/not, then actions that assign a
  variable or call an operation: ``if speed == 0 and retries < 3 then recovery.recover()``.

Variables are ``attribute`` or ``Element.attribute``. Linguistic terms of a variable are written FCL
style: ``slow := trape 0 0 40 80; fast := trian 60 200 200``. One grammar serves the validator and
the engines: a text is read by the fast reader (:mod:`acordcs.rules.fast`, a recursive descent
without lark) or, where it declines (every error, and a few rare forms), by lark's LALR(1) parser of
``rules.lark`` (:mod:`acordcs.rules.lark_parser`, through lark's public API), which builds the same
tree and words every error: a :class:`RuleSyntaxError` with the column in the rule text.
"""

from __future__ import annotations

from typing import Any

from acordcs.rules import fast
from acordcs.rules.errors import RuleSyntaxError
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
]
HEDGES = ("not", "very", "somewhat")
KEYWORDS = frozenset(
    "if then and or not is with true false very somewhat trape trian gauss gbell sigm".split()
)


def _parse(start: str, text: str) -> list[Any]:
    """The children ``start`` derives ``text`` into, as built (the keywords' tokens left out)."""
    if "\n" in text or "\r" in text:
        raise RuleSyntaxError(
            "a rule is one line; put each rule on its own line", column=text.find("\n") + 1
        )
    try:
        return fast.read(start, text)
    except fast.Decline:  # an error, or a form the fast reader leaves to lark, which words errors
        pass
    from acordcs.rules import lark_parser  # here: it imports lark, which most processes never need

    # a keyword's token (IF, THEN, AND) is a str; what the builders made never is
    return [c for c in lark_parser.parse(start, text).children if not isinstance(c, str)]


def _assemble(kind: RuleKind, children: list[Any], text: str) -> Rule:
    label = None
    weight = 1.0
    condition = None
    actions = []
    for child in children:
        if isinstance(child, tuple) and child[0] == "label":
            label = child[1]
        elif isinstance(child, tuple) and child[0] == "weight":
            weight = child[1]
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
    return _parse("start_terms", flat)


def split_rules(tag_value: str) -> list[RuleLine]:
    """The rules of a Rule tag value: one per non-blank line; ``#`` or ``//`` starts a comment line."""
    out = []
    for number, raw in enumerate(tag_value.splitlines(), start=1):
        line = raw.strip()
        if not line or line.startswith(("#", "//")):
            continue
        out.append(RuleLine(line, number))
    return out
