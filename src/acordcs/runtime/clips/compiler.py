"""Crisp rules, as parsed by :func:`acordcs.metamodel.rules.parse_rule`, compiled to CLIPS ``defrule`` text.

A crisp rule ``retry: if Control.speed == 0 and Recovery.zeros <= 3 then Recovery.recover()``, the
second of rule set ``recovery``, becomes (one line, wrapped here)::

    (defrule recovery::retry (declare (salience 9998))
      (acord-eval (set recovery)) (acord-var (i 1)) (acord-var (i 2))
      (test (and (<> ?*acord-f2* ?*acord-cycle*)
                 (if (and (if (numberp ?*Control.speed*) then (= ?*Control.speed* 0.0)
                              else (acord-eq ?*Control.speed* 0.0))
                          (if (numberp ?*Recovery.zeros*)
                           then (and (= ?*Recovery.zeros* ?*Recovery.zeros*) (<= ?*Recovery.zeros* 3.0))
                           else (acord-le ?*Recovery.zeros* 3.0)))
                  then (or (not ?*acord-err*) (acord-report 2))
                  else (if ?*acord-err* then (acord-report 2) FALSE else FALSE))))
      =>
      (bind ?*acord-f2* ?*acord-cycle*)
      (bind ?acord-a (create$ ))
      (if ?*acord-err* then (acord-report 2)
       else (bind ?*acord-out* (create$ ?*acord-out* -1 2 0 ?acord-a))))

Every operator is checked (deffunctions of the prelude, with the number case inline), so a bad value
(a string where a number is needed, a division by zero) is an evaluation error reported back to
Python, not a CLIPS error that halts the run. Every literal that reaches CLIPS text is escaped by
:func:`quote` or checked finite; values themselves never appear in CLIPS text at all.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from acordcs.metamodel.rules import (
    Arith,
    Assign,
    BoolOp,
    Call,
    Compare,
    Const,
    Name,
    Neg,
    Not,
    Rule,
    VarRef,
)
from acordcs.runtime.engine import RuleError

_COMPARE = {
    "==": "acord-eq",
    "!=": "acord-ne",
    "<": "acord-lt",
    "<=": "acord-le",
    ">": "acord-gt",
    ">=": "acord-ge",
}
_ARITH = {"+": "acord-add", "-": "acord-sub", "*": "acord-mul", "/": "acord-div"}


_INLINE = {"==": "=", "!=": "<>"}


def _all(tests: list[str]) -> str:
    return tests[0] if len(tests) == 1 else f"(and {' '.join(tests)})"


def _plain(node: object) -> bool:
    return isinstance(node, VarRef) or (
        isinstance(node, Const) and not isinstance(node.value, bool | str)
    )


def quote(text: str) -> str:
    """``text`` as a CLIPS string literal: only backslash and double quote are special inside one."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


@dataclass(frozen=True, slots=True)
class Target:
    """A resolved variable: its 1-based number and the CLIPS global holding its value."""

    index: int
    global_name: str


# Resolvers raise LookupError with a message saying what to do; the compiler adds where.
VariableResolver = Callable[[Name], Target]
OperationResolver = Callable[[Name, int], int]


@dataclass(frozen=True, slots=True)
class CompiledRule:
    fired_global: str
    constructs: tuple[str, ...]


class _Compiler:
    def __init__(
        self,
        ruleset: str,
        label: str,
        rule_id: int,
        variables: VariableResolver,
        operations: OperationResolver,
    ):
        self.ruleset = ruleset
        self.label = label
        self.rule_id = rule_id
        self.variables = variables
        self.operations = operations
        self.seen: set[int] = set()

    def error(self, message: str, column: int | None) -> RuleError:
        return RuleError(message, ruleset=self.ruleset, rule=self.label, column=column or None)

    def variable(self, name: Name) -> Target:
        try:
            target = self.variables(name)
        except LookupError as err:
            raise self.error(str(err.args[0]), name.column) from None
        self.seen.add(target.index)
        return target

    # ------------------------------------------------------------------------------ expressions
    def value(self, node: object) -> str:
        """CLIPS text computing the value of ``node`` (any type)."""
        if isinstance(node, Const):
            return self.constant(node)
        if isinstance(node, VarRef):
            return self.variable(node.var).global_name
        if isinstance(node, Arith):
            return self.binary(node, _ARITH[node.op])
        if isinstance(node, Neg):
            return f"(acord-neg {self.value(node.operand)})"
        if isinstance(node, Compare | BoolOp | Not):
            return self.condition(node)
        raise self.error(f"unsupported expression {type(node).__name__}", first_column(node))

    def constant(self, node: Const) -> str:
        value = node.value
        if isinstance(value, bool):
            return "TRUE" if value else "FALSE"
        if isinstance(value, str):
            return quote(value)
        if isinstance(value, int) and abs(value) < 2**63:
            return repr(value)  # CLIPS integers: a count stays a count (0 + 1 is 1, not 1.0)
        if not math.isfinite(float(value)):
            raise self.error(
                f"the number {value} is out of range; write a finite number", node.column
            )
        return repr(float(value))

    def binary(self, node: Compare | Arith, function: str) -> str:
        """A checked operation; on plain operands (variables, numbers) with the number case inline.

        The inline case skips a deffunction call, a third of a condition's cost: it is the same
        test the deffunction makes first (numbers, and NaN never ordered), so results are identical.
        """
        left, right = self.value(node.left), self.value(node.right)
        checked = f"({function} {left} {right})"
        if not (_plain(node.left) and _plain(node.right)):
            return checked
        variables = [
            t for t, n in ((left, node.left), (right, node.right)) if isinstance(n, VarRef)
        ]
        if not variables:
            return checked
        guard = [f"(numberp {v})" for v in variables]
        op = node.op
        if op in ("<", "<=", ">", ">="):
            fast = _all([*(f"(= {v} {v})" for v in variables), f"({op} {left} {right})"])
        elif op == "/":
            guard.append(f"(<> {right} 0)")
            fast = f"(/ {left} {right})"
        else:
            fast = f"({_INLINE.get(op, op)} {left} {right})"
        return f"(if {_all(guard)} then {fast} else {checked})"

    def condition(self, node: object) -> str:
        """CLIPS text computing TRUE or FALSE (or flagging an evaluation error)."""
        if isinstance(node, Compare):
            return self.binary(node, _COMPARE[node.op])
        if isinstance(node, BoolOp):
            return f"({node.op} {self.condition(node.left)} {self.condition(node.right)})"
        if isinstance(node, Not):
            return f"(not {self.condition(node.operand)})"
        if isinstance(node, Const) and isinstance(node.value, bool):
            return self.constant(node)
        if isinstance(node, VarRef):
            return f"(acord-bool {self.variable(node.var).global_name})"
        what = "text" if isinstance(node, Const) and isinstance(node.value, str) else "a number"
        raise self.error(
            f"a condition must be true or false, but this part is {what}; compare it, e.g. 'x > 0'",
            first_column(node),
        )

    # ---------------------------------------------------------------------------------- actions
    def action(self, node: object) -> str:
        rid = self.rule_id
        if isinstance(node, Assign):
            target = self.variable(node.var)
            return (
                f"(bind ?acord-v {self.value(node.value)})"
                f" (if ?*acord-err* then (acord-report {rid})"
                f" else {assignment(target, '?acord-v', f'?acord-t{target.index}')})"
            )
        if isinstance(node, Call):
            try:
                op = self.operations(node.target, len(node.args))
            except LookupError as err:
                raise self.error(str(err.args[0]), node.target.column) from None
            args = " ".join(self.value(a) for a in node.args)
            return (
                f"(bind ?acord-a (create$ {args}))"
                f" (if ?*acord-err* then (acord-report {rid}) else"
                f" (bind ?*acord-out* (create$ ?*acord-out* -{op} {rid} {len(node.args)} ?acord-a)))"
            )
        raise self.error(f"unsupported action {type(node).__name__}", first_column(node))


def touch(index: int) -> str:
    """Re-assert variable ``index``'s ``acord-var`` fact: CLIPS evaluates again the rules reading it."""
    fact = f"?*acord-vf{index}*"
    return (
        f"(if (fact-existp {fact}) then (retract {fact}))"
        f" (bind {fact} (assert (acord-var (i {index}))))"
    )


def assignment(target: Target, value: str, changed: str | None = None) -> str:
    """Record the assignment for Python, bind the global and, when the value changed, either
    :func:`touch` the variable at once or, given ``changed`` (a local variable), set that flag: a
    crisp rule touches what it changed after its last action, so that no rule is evaluated on the
    values in between two actions of a firing."""
    i, glob = target.index, target.global_name
    after = f"(bind {changed} TRUE)" if changed else touch(i)
    # neq is exact (1 vs 1.0 differ): Python hears of every change of value or type, and nothing else.
    # Inline rather than deffunctions: this runs on every firing, and a call costs as much as the work.
    return (
        f"(if (neq {glob} {value}) then (bind ?*acord-out* (create$ ?*acord-out* {i} {value}))"
        f" (bind ?acord-same (acord-eq {glob} {value})) (bind {glob} {value})"
        f" (if (not ?acord-same) then {after}))"
    )


def checked(rule_id: int, condition: str) -> str:
    """The condition's truth, FALSE after an evaluation error, which is then reported (and cleared).

    ``condition`` comes from :meth:`_Compiler.condition`, so it is TRUE or FALSE, never another value.
    """
    report = f"(acord-report {rule_id})"
    return (
        f"(if {condition} then (or (not ?*acord-err*) {report})"
        f" else (if ?*acord-err* then {report} FALSE else FALSE))"
    )


def first_column(node: object) -> int | None:
    """The column of the first name inside ``node``: the parser gives columns to names only."""
    stack = [node]
    while stack:
        n = stack.pop()
        if isinstance(n, VarRef):
            return n.var.column
        if isinstance(n, Call):
            return n.target.column
        if isinstance(n, Assign):
            return n.var.column
        if isinstance(n, BoolOp | Compare | Arith):
            stack.extend((n.right, n.left))
        elif isinstance(n, Not | Neg):
            stack.append(n.operand)
    return None


def compile_rule(
    rule: Rule,
    *,
    ruleset: str,
    module: str,
    label: str,
    rule_id: int,
    salience: int,
    variables: VariableResolver,
    operations: OperationResolver,
) -> CompiledRule:
    """The CLIPS constructs of one crisp rule. Raises RuleError naming the set, the rule and the column."""
    c = _Compiler(ruleset, label, rule_id, variables, operations)
    condition = c.condition(rule.condition)
    # One pattern per variable the condition reads: Rete re-evaluates this rule when one changes.
    reads = " ".join(f"(acord-var (i {i}))" for i in sorted(c.seen))
    actions = " ".join(c.action(a) for a in rule.actions)
    written = sorted({c.variable(a.var).index for a in rule.actions if isinstance(a, Assign)})
    flags = " ".join(f"(bind ?acord-t{i} FALSE)" for i in written)
    touches = " ".join(f"(if ?acord-t{i} then {touch(i)})" for i in written)
    fired = f"?*acord-f{rule_id}*"
    defrule = (
        f"(defrule {module}::{label} (declare (salience {salience}))"
        f" (acord-eval (set {module})){' ' + reads if reads else ''}"
        f" (test (and (<> {fired} ?*acord-cycle*) {checked(rule_id, condition)}))"
        f" => {' '.join(part for part in (f'(bind {fired} ?*acord-cycle*)', flags, actions, touches) if part)})"
    )
    return CompiledRule(fired, (f"(defglobal MAIN {fired} = 0)", defrule))
