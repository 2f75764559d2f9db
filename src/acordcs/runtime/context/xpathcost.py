"""What an untrusted subscriber's XPath may cost, and what a document costs to evaluate it on.

lxml cannot interrupt an XPath evaluation, so the cost of the expressions the index does not
evaluate itself (the fallback subscriptions) is bounded before they run, in two parts:

- the **expression** (:func:`check_linear`, at ``subscribe``): one evaluation visits each node of the
  document a bounded number of times. Refused: a location path from the root (``/``, ``//``) or a
  descendant step (``//``, ``descendant::``) inside a predicate (``//*[count(//*) > 0]`` evaluates
  the whole document once per node: quadratic, cubic when nested); a predicate inside a predicate;
  the axes ``ancestor``, ``preceding``, ``following`` and their siblings and ``-or-self`` forms
  (each a walk of the document per node); more than :data:`MAX_TERMS` predicates and function calls;
- the **document** (:func:`document_cost`, at ``publish``): what remains is the string-value of
  nodes (``contains(., 'fire')`` on every element concatenates the text below each one) and
  relative paths below each node. Both are bounded by the sum, over elements, of their depth, plus
  the sum, over text, of its length times its depth: a document above ``Limits.max_cost`` is refused.

An expression that passes, on a document that passes, costs at most about ``MAX_TERMS`` times
``max_cost`` character operations (the default 4,000,000: a few milliseconds per term).
"""

from __future__ import annotations

import re

from lxml import etree

from acordcs.runtime.context.errors import SubscriptionError

MAX_TERMS = 8
"""Predicates plus function calls an untrusted fallback expression may have."""

_TOKEN = re.compile(
    r"""\s*(?:
      (?P<literal>'[^']*'|"[^"]*")
    | (?P<number>[0-9]+(?:\.[0-9]*)?|\.[0-9]+)
    | (?P<axis>[A-Za-z_][\w.\-]*)\s*::
    | (?P<call>[A-Za-z_][\w.\-]*(?::[A-Za-z_][\w.\-]*)?)\s*(?=\()
    | (?P<name>[A-Za-z_][\w.\-]*(?::(?:[A-Za-z_][\w.\-]*|\*))?|\*)
    | (?P<op>//|/|\.\.|\.|@|\[|\]|\(|\)|,|\||!=|<=|>=|=|<|>|\+|-|\$)
    )""",
    re.VERBOSE,
)
_WALKING_AXES = frozenset(
    (
        "ancestor",
        "ancestor-or-self",
        "preceding",
        "preceding-sibling",
        "following",
        "following-sibling",
    )
)
_DESCENDING_AXES = frozenset(("descendant", "descendant-or-self"))
_NODE_TESTS = frozenset(("node", "text", "comment", "processing-instruction"))
_OPERATOR_NAMES = frozenset(("and", "or", "div", "mod", "*"))  # operators after an operand


def _refuse(expression: str, why: str, position: int) -> SubscriptionError:
    return SubscriptionError(
        f"XPath expression {expression!r} {why}: too costly for a "
        "subscription the index does not evaluate (see docs/providers.md, Security model)",
        file="<xpath>",
        line=1,
        column=position + 1,
        element="subscription",
        hint="use a relative path inside predicates (e.g. //alarm[contains(., 'fire')]), or "
        "Limits(trusted_subscribers=True) for subscribers you trust",
    )


def check_linear(expression: str) -> None:
    """Raise :class:`SubscriptionError` unless ``expression`` is of the linear forms (module doc).

    ``expression`` compiled with lxml already: this only reads its tokens."""
    depth = 0  # predicate nesting
    terms = 0
    operand = False  # the previous token ends an operand: a '/' now continues a path
    pos, end = 0, len(expression.rstrip())
    while pos < end:
        match = _TOKEN.match(expression, pos)
        if match is None:  # a character the scanner does not know: harmless, lxml compiled it
            pos, operand = pos + 1, False
            continue
        kind = match.lastgroup or ""
        text, at, pos = match.group(kind), match.start(kind), match.end()
        if kind == "axis":
            if text in _WALKING_AXES:
                raise _refuse(expression, f"uses the {text} axis", at)
            if text in _DESCENDING_AXES and depth:
                raise _refuse(expression, f"uses the {text} axis inside a predicate", at)
            operand = False
        elif kind == "call":
            terms += text not in _NODE_TESTS
            operand = False
        elif kind in ("literal", "number"):
            operand = True
        elif kind == "name":  # a name test (a step), or an operator after an operand
            operand = not (operand and text in _OPERATOR_NAMES)
        elif text == "[":
            if depth:
                raise _refuse(expression, "has a predicate inside a predicate", at)
            depth, terms, operand = depth + 1, terms + 1, False
        elif text == "]":
            depth, operand = max(0, depth - 1), True
        elif text in ("/", "//"):
            if depth and not operand:
                raise _refuse(expression, "has a path from the root inside a predicate", at)
            if depth and text == "//":
                raise _refuse(expression, "has a descendant step '//' inside a predicate", at)
            operand = False
        else:
            operand = text in (")", ".", "..")
        if terms > MAX_TERMS:
            raise _refuse(
                expression, f"has more than {MAX_TERMS} predicates and function calls", at
            )


def document_cost(root: etree._Element) -> int:
    """Sum over elements of their depth, plus over text (and tails) of its length times the depth
    of the element holding it: bounds the work of string-values and relative paths from every node."""
    total = 0
    depth = 0
    for event, element in etree.iterwalk(root, events=("start", "end")):
        if event == "start":
            depth += 1
            total += depth * (1 + len(element.text or ""))
        else:
            depth -= 1
            if element.tail:
                total += depth * len(element.tail)
    return total
