"""Subscription expressions: validation with lxml and recognition of the indexable forms.

Every expression is compiled *and evaluated once* on a probe document, because lxml reports syntax
errors at compile time but unknown functions, variables and namespace prefixes only when evaluating.
Expressions of the forms below are additionally described as an :class:`IndexedForm`, which the
subscription index evaluates without running one XPath per subscription:

    PATH                      (the path selects something)
    PATH[V op CONST]          V is ``.``, a child name or ``@attribute``; op in = != < <= > >=
    PATH[CONST op V]          (flipped to the form above)

PATH is an absolute location path of ``/name``, ``//name``, ``*`` and a final ``@name`` steps. CONST
is a number literal (optionally negated) or a string literal; its value is obtained from lxml itself,
so the index compares with exactly the numbers libxml2 would use.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from lxml import etree

from acordcs.runtime.context.errors import SubscriptionError
from acordcs.runtime.context.xpathnum import xpath_number

_NAME = r"[A-Za-z_][A-Za-z0-9_]*"  # no "-" or ".": "a-1" lexing is left to lxml
_PATH = re.compile(rf"(?:/{{1,2}}(?:{_NAME}|\*))+(?:/{{1,2}}@{_NAME})?")
_CHILD_PATH = re.compile(rf"(?:/{_NAME})+")
_VALUE = rf"\.|@?{_NAME}"
_CONST = r"-?(?:[0-9]+(?:\.[0-9]*)?|\.[0-9]+)(?:[eE][+-]?[0-9]+)?|'[^']*'|\"[^\"]*\""
_OP = r"!=|<=|>=|=|<|>"
_PRED_V_FIRST = re.compile(rf"\s*(?P<v>{_VALUE})\s*(?P<op>{_OP})\s*(?P<c>{_CONST})\s*")
_PRED_C_FIRST = re.compile(rf"\s*(?P<c>{_CONST})\s*(?P<op>{_OP})\s*(?P<v>{_VALUE})\s*")
_FLIP = {"=": "=", "!=": "!=", "<": ">", "<=": ">=", ">": "<", ">=": "<="}
# names the XPath lexer may read as operators depending on context: leave those to lxml
_KEYWORDS = {"and", "or", "div", "mod"}

_PROBE = etree.ElementTree(etree.fromstring(b"<probe/>"))

# The probe evaluation misses what sits in a predicate of a path the probe does not match
# (``/robot[frobnicate(.)]``), so function names and variables are also checked statically;
# the cost check (xpathcost) knows the cost of these functions only.
CORE_FUNCTIONS = frozenset(
    [
        "last",
        "position",
        "count",
        "id",
        "local-name",
        "namespace-uri",
        "name",
        "string",
        "concat",
        "starts-with",
        "contains",
        "substring-before",
        "substring-after",
        "substring",
        "string-length",
        "normalize-space",
        "translate",
        "boolean",
        "not",
        "true",
        "false",
        "lang",
        "number",
        "sum",
        "floor",
        "ceiling",
        "round",
    ]
)
_NODE_TYPES = frozenset({"node", "text", "comment", "processing-instruction"})
_LITERALS = re.compile(r"'[^']*'|\"[^\"]*\"")
_CALL = re.compile(r"(?<![\w.\-:@$])([A-Za-z_][\w.\-]*(?::[A-Za-z_][\w.\-]*)?)\s*\(")


@dataclass(frozen=True)
class IndexedForm:
    """An expression the index evaluates itself. ``op`` is None for a bare PATH."""

    path: str
    child_steps: tuple[str, ...] | None  # set when PATH is /a/b/c (walked without XPath)
    value_kind: str | None = None  # "self", "child" or "attr"
    value_name: str | None = None
    op: str | None = None
    const_kind: str | None = None  # "num" or "str"
    const: float | str | None = None


def _constant(text: str, op: str) -> tuple[str, float | str]:
    if text[0] in "'\"":
        literal = text[1:-1]
        if op in ("=", "!="):
            return "str", literal
        return "num", xpath_number(literal)
    return "num", float(etree.XPath(text)(_PROBE))


def recognise(expression: str) -> IndexedForm | None:
    """The indexed form of an already validated expression, or None (evaluated by lxml)."""
    bracket = expression.find("[")
    path = expression if bracket < 0 else expression[:bracket]
    if not _PATH.fullmatch(path) or any(
        step.lstrip("@") in _KEYWORDS for step in path.replace("//", "/").split("/")
    ):
        return None
    steps = tuple(path[1:].split("/")) if _CHILD_PATH.fullmatch(path) else None
    if bracket < 0:
        return IndexedForm(path, steps)
    if not expression.endswith("]"):
        return None
    predicate = expression[bracket + 1 : -1]
    match = _PRED_V_FIRST.fullmatch(predicate)
    op = match["op"] if match else None
    if match is None:
        match = _PRED_C_FIRST.fullmatch(predicate)
        if match is None:
            return None
        op = _FLIP[match["op"]]
    value = match["v"]
    if value.lstrip("@") in _KEYWORDS:
        return None
    if value == ".":
        kind, name = "self", None
    elif value.startswith("@"):
        kind, name = "attr", value[1:]
    else:
        kind, name = "child", value
    const_kind, const = _constant(match["c"], op)
    return IndexedForm(path, steps, kind, name, op, const_kind, const)


def compile_expression(expression: str, max_chars: int, what: str = "subscription") -> etree.XPath:
    """Compile ``expression`` and evaluate it once, or raise :class:`SubscriptionError`."""
    if not isinstance(expression, str):
        raise SubscriptionError(
            f"an XPath expression must be a str, not {type(expression).__name__}",
            element=what,
            hint="pass the expression text",
        )
    if not expression.strip():
        raise SubscriptionError(
            "empty XPath expression", element=what, hint="pass None to select everything"
        )
    if len(expression) > max_chars:
        raise SubscriptionError(
            f"XPath expression of {len(expression)} characters exceeds {max_chars}",
            element=what,
            hint="simplify it or raise Limits.max_expression_chars",
        )
    try:
        compiled = etree.XPath(expression)
        compiled(_PROBE)
    except etree.XPathError as err:
        column = None
        log = getattr(err, "error_log", None)
        if log:
            column = log[-1].column or None
        kind = "syntax error" if isinstance(err, etree.XPathSyntaxError) else "cannot be evaluated"
        pointer = f" at column {column}" if column else ""
        raise SubscriptionError(
            f"XPath expression {expression!r} {kind}{pointer}: {err}",
            file="<xpath>",
            line=1 if column else None,
            column=column,
            element=what,
            hint="XPath 1.0 without extension functions or variables; fix the expression",
        ) from None
    _check_names(expression, what)
    return compiled


def _check_names(expression: str, what: str) -> None:
    code = _LITERALS.sub(lambda m: " " * len(m.group()), expression)
    problem = None
    dollar = code.find("$")
    if dollar >= 0:
        problem, column = "uses a variable (Undefined variable); none can be bound", dollar + 1
    else:
        for match in _CALL.finditer(code):
            name = match.group(1)
            if name not in CORE_FUNCTIONS and name not in _NODE_TYPES and name not in _KEYWORDS:
                problem = (
                    f"calls {name}() (Unregistered function): only XPath 1.0 core functions exist"
                )
                column = match.start(1) + 1
                break
    if problem is not None:
        raise SubscriptionError(
            f"XPath expression {expression!r} {problem}, at column {column}",
            file="<xpath>",
            line=1 if column else None,
            column=column,
            element=what,
            hint="XPath 1.0 without extension functions or variables; fix the expression",
        )
