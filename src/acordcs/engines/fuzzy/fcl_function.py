"""jFuzzyLogic's FUNCTION terms: an output singleton whose position is computed from the inputs.

``TERM t := FUNCTION 2 * x + ln(y);`` (jFuzzyLogic's MembershipFunctionFuncion, evaluated by its
Mff* classes): ``+ - * / ^ %`` (``%`` is Java's remainder, sign of the dividend), ``exp``, ``ln``
(natural), ``log`` (base 10), ``sin``, ``cos``, ``tan``, ``abs``, numbers and input variables.
Parsed with ``fcl_function.lark`` and compiled to a postfix program that a loop evaluates: no
``eval``, no recursion, and limits on size (:data:`MAX_TEXT` characters, :data:`MAX_DEPTH`
nested parentheses) checked before parsing. A value that is not a finite number at any step (a
division by 0, ``ln`` of 0) makes the term undefined for that firing.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from functools import cache
from importlib import resources

from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedInput

from acordcs.cachedir import lark_cache
from acordcs.engines.rule_engine import RuleError

MAX_TEXT = 2000
MAX_DEPTH = 50


def _safe(fn: Callable[..., float]) -> Callable[..., float]:
    def call(*args: float) -> float:
        try:
            return fn(*args)
        except (ArithmeticError, ValueError):  # ZeroDivision, Overflow, math domain
            return math.nan

    return call


FUNCTIONS: dict[str, Callable[[float], float]] = {
    "exp": _safe(math.exp),
    "ln": _safe(math.log),
    "log": _safe(math.log10),
    "sin": _safe(math.sin),
    "cos": _safe(math.cos),
    "tan": _safe(math.tan),
    "abs": abs,
}
_BINARY: dict[str, Callable[[float, float], float]] = {
    "add": lambda a, b: a + b,
    "sub": lambda a, b: a - b,
    "mul": lambda a, b: a * b,
    "div": _safe(lambda a, b: a / b),
    "pow": _safe(lambda a, b: float(a**b) if not (a < 0 and b != int(b)) else math.nan),
    "mod": _safe(math.fmod),
}
_SYMBOL = {"add": "+", "sub": "-", "mul": "*", "div": "/", "pow": "^", "mod": "%"}


@cache
def _parser() -> Lark:
    grammar = resources.files(__package__).joinpath("fcl_function.lark").read_text("utf-8")
    return Lark(grammar, parser="lalr", cache=lark_cache(grammar, "fcl_function"))


class Expression:
    """A parsed FUNCTION expression: ``variables`` it reads, ``text`` (as written back), and
    :meth:`evaluate`. Equal when their texts are."""

    __slots__ = ("program", "text", "variables")

    def __init__(self, program: tuple, text: str, variables: tuple[str, ...]) -> None:
        self.program, self.text, self.variables = program, text, variables

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Expression) and other.text == self.text

    def __hash__(self) -> int:
        return hash(self.text)

    def __repr__(self) -> str:
        return f"Expression({self.text!r})"

    def evaluate(self, values: Mapping[str, float | None]) -> float:
        """The value on ``values`` (variable -> number; a missing one or None gives NaN)."""
        stack: list[float] = []
        push, pop, finite = stack.append, stack.pop, math.isfinite
        for op, arg in self.program:
            if op == "num":
                v = arg
            elif op == "var":
                v = values.get(arg)
                v = math.nan if v is None else float(v)
            elif op == "neg":
                v = -pop()
            elif op == "call":
                v = FUNCTIONS[arg](pop())
            else:
                b = pop()
                v = _BINARY[op](pop(), b)
            if not finite(v):  # undefined from here on (1 ^ ln(0) is not 1)
                return math.nan
            push(v)
        return stack[0]


def parse_function(text: str, where: str = "FUNCTION") -> Expression:
    """The expression ``text`` (after the word FUNCTION); RuleError says what is wrong in it."""
    if len(text) > MAX_TEXT:
        raise RuleError(
            f"{where}: the expression has {len(text):,} characters; at most {MAX_TEXT:,}"
        )
    depth = deepest = 0
    for ch in text:
        depth += ch == "("
        depth -= ch == ")"
        deepest = max(deepest, depth)
    if deepest > MAX_DEPTH:
        raise RuleError(f"{where}: parentheses nest {deepest} deep; at most {MAX_DEPTH}")
    try:
        tree = _parser().parse(text)
    except UnexpectedInput as err:
        col = getattr(err, "column", "?")
        raise RuleError(
            f"{where}: the expression does not parse at character {col} of {text.strip()!r}; "
            "write numbers, input names, + - * / ^ %, parentheses and exp ln log sin cos tan abs"
        ) from None
    return _compile(tree, where)


def _compile(tree: Tree | Token, where: str) -> Expression:
    """Post-order walk with an explicit stack: the program, its text and the names it reads."""
    program: list[tuple[str, object]] = []
    texts: list[str] = []
    names: dict[str, None] = {}
    stack: list[tuple[Tree | Token, bool]] = [(tree, False)]
    while stack:
        node, done = stack.pop()
        if isinstance(node, Token):  # a unary "+" leaves its operand's tree in place
            continue
        kind = node.data
        if kind == "num":
            value = float(node.children[0])
            program.append(("num", value))
            texts.append(str(node.children[0]))
        elif kind == "var":
            name = str(node.children[0])
            program.append(("var", name))
            names[name] = None
            texts.append(name)
        elif not done:
            stack.append((node, True))
            kids = [c for c in node.children if isinstance(c, Tree)]
            stack.extend((c, False) for c in reversed(kids))
        elif kind == "call":
            name = str(node.children[0])
            if name.lower() not in FUNCTIONS:
                raise RuleError(
                    f"{where}: unknown function {name}(); use one of {', '.join(FUNCTIONS)}"
                )
            program.append(("call", name.lower()))
            texts.append(f"{name.lower()}({texts.pop()})")
        elif kind == "neg":
            program.append(("neg", None))
            texts.append(f"(-{texts.pop()})")
        elif kind in _BINARY:
            program.append((kind, None))
            right, left = texts.pop(), texts.pop()
            texts.append(f"({left} {_SYMBOL[kind]} {right})")
        else:  # start or a grouping rule with one expression below
            continue
    return Expression(tuple(program), texts[-1], tuple(names))
