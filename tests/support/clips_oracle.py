"""A plain-Python oracle of crisp rules, and random crisp rule sets and values to feed it.

The oracle walks the rule tree of ``parse_rule`` itself and implements the documented semantics
(docs/clips-engine.md) without CLIPS: rules in definition order, each at most
once per fire, the first whose condition holds fires, unfired rules are evaluated again on the new
values, until none fires; evaluation errors make a condition false or skip one action.
"""

from __future__ import annotations

import functools
import math
import operator

from hypothesis import strategies as st

from acordcs.engines.clips import ClipsEngine
from acordcs.rules import (
    Arith,
    Assign,
    BoolOp,
    Call,
    Compare,
    Const,
    Neg,
    Not,
    VarRef,
    parse_rule,
)


class EvalError(Exception):
    pass


def _number(v: object) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool)


def _equal(a: object, b: object) -> bool:
    if _number(a) and _number(b):
        return a == b
    return type(a) is type(b) and a == b


_ORDER = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
_ARITH = {"+": operator.add, "-": operator.sub, "*": operator.mul}


class Oracle:
    """Plain-Python crisp rules over a dict of values keyed by full variable name."""

    def __init__(self, rules: list[str], names: list[str]):
        self.rules = [parse_rule(text, "crisp") for text in rules]
        self.names = names

    def full(self, text: str) -> str:
        if text in self.names:
            return text
        (match,) = [n for n in self.names if n.rpartition(".")[2] == text]
        return match

    def value(self, node: object, env: dict) -> object:
        if isinstance(node, Const):
            return node.value
        if isinstance(node, VarRef):
            return env[self.full(node.var.text)]
        if isinstance(node, Neg):
            v = self.value(node.operand, env)
            if not _number(v):
                raise EvalError("neg")
            return -v
        if isinstance(node, Arith):
            a, b = self.value(node.left, env), self.value(node.right, env)
            if not (_number(a) and _number(b)):
                raise EvalError(node.op)
            if node.op == "/":
                if b == 0:
                    raise EvalError("division by zero")
                return a / b
            return _ARITH[node.op](a, b)
        return self.truth(node, env)

    def truth(self, node: object, env: dict) -> bool:
        if isinstance(node, Compare):
            a, b = self.value(node.left, env), self.value(node.right, env)
            if node.op == "==":
                return _equal(a, b)
            if node.op == "!=":
                return not _equal(a, b)
            if (_number(a) and _number(b)) or (isinstance(a, str) and isinstance(b, str)):
                return _ORDER[node.op](a, b)
            raise EvalError("order")
        if isinstance(node, BoolOp):
            left = self.truth(node.left, env)
            if node.op == "and":
                return left and self.truth(node.right, env)
            return left or self.truth(node.right, env)
        if isinstance(node, Not):
            return not self.truth(node.operand, env)
        v = self.value(node, env) if isinstance(node, VarRef | Const) else None
        if isinstance(v, bool):
            return v
        raise EvalError("not a boolean")

    def fire(self, env: dict) -> tuple[list, set[int]]:
        """Mutates env; returns the calls made (name, args) and the indices of rules with errors."""
        fired: set[int] = set()
        calls: list = []
        errors: set[int] = set()
        while True:
            chosen = None
            for i, rule in enumerate(self.rules):
                if i in fired:
                    continue
                try:
                    holds = self.truth(rule.condition, env)
                except EvalError:
                    errors.add(i)
                    holds = False
                if holds and chosen is None:
                    chosen = i
            if chosen is None:
                return calls, errors
            fired.add(chosen)
            for action in self.rules[chosen].actions:
                try:
                    if isinstance(action, Assign):
                        env[self.full(action.var.text)] = self.value(action.value, env)
                    else:
                        assert isinstance(action, Call)
                        args = tuple(self.value(a, env) for a in action.args)
                        calls.append((action.target.text, args))
                except EvalError:
                    errors.add(chosen)


def same(a: object, b: object) -> bool:
    if isinstance(a, float) and isinstance(b, float) and math.isnan(a) and math.isnan(b):
        return True
    if isinstance(a, tuple) and isinstance(b, tuple):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b, strict=True))
    return type(a) is type(b) and a == b


def recorder(engine: ClipsEngine, names: list[str]) -> list:
    calls: list = []
    for name in names:
        engine.bind_operation(name, lambda *args, _n=name: calls.append((_n, args)))
    return calls


def check_fire(engine: ClipsEngine, oracle: Oracle, env: dict, calls: list, ruleset: str) -> None:
    engine.errors.clear()
    engine.fire(ruleset)
    expected_calls, expected_errors = oracle.fire(env)
    for name, value in env.items():
        assert same(engine.get(name), value), (name, engine.get(name), value)
    assert len(calls) == len(expected_calls)
    for got, want in zip(calls, expected_calls, strict=True):
        assert got[0] == want[0]
        assert same(got[1], want[1]), (got, want)
    assert {e.rule for e in engine.errors} == {f"r{i}" for i in expected_errors}
    calls.clear()


# ---------------------------------------------------------------------------- random rule sets
NUMERIC = ["A.x", "A.y", "B.z"]
NAMES = [*NUMERIC, "B.s", "A.f"]
STRINGS = ["", "a", "b", "it's", '") (assert (pwned))', "back\\slash", "ü;(x)"]


def string_literal(text: str) -> str:
    return f"'{text}'" if "'" not in text else f'"{text}"'


# Each strategy is made once (functools.cache) and drawn from many times: a strategy made afresh
# for every draw is validated afresh, which took most of the oracle tests' time (the draws are the
# same, made once or afresh).
@functools.cache
def numbers_() -> st.SearchStrategy[str]:
    atoms = st.one_of(
        st.sampled_from([*NUMERIC, "x", "z"]),
        st.sampled_from(["0", "1", "2.5", "-3", "0.1", "1e3"]),
        st.sampled_from(["A.f", "B.s"]),  # type errors on purpose, now and then
    )
    return st.recursive(
        atoms,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["+", "-", "*", "/"]), inner).map(
                lambda t: f"({t[0]} {t[1]} {t[2]})"
            ),
            inner.map(lambda e: f"-{e}" if not e.startswith("-") else e),
        ),
        max_leaves=4,
    )


@functools.cache
def conditions() -> st.SearchStrategy[str]:
    comparison = st.one_of(
        st.tuples(numbers_(), st.sampled_from(["==", "!=", "<", "<=", ">", ">="]), numbers_()).map(
            " ".join
        ),
        st.tuples(
            st.just("B.s"),
            st.sampled_from(["==", "!=", "<", ">="]),
            st.sampled_from(STRINGS).map(string_literal),
        ).map(" ".join),
        st.sampled_from(["A.f", "not A.f", "true", "false", "A.f == true"]),
    )
    return st.recursive(
        comparison,
        lambda inner: st.one_of(
            st.tuples(inner, st.sampled_from(["and", "or"]), inner).map(
                lambda t: f"({t[0]} {t[1]} {t[2]})"
            ),
            inner.map(lambda c: f"not ({c})"),
        ),
        max_leaves=4,
    )


@functools.cache
def actions(index: int) -> st.SearchStrategy[str]:
    assign = st.one_of(
        st.tuples(st.sampled_from(NUMERIC), numbers_()).map(lambda t: f"{t[0]} = {t[1]}"),
        st.tuples(st.just("A.f"), conditions()).map(lambda t: f"A.f = ({t[1]})"),
        st.sampled_from(STRINGS).map(lambda s: f"B.s = {string_literal(s)}"),
    )
    trace = f"Trace.fired({index})"
    return st.lists(assign, max_size=3).map(lambda xs: " and ".join([trace, *xs]))


@st.composite
def rule_sets(draw):
    n = draw(st.integers(1, 6))
    return [f"if {draw(conditions())} then {draw(actions(i))}" for i in range(n)]


values = st.fixed_dictionaries(
    {
        "A.x": st.one_of(st.integers(-4, 4), st.floats(-10, 10), st.just(math.nan)),
        "A.y": st.one_of(st.integers(-4, 4), st.floats(allow_nan=True, allow_infinity=True)),
        "B.z": st.sampled_from([0, 1, -1, 0.5, 2.0]),
        "B.s": st.one_of(
            st.sampled_from(STRINGS),
            st.text(
                st.characters(exclude_categories=("Cs",), exclude_characters="\x00"), max_size=6
            ),
        ),
        "A.f": st.booleans(),
    }
)
