"""Crisp rules, as parsed by :func:`acordcs.rules.parser.parse_rule`, compiled to CLIPS ``defrule`` text.

A crisp rule ``retry: if Control.speed == 0 and Recovery.zeros <= 3 then Recovery.recover()``, the
second of rule set ``recovery``, both variables declared as numbers, becomes (one line, wrapped)::

    (defrule recovery::retry (declare (salience 9998))
      (acord-var (i 1)) (acord-var (i 2)) (acord-eval (set recovery))
      (test (if ?*acord-num*
             then (and (= ?*Control.speed* 0) (not (> ?*Recovery.zeros* 3))
                       (<> ?*acord-f2* ?*acord-cycle*))
             else (and (<> ?*acord-f2* ?*acord-cycle*)
                       (if (and (if (numberp ?*Control.speed*) then (= ?*Control.speed* 0)
                                    else (acord-eq ?*Control.speed* 0))
                                (if (numberp ?*Recovery.zeros*) then (not (> ?*Recovery.zeros* 3))
                                    else (acord-le ?*Recovery.zeros* 3)))
                        then (or (not ?*acord-err*) (acord-report 2))
                        else (and ?*acord-err* (acord-report 2))))))
      =>
      (bind ?*acord-f2* ?*acord-cycle*)
      (bind ?*acord-out* (create$ ?*acord-out* -1)))

Every operator is checked (deffunctions of the prelude, with the number case inline), so a bad value
(a string where a number is needed, a division by zero, an integer result past 64 bits, which
CLIPS itself would wrap) is an evaluation error reported back to
Python, not a CLIPS error that halts the run. Every literal that reaches CLIPS text is escaped by
:func:`quote` or checked finite; values themselves never appear in CLIPS text at all.

The first branch is numeric mode (:data:`NUMERIC_FLAG`): while every variable declared as a number
holds a number, a comparison of such variables and number literals (no arithmetic) cannot fail, and computes what
the checked branch computes, without a check. ``(acord-eval ...)`` comes last: asserting it at
each fire then joins it with one stored partial match per rule, not with each ``acord-var``.

What is left out when it cannot matter (each saves CLIPS work on every fire):

- a condition that cannot fail (``==``/``!=`` between variables and literals, ``and``/``or``/``not``
  of those) has no error wrapper, and tests its "fired in this fire" global last, after the
  condition (the condition is usually false, so the global is usually not read);
- an action whose values cannot fail (literals, variables) has no error check, and a call records
  its arguments directly instead of through a local multifield;
- the last action of a rule, when it assigns, re-asserts its variable's fact at once (no flag):
  nothing of the firing comes after it.

A call, or the assignment of a literal, is recorded for Python as one negative number, its site in
:class:`.records.Sites`, which holds what Python needs (the operation, the rule, the literal).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from acordcs.engines.clips.records import Sites, python_constant
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import (
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
    depth_message,
    rule_too_deep,
)

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
_OVERFLOWS = frozenset("+-*")  # integer results past 2**63 wrap in CLIPS: see prelude
# TRUE only while every variable declared as a number holds one (the engine keeps it so, and a
# rule assigning something else to such a variable clears it): see compile_rule.
NUMERIC_FLAG = "?*acord-num*"
# CLIPS computes (< a b) as "not a >= b", so on NaN every ordering is TRUE. The negation of the
# opposite ordering is IEEE's answer (false on NaN) in two calls, where guarding with (= a a) took three.
_NEGATED = {"<": ">=", "<=": ">", ">": "<=", ">=": "<"}


def _all(tests: list[str]) -> str:
    return tests[0] if len(tests) == 1 else f"(and {' '.join(tests)})"


def _and_then(condition: str, test: str) -> str:
    """``(and condition test)``, flattened when ``condition`` is itself an ``and`` (a call less)."""
    if condition.startswith("(and "):
        return f"{condition[:-1]} {test})"
    return f"(and {condition} {test})"


def _plain(node: object) -> bool:
    return isinstance(node, VarRef) or (
        isinstance(node, Const) and not isinstance(node.value, bool | str)
    )


def _numeric(node: object) -> bool:
    """Whether ``node``'s value is a number whenever its evaluation did not fail."""
    if isinstance(node, Const):
        return isinstance(node.value, int | float) and not isinstance(node.value, bool)
    return isinstance(node, Arith | Neg)  # the checked forms return 0 on failure, a number too


def fails(node: object, condition: bool = False) -> bool:
    """Whether evaluating ``node`` (as a condition, or as a value) can be an evaluation error.

    Only the checked operations fail: orderings, arithmetic, and a variable used as a condition
    (it must hold a boolean). ``==``/``!=`` accept any two values; literals and variables as values
    cannot fail. What cannot fail needs no error wrapper in CLIPS.
    """
    if isinstance(node, Const):
        return False
    if isinstance(node, VarRef):
        return condition
    if isinstance(node, Compare):
        return node.op not in _INLINE or fails(node.left) or fails(node.right)
    if isinstance(node, BoolOp):
        return fails(node.left, True) or fails(node.right, True)
    if isinstance(node, Not):
        return fails(node.operand, True)
    return True


def quote(text: str) -> str:
    """``text`` as a CLIPS string literal: only backslash and double quote are special inside one."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


@dataclass(frozen=True, slots=True)
class Target:
    """A resolved variable: its 1-based number and the CLIPS global holding its value.

    ``numeric``: declared as a number, so it holds a number whenever :data:`NUMERIC_FLAG` is TRUE.
    """

    index: int
    global_name: str
    numeric: bool = False


# Resolvers raise LookupError with a message saying what to do; the compiler adds where.
VariableResolver = Callable[[Name], Target]
OperationResolver = Callable[[Name, int], int]


@dataclass(frozen=True, slots=True)
class CompiledRule:
    fired_global: str
    constructs: tuple[str, ...]
    reads: tuple[int, ...] = ()  # the variables whose acord-var facts the rule matches


class _Compiler:
    def __init__(
        self,
        ruleset: str,
        label: str,
        rule_id: int,
        variables: VariableResolver,
        operations: OperationResolver,
        sites: Sites,
    ):
        self.ruleset = ruleset
        self.label = label
        self.rule_id = rule_id
        self.variables = variables
        self.operations = operations
        self.sites = sites
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
        if node.op in _OVERFLOWS or not (_plain(node.left) and _plain(node.right)):
            return checked  # + - * on integers may overflow: only the deffunction checks that
        variables = [
            t for t, n in ((left, node.left), (right, node.right)) if isinstance(n, VarRef)
        ]
        if not variables:
            return checked
        guard = [f"(numberp {v})" for v in variables]
        op = node.op
        if op in _NEGATED:
            fast = f"(not ({_NEGATED[op]} {left} {right}))"
        elif op == "/":
            guard.append(f"(<> {right} 0)")
            fast = f"(/ {left} {right})"
        else:
            fast = f"({_INLINE.get(op, op)} {left} {right})"
        return f"(if {_all(guard)} then {fast} else {checked})"

    def fast_value(self, node: object) -> str | None:
        """CLIPS text of a number computed without any check, or None: a numeric variable or a
        number literal; arithmetic is never unchecked (division by zero, integer overflow)."""
        if isinstance(node, Const):
            return self.constant(node) if _numeric(node) else None
        if isinstance(node, VarRef):
            target = self.variable(node.var)
            return target.global_name if target.numeric else None
        # No arithmetic: + - * and negation of integers may overflow, which only the checked
        # deffunctions detect (and report, which this branch cannot)
        return None

    def fast_condition(self, node: object) -> str | None:
        """The condition without type checks, valid while :data:`NUMERIC_FLAG` is TRUE, or None
        when some part of it needs them. It cannot fail, so it needs no error wrapper either."""
        if isinstance(node, Compare):
            left, right = self.fast_value(node.left), self.fast_value(node.right)
            if not (left and right):
                return None
            if node.op in _NEGATED:
                return f"(not ({_NEGATED[node.op]} {left} {right}))"
            return f"({_INLINE[node.op]} {left} {right})"
        if isinstance(node, BoolOp):
            left, right = self.fast_condition(node.left), self.fast_condition(node.right)
            return f"({node.op} {left} {right})" if left and right else None
        if isinstance(node, Not):
            operand = self.fast_condition(node.operand)
            return f"(not {operand})" if operand else None
        if isinstance(node, Const) and isinstance(node.value, bool):
            return self.constant(node)
        return None

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
    def action(self, node: object, touch_now: bool) -> str:
        """One action. ``touch_now``: an assignment re-asserts its variable's fact at once (it is
        the rule's last action), else it sets the local flag the rule's end reads."""
        rid = self.rule_id
        if isinstance(node, Assign):
            target = self.variable(node.var)
            after = touch(target.index) if touch_now else f"(bind ?acord-t{target.index} TRUE)"
            numeric = _numeric(node.value)
            value = self.value(node.value)
            if isinstance(node.value, Const | VarRef):  # one field, no evaluation: used as is
                check = numeric_check(target, value, numeric or self.fast_value(node.value))
                record = None
                if isinstance(node.value, Const):  # Python knows the value: its site says it all
                    site = self.sites.constant(target.index, python_constant(node.value.value))
                    record = f"-{site}"
                return check + assignment(target, value, after, numeric, record)
            body = numeric_check(target, "?acord-v", numeric) + assignment(
                target, "?acord-v", after, numeric
            )
            if not fails(node.value):
                return f"(bind ?acord-v {value}) {body}"
            return (
                f"(bind ?acord-v {value}) (if ?*acord-err* then (acord-report {rid}) else {body})"
            )
        if isinstance(node, Call):
            try:
                op = self.operations(node.target, len(node.args))
            except LookupError as err:
                raise self.error(str(err.args[0]), node.target.column) from None
            site = self.sites.call(op, rid, len(node.args))
            args = "".join(f" {self.value(a)}" for a in node.args)
            if not any(fails(a) for a in node.args):
                return f"(bind ?*acord-out* (create$ ?*acord-out* -{site}{args}))"
            return (
                f"(bind ?acord-a (create${args}))"
                f" (if ?*acord-err* then (acord-report {rid}) else"
                f" (bind ?*acord-out* (create$ ?*acord-out* -{site} ?acord-a)))"
            )
        raise self.error(f"unsupported action {type(node).__name__}", first_column(node))


def touch(index: int) -> str:
    """Re-assert variable ``index``'s ``acord-var`` fact: CLIPS evaluates again the rules reading it.

    The fact only exists once a crisp rule reads the variable (until then its global is FALSE):
    re-asserting a fact nothing matches would be work for nothing.
    """
    fact = f"?*acord-vf{index}*"
    return (
        f"(if {fact} then (if (fact-existp {fact}) then (retract {fact}))"
        f" (bind {fact} (assert (acord-var (i {index})))))"
    )


def assignment(
    target: Target, value: str, after: str, numeric: bool = False, record: str | None = None
) -> str:
    """Record the assignment for Python, bind the global and, when the value changed, run ``after``
    (:func:`touch`, or setting a flag the rule's end reads, so that no rule is evaluated on the
    values in between two actions of a firing). ``numeric``: ``value`` is surely a number, so the
    value comparison is inline rather than ``acord-eq``. ``record``: what tells Python (by
    default ``index value``; a constant's site number says both)."""
    i, glob = target.index, target.global_name
    record = record or f"{i} {value}"
    # neq is exact (1 vs 1.0 differ): Python hears of every change of value or type, and nothing else.
    # Inline rather than deffunctions: this runs on every firing, and a call costs as much as the work.
    same = f"(and (numberp {glob}) (= {glob} {value}))" if numeric else f"(acord-eq {glob} {value})"
    return (
        f"(if (neq {glob} {value}) then (bind ?*acord-out* (create$ ?*acord-out* {record}))"
        f" (if {same} then (bind {glob} {value}) else (bind {glob} {value}) {after}))"
    )


def numeric_check(target: Target, value: str, surely_numeric: object) -> str:
    """Before assigning ``value`` to a numeric variable: clear :data:`NUMERIC_FLAG` if it is not a
    number (no check when it surely is: a number literal, arithmetic, a numeric variable)."""
    if not target.numeric or surely_numeric:
        return ""
    return f"(if (not (numberp {value})) then (bind {NUMERIC_FLAG} FALSE)) "


def checked(rule_id: int, condition: str) -> str:
    """The condition's truth, FALSE after an evaluation error, which is then reported (and cleared).

    ``condition`` comes from :meth:`_Compiler.condition`, so it is TRUE or FALSE, never another value.
    ``acord-report`` returns FALSE.
    """
    report = f"(acord-report {rule_id})"
    return (
        f"(if {condition} then (or (not ?*acord-err*) {report}) else (and ?*acord-err* {report}))"
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
    sites: Sites,
) -> CompiledRule:
    """The CLIPS constructs of one crisp rule. Raises RuleError naming the set, the rule and the column."""
    c = _Compiler(ruleset, label, rule_id, variables, operations, sites)
    if rule_too_deep(rule):  # a tree built in Python: the parser refuses these in text
        raise c.error(depth_message(), None)
    condition = c.condition(rule.condition)
    reads = sorted(c.seen)
    patterns = "".join(f" (acord-var (i {i}))" for i in reads)
    fired = f"?*acord-f{rule_id}*"
    unfired = f"(<> {fired} ?*acord-cycle*)"
    if fails(rule.condition, True):
        test = f"(and {unfired} {checked(rule_id, condition)})"
    else:  # nothing to report: the condition first, the fired check only when it holds
        test = _and_then(condition, unfired)
    fast = c.fast_condition(rule.condition) if reads else None
    if fast:  # one flag read instead of a type check per operand and the error wrapper
        test = f"(if {NUMERIC_FLAG} then {_and_then(fast, unfired)} else {test})"
    actions = list(rule.actions)
    assigned = [c.variable(a.var).index for a in actions if isinstance(a, Assign)]
    touch_last = (
        bool(actions) and isinstance(actions[-1], Assign) and assigned.count(assigned[-1]) == 1
    )
    flagged = sorted(set(assigned[:-1] if touch_last else assigned))
    body = [f"(bind {fired} ?*acord-cycle*)"]
    body += [f"(bind ?acord-t{i} FALSE)" for i in flagged]
    body += [c.action(a, touch_last and n == len(actions) - 1) for n, a in enumerate(actions)]
    body += [f"(if ?acord-t{i} then {touch(i)})" for i in flagged]
    defrule = (
        f"(defrule {module}::{label} (declare (salience {salience}))"
        f"{patterns} (acord-eval (set {module})) (test {test}) => {' '.join(body)})"
    )
    return CompiledRule(fired, (f"(defglobal MAIN {fired} = 0)", defrule), tuple(reads))
