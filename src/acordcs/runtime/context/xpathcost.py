"""What an untrusted subscriber's XPath may cost, and what a document costs to evaluate it on.

lxml cannot interrupt an XPath evaluation, so the cost of the expressions the index does not
evaluate itself (the fallback subscriptions) is bounded before they run, in two parts:

- the **document** (:func:`document_cost`, at ``publish``): the sum, over elements, of their depth,
  plus the sum, over text, of its length times its depth. It bounds the total length of the
  string-values of all elements (each character counts once per element it is in): a document
  above ``Limits.max_cost`` is refused, as one above ``Limits.max_nodes`` nodes;
- the **expression** (:func:`check_cost`, at ``subscribe``): read into a tree
  (:mod:`.xpathparse`) and costed in *units*, where :data:`PASS` units are one walk over every
  node, or one reading of every string-value, of a document within those limits. Each operation
  of the expression is allowed only in forms where one evaluation performs it at most once per
  node of the document in total, even inside a predicate (evaluated once per node); it then costs
  one pass (:data:`PASS`: a step, a reading of string-values) or one unit (an operator, a
  literal, a function call, a predicate; ``and`` and ``or`` are operators that read and compare
  nothing). The exact values, and what reads string-values, are those of docs/providers.md
  ("Security model"), pinned by ``tests/runtime/test_context_xpath_cost_model_is_pinned.py``.
  Operations that would revisit the document once per node are refused, whatever their count
  (libxml2's algorithms, measured): a path from the root, a descendant, ancestor, sibling,
  preceding or following step inside a predicate (every node walks the document again); the
  string-value of, or a step from, the parent (``..``) inside a predicate
  (``//*[string-length(..) = 1]`` reads the parent once per child: quadratic on a flat
  document); a descendant, parent, ancestor, following or preceding (or sibling) step after a
  step that selects several nodes: only child, attribute and self steps may follow one (libxml2
  merges the overlapping results of the others with a quadratic duplicate check); a union or a
  comparison of two node-sets that may each hold several nodes (every node of one against every
  node of the other); ``lang()`` (reads every ancestor's attributes) and ``id()``;
  ``translate()`` (about 30 passes per call: libxml2 handles every character separately); a
  function that is not one of XPath 1.0's core functions (lxml refuses them first; the cost
  check knows the cost of those only); ``contains``, ``substring-before`` and
  ``substring-after`` unless their second argument is a literal (libxml2 compares it at every
  character of the first: each of its characters costs two passes); the namespace axis
  (namespace nodes are not counted by ``max_nodes``); a predicate inside a predicate.

An expression costing more than ``Limits.max_xpath_cost`` units is refused. What passes costs at most
that many units on a document within the limits: ``tests/runtime/test_context_xpath_cost.py``
checks it on adversarial documents with expressions generated over every axis and function.
"""

from __future__ import annotations

from dataclasses import dataclass

from lxml import etree

from acordcs.runtime.context.errors import SubscriptionError
from acordcs.runtime.context.xpathexpr import CORE_FUNCTIONS
from acordcs.runtime.context.xpathparse import (
    Binary,
    Call,
    Expr,
    Filter,
    Literal,
    Negate,
    Number,
    Path,
    Step,
    Variable,
    XPathSyntax,
    parse,
)

PASS = 8
"""Units of one walk over every node or one reading of every string-value of a document."""
UNIT = 1
"""Units of an operator, literal, function call or predicate (per node it is evaluated on)."""
NEEDLE = 2 * PASS
"""Units of each character ``contains()`` and its kin look for: libxml2 compares it at every
character of the searched string (measured: about three readings of the string per character)."""

_SEARCHED = {"contains": (1,), "substring-before": (1,), "substring-after": (1,)}
_NO_READ = frozenset(("count", "name", "local-name", "namespace-uri", "boolean", "not"))
_NO_ARGS = frozenset(("last", "position", "true", "false"))
_READ_CONTEXT = frozenset(("string", "number", "string-length", "normalize-space"))
_FORWARD = frozenset(("child", "attribute", "self"))
_UPWARD = frozenset(("parent", "ancestor", "ancestor-or-self"))
_SIDEWAYS = frozenset(("following", "following-sibling", "preceding", "preceding-sibling"))


@dataclass(slots=True)
class _Value:
    """What an evaluated (sub)expression yields, as far as its cost is concerned."""

    nodes: bool = False
    single: bool = False  # a node-set of at most one node
    document: bool = False  # the document node itself (its element child is single)
    shared: bool = False  # a predicate node's parent: the other children share it
    constant: int | None = None  # a scalar known now: at most this many characters as a string


class _Refused(Exception):
    def __init__(self, why: str, position: int) -> None:
        super().__init__(why)
        self.why, self.position = why, position


class _Costing:
    def __init__(self) -> None:
        self.units = 0

    # -- values -----------------------------------------------------------------------------------
    def read(self, value: _Value, pos: int) -> None:
        """The string-values of ``value``'s nodes are computed (a comparison, a conversion)."""
        if not value.nodes:
            return
        if value.shared:
            raise _Refused(
                "reads the string-value of a node reached by the parent axis ('..'), once for "
                "every node the predicate is evaluated on (quadratic)",
                pos,
            )
        self.units += PASS

    def expression(self, node: Expr, inside: bool) -> _Value:
        """Cost ``node``; ``inside``: within a predicate (evaluated once per node)."""
        if isinstance(node, Literal):
            self.units += UNIT
            return _Value(constant=len(node.value))
        if isinstance(node, Number):
            self.units += UNIT
            # as a string, a number literal is at most one character longer (".5" is "0.5")
            return _Value(constant=len(node.text) + 1)
        if isinstance(node, Variable):
            raise _Refused("uses a variable", node.pos)
        if isinstance(node, Negate):
            self.units += UNIT
            self.read(self.expression(node.operand, inside), node.pos)
            return _Value()
        if isinstance(node, Binary):
            return self.binary(node, inside)
        if isinstance(node, Call):
            return self.call(node, inside)
        if isinstance(node, Filter):
            value = self.expression(node.primary, inside)
            value.document = False
            return self.predicates(node.predicates, value, inside, node.pos)
        return self.path(node, inside)

    def binary(self, node: Binary, inside: bool) -> _Value:
        self.units += UNIT
        left = self.expression(node.left, inside)
        right = self.expression(node.right, inside)
        if node.op == "|":
            if not (left.single or right.single):
                raise _Refused(
                    "unites two node-sets that may each hold many nodes (libxml2 checks every "
                    "node of one against every node of the other: quadratic)",
                    node.pos,
                )
            return _Value(nodes=True, shared=left.shared or right.shared)
        if node.op in ("and", "or"):
            return _Value()
        both = left.nodes and right.nodes and not (left.single or right.single)
        if node.op in ("=", "!=", "<", "<=", ">", ">=") and both:
            raise _Refused(
                f"compares two node-sets with '{node.op}' (every node of one against every "
                "node of the other: quadratic)",
                node.pos,
            )
        self.read(left, node.pos)
        self.read(right, node.pos)
        return _Value()

    def call(self, node: Call, inside: bool) -> _Value:
        self.units += UNIT
        name, pos = node.name, node.pos
        if name == "lang":
            raise _Refused(
                "calls lang(), which reads the attributes of every ancestor of every node "
                "(quadratic)",
                pos,
            )
        if name == "translate":
            raise _Refused(
                "calls translate(), which costs libxml2 about 30 times a reading of its string "
                "(it looks up and appends every character separately)",
                pos,
            )
        if name == "id":
            raise _Refused(
                "calls id(), which selects nodes anywhere in the document (its result cannot "
                "be bounded per node)",
                pos,
            )
        if name not in CORE_FUNCTIONS:  # lxml refuses them first; the costs here are XPath 1.0's
            raise _Refused(
                f"calls {name}(), which is not an XPath 1.0 core function (the cost check knows "
                "the cost of those only)",
                pos,
            )
        args = [self.expression(arg, inside) for arg in node.args]
        if name in _NO_ARGS or name in _NO_READ:
            return _Value()
        if not args and name in _READ_CONTEXT:
            self.read(_Value(nodes=True, single=True), pos)  # the context node's string-value
            return _Value()
        searched = _SEARCHED.get(name, ())
        for index, (arg, value) in enumerate(zip(node.args, args, strict=True)):
            if index in searched:
                if value.constant is None:
                    raise _Refused(
                        f"gives {name}() a computed argument {index + 1}: libxml2 looks for it at "
                        "every character of the first, so two long strings cost the product of "
                        "their lengths (give a literal)",
                        arg.pos,
                    )
                self.units += NEEDLE * value.constant
            else:
                self.read(value, arg.pos)
        if name == "concat":
            if all(v.constant is not None for v in args):
                return _Value(constant=sum(v.constant or 0 for v in args))
            # libxml2 appends each argument to the result so far: k arguments copy the first
            # k times, the second k - 1 times...
            self.units += PASS * (len(args) * (len(args) + 1) // 2 - len(args))
        return _Value()

    # -- paths ------------------------------------------------------------------------------------
    def path(self, node: Path, inside: bool) -> _Value:
        if node.absolute:
            if inside:
                raise _Refused("has a path from the root inside a predicate", node.pos)
            current = _Value(nodes=True, single=True, document=True)
        elif node.start is not None:
            current = self.expression(node.start, inside)
            current.document = False
        else:
            current = _Value(nodes=True, single=True)  # the context node
        for step in node.steps:
            current = self.step(step, current, inside)
        return current

    def step(self, step: Step, current: _Value, inside: bool) -> _Value:
        self.units += PASS
        axis, pos = step.axis, step.pos
        if axis == "namespace":
            raise _Refused("uses the namespace axis (namespace nodes are not counted)", pos)
        if current.shared and axis not in _UPWARD and axis != "self":
            raise _Refused(
                f"takes a {axis} step from a node reached by the parent axis ('..'), once for "
                "every node the predicate is evaluated on (quadratic)",
                pos,
            )
        if (axis in _SIDEWAYS or axis.startswith("ancestor")) and inside:
            raise _Refused(f"uses the {axis} axis inside a predicate", pos)
        if axis.startswith("descendant") and inside:
            what = "a descendant step '//'" if step.test == "node()" else f"the {axis} axis"
            raise _Refused(f"has {what} inside a predicate", pos)
        if axis not in _FORWARD and not current.single:
            raise _Refused(
                f"takes a {axis} step from a step that may select many nodes (libxml2 merges "
                "their overlapping results with a quadratic duplicate check)",
                pos,
            )
        if axis == "self":
            result = _Value(
                True, current.single, current.document and step.test == "node()", current.shared
            )
        elif axis == "parent":
            result = _Value(nodes=True, single=True, shared=inside or current.shared)
        elif axis in _UPWARD:
            result = _Value(nodes=True, shared=inside or current.shared)
        else:
            single = current.single and (
                (axis == "attribute" and step.named) or (axis == "child" and current.document)
            )
            result = _Value(nodes=True, single=single and not step.test.endswith("()"))
        return self.predicates(step.predicates, result, inside, pos)

    def predicates(self, predicates: list[Expr], value: _Value, inside: bool, pos: int) -> _Value:
        if not predicates:
            return value
        if inside:
            raise _Refused("has a predicate inside a predicate", pos)
        if value.shared:
            raise _Refused("has a predicate on a node reached by the parent axis ('..')", pos)
        for predicate in predicates:
            self.units += UNIT
            self.expression(predicate, inside=True)
        value.constant, value.document = None, False
        return value


def _refusal(expression: str, why: str, position: int) -> SubscriptionError:
    return SubscriptionError(
        f"XPath expression {expression!r} {why}: too costly for a "
        "subscription the index does not evaluate (see docs/providers.md, Security model)",
        file="<xpath>",
        line=1,
        column=position + 1,
        element="subscription",
        hint="use relative child paths inside predicates (e.g. //alarm[level > 3 and "
        "contains(., 'fire')]), or Limits(trusted_subscribers=True) for subscribers you trust",
    )


def expression_cost(expression: str) -> int:
    """The units :func:`check_cost` counts for ``expression``, or :class:`SubscriptionError`
    when one of its operations is refused whatever the limit (module doc)."""
    try:
        costing = _Costing()
        if costing.expression(parse(expression), inside=False).nodes:
            costing.units += PASS  # the selected nodes become Python objects
    except XPathSyntax as err:
        raise _refusal(
            expression, f"cannot be read by the cost check ({err})", err.position
        ) from None
    except _Refused as refused:
        raise _refusal(expression, refused.why, refused.position) from None
    return costing.units


def check_cost(expression: str, limit: int) -> int:
    """Raise :class:`SubscriptionError` unless ``expression`` (compiled by lxml already) is of the
    allowed forms and costs at most ``limit`` units; return its cost."""
    units = expression_cost(expression)
    if units > limit:
        raise _refusal(
            expression,
            f"costs {units} units, more than the limit of {limit} ({PASS} units are one pass "
            "over the document)",
            0,
        )
    return units


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
