"""The CLIPS side of the engine: constructs built once per environment, and generated dispatchers.

Everything lives in module MAIN, which exports it all; each rule set is a module importing MAIN.

Values of model variables are defglobals named after the variable (``?*Control.speed*``). Python
pushes the values changed since the last fire and fires a rule set in ONE call (a push function
made for the pattern of changed variables, see :func:`pusher`, or the generic ``acord-fire-set``);
it gets back ``?*acord-out*``, a flat multifield of records in firing order:

- ``idx value``            (idx > 0): variable number idx was assigned value;
- ``-site args..``         (negative): site number ``site`` of a crisp rule (see
  :class:`.records.Sites`) called its operation with ``args``, or assigned its literal;
- ``err rule message``     an evaluation error (rule 0: the engine itself, e.g. the firing limit);
- ``op name nargs args..`` a native rule called an operation by name (``acord-op``).

Variable number 0 is :data:`NUMERIC_FLAG` (see ClipsEngine._sync_numeric).

Why records and not Python callbacks from CLIPS: a callback crossing CLIPS costs microseconds, and a
Python exception inside a CLIPS run halts the run (clipspy issue #48); records keep Python outside the
run, so a raising operation cannot disturb the rules, and re-entering the engine is safe.

Crisp rules fire at most once per fire: each has a global holding the number of the fire it last
fired in. They match ``(acord-eval (set S))``, asserted at the start of a fire, and one
``(acord-var (i k))`` fact per variable k their condition reads (asserted when a first rule reads
k). A firing that changed variable k re-asserts that fact after its last action, so CLIPS evaluates
again the rules reading k, and only those, on the new value (chaining to quiescence at the cost of
the rules actually affected). Native rules match ``(acord-fire)``, asserted for the duration of a
fire of a set that has native rules.
"""

from __future__ import annotations

from collections.abc import Sequence

from acordcs.engines.clips.clips_compiler import NUMERIC_FLAG, Target, assignment, quote, touch

_ORDER_TEMPLATE = """
(deffunction MAIN::acord-{name} (?a ?b)
  (if (and (numberp ?a) (numberp ?b))
   then (and (= ?a ?a) (= ?b ?b) ({op} ?a ?b))
   else (if (and (stringp ?a) (stringp ?b))
         then ({op} (str-compare ?a ?b) 0)
         else (acord-fail (str-cat "'{sym}' needs two numbers or two strings, not "
                                   (acord-kind ?a) " and " (acord-kind ?b))))))
"""

# CLIPS integers are C long longs and wrap silently past 2**63: integer results are checked.
# Sums and differences exactly (by sign); products through their float value, which is within
# 2048 of the exact one below 2**64, so the bound 2**63 - 4096 misses no overflow (it also
# refuses the products within 4096 of the limit). No division is used: LLONG_MIN / -1 traps in C.
_OVERFLOW = "(acord-fail \"integer overflow: '{sym}' leaves the 64-bit range; use a float\") 0"
_INT_CHECK = {
    "+": "(and (eq (>= ?a 0) (>= ?b 0)) (neq (>= ?r 0) (>= ?a 0)))",
    "-": "(and (neq (>= ?a 0) (>= ?b 0)) (neq (>= ?r 0) (>= ?a 0)))",
    "*": "(>= (abs (* (float ?a) (float ?b))) 9223372036854771712.0)",
}
_ARITH_TEMPLATE = """
(deffunction MAIN::acord-{name} (?a ?b)
  (if (and (integerp ?a) (integerp ?b))
   then (bind ?r ({op} ?a ?b)) (if {check} then {overflow} else ?r)
   else (if (and (numberp ?a) (numberp ?b))
         then ({op} ?a ?b)
         else (acord-fail (str-cat "'{sym}' needs two numbers, not " (acord-kind ?a) " and " (acord-kind ?b)))
              0)))
"""

# NUMERIC_FLAG (compiler.py) is pushed by the engine as variable number 0.
__all__ = [
    "FIRE",
    "NUMERIC_FLAG",
    "RUN",
    "assign_dispatcher",
    "fixed_constructs",
    "pusher",
    "put_dispatcher",
]

_FIXED = [
    "(defmodule MAIN (export ?ALL))",
    "(deftemplate MAIN::acord-fire (slot set))",
    "(deftemplate MAIN::acord-eval (slot set))",
    "(deftemplate MAIN::acord-var (slot i))",
    """(defglobal MAIN
        ?*acord-out* = (create$)
        ?*acord-err* = FALSE
        ?*acord-tick* = FALSE
        ?*acord-limit* = 10000
        ?*acord-cycle* = 0
        ?*acord-num* = FALSE)""",
    """(deffunction MAIN::acord-kind (?x)
        (if (numberp ?x) then "number"
         else (if (stringp ?x) then "string"
         else (if (or (eq ?x TRUE) (eq ?x FALSE)) then "boolean"
         else (if (eq ?x nil) then "unset" else (lowcase (str-cat (type ?x))))))))""",
    """(deffunction MAIN::acord-fail (?message)
        (if (not ?*acord-err*) then (bind ?*acord-err* ?message))
        FALSE)""",
    # The error flag is FALSE whenever an evaluation starts: whoever reads it set, clears it.
    """(deffunction MAIN::acord-report (?rule)
        (bind ?*acord-out* (create$ ?*acord-out* err ?rule ?*acord-err*))
        (bind ?*acord-err* FALSE)
        FALSE)""",
    """(deffunction MAIN::acord-bool (?x)
        (if (or (eq ?x TRUE) (eq ?x FALSE)) then ?x
         else (acord-fail (str-cat "a condition needs true or false, not " (acord-kind ?x)))))""",
    """(deffunction MAIN::acord-eq (?a ?b)
        (if (and (numberp ?a) (numberp ?b)) then (= ?a ?b) else (eq ?a ?b)))""",
    "(deffunction MAIN::acord-ne (?a ?b) (not (acord-eq ?a ?b)))",
    """(deffunction MAIN::acord-div (?a ?b)
        (if (and (numberp ?a) (numberp ?b))
         then (if (= ?b 0) then (acord-fail "division by zero") 0 else (/ ?a ?b))
         else (acord-fail (str-cat "'/' needs two numbers, not " (acord-kind ?a) " and " (acord-kind ?b)))
              0))""",
    """(deffunction MAIN::acord-neg (?a)
        (if (and (integerp ?a) (< ?a -9223372036854775807))
         then (acord-fail "integer overflow: '-' leaves the 64-bit range; use a float") 0
         else (if (numberp ?a) then (* -1 ?a)
         else (acord-fail (str-cat "'-' needs a number, not " (acord-kind ?a))) 0)))""",
    """(deffunction MAIN::acord-op (?name $?args)
        (bind ?*acord-out* (create$ ?*acord-out* op ?name (length$ ?args) ?args)))""",
    # Leftovers of a fire interrupted by a CLIPS error must not leak into the next fire; returns
    # the records of what happened before the error.
    """(deffunction MAIN::acord-cleanup ()
        (clear-focus-stack)
        (do-for-all-facts ((?f acord-fire)) TRUE (retract ?f))
        (do-for-all-facts ((?f acord-eval)) TRUE (retract ?f))
        (bind ?*acord-tick* FALSE)
        (bind ?*acord-err* FALSE)
        ?*acord-out*)""",
]

# Defined after the dispatchers exist (they call acord-put).
FIRE = """(deffunction MAIN::acord-fire-set (?set ?natives $?pairs)
  (bind ?n (length$ ?pairs))
  (bind ?k 1)
  (while (< ?k ?n) (acord-put (nth$ ?k ?pairs) (nth$ (+ ?k 1) ?pairs)) (bind ?k (+ ?k 2)))
  (acord-run ?set ?natives))"""

# The focus stack is empty between fires (run empties it; the limit and acord-cleanup clear it).
RUN = """(deffunction MAIN::acord-run (?set ?natives)
  (bind ?*acord-out* (create$))
  (bind ?*acord-cycle* (+ ?*acord-cycle* 1))
  (bind ?started (if ?natives then (assert (acord-fire (set ?set))) else FALSE))
  (bind ?*acord-tick* (assert (acord-eval (set ?set))))
  (focus ?set)
  (run ?*acord-limit*)
  (if (get-focus) then
      (bind ?*acord-out* (create$ ?*acord-out* err 0 "limit"))
      (clear-focus-stack))
  (if (fact-existp ?*acord-tick*) then (retract ?*acord-tick*))
  (bind ?*acord-tick* FALSE)
  (if (and ?started (fact-existp ?started)) then (retract ?started))
  ?*acord-out*)"""


def fixed_constructs() -> list[str]:
    """The constructs every environment starts with, in build order."""
    ops = [
        _ORDER_TEMPLATE.format(name=name, op=op, sym=sym)
        for name, op, sym in (
            ("lt", "<", "<"),
            ("le", "<=", "<="),
            ("gt", ">", ">"),
            ("ge", ">=", ">="),
        )
    ]
    ops += [
        _ARITH_TEMPLATE.format(
            name=name, op=op, sym=op, check=_INT_CHECK[op], overflow=_OVERFLOW.format(sym=op)
        )
        for name, op in (("add", "+"), ("sub", "-"), ("mul", "*"))
    ]
    return _FIXED + ops


def _bisect(globals_: Sequence[str], low: int, high: int) -> str:
    # A balanced tree of ifs: pushing a value costs O(log n) tests, not O(n).
    if low == high:
        return f"(bind {globals_[low]} ?v)"
    mid = (low + high) // 2
    return f"(if (<= ?i {mid}) then {_bisect(globals_, low, mid)} else {_bisect(globals_, mid + 1, high)})"


def pusher(name: str, module: str, natives: bool, globals_: Sequence[str]) -> str:
    """A push function for one pattern of changed variables: it takes just their values, binds
    them and fires ``module``; half the arguments of (index, value) pairs, and no dispatch.

    It does what ``acord-run`` does, inline and specialised for ``module`` (a deffunction call less
    per fire). ``natives``: assert ``(acord-fire)`` (only native rules match it: a set without any
    skips it); without native rules nothing else can retract the ``acord-eval`` fact."""
    params = " ".join(f"?v{i}" for i in range(len(globals_)))
    binds = "".join(f" (bind {g} ?v{i})" for i, g in enumerate(globals_))
    started = f" (bind ?acord-started (assert (acord-fire (set {module}))))" if natives else ""
    if natives:
        done = (
            " (if (fact-existp ?acord-tick) then (retract ?acord-tick))"
            " (if (fact-existp ?acord-started) then (retract ?acord-started))"
        )
    else:
        done = " (retract ?acord-tick)"
    return (
        f"(deffunction MAIN::{name} ({params}){binds}"
        " (bind ?*acord-out* (create$)) (bind ?*acord-cycle* (+ ?*acord-cycle* 1))"
        f"{started} (bind ?acord-tick (assert (acord-eval (set {module}))))"
        f" (focus {module}) (run ?*acord-limit*)"
        ' (if (get-focus) then (bind ?*acord-out* (create$ ?*acord-out* err 0 "limit")) (clear-focus-stack))'
        f"{done} ?*acord-out*)"
    )


def put_dispatcher(globals_: Sequence[str]) -> str:
    """``(acord-put i v)``: bind ``globals_[i]`` (variable number i; 0 is :data:`NUMERIC_FLAG`) to v."""
    return f"(deffunction MAIN::acord-put (?i ?v) {_bisect(globals_, 0, len(globals_) - 1)})"


def assign_dispatcher(names: Sequence[str], targets: Sequence[Target]) -> str:
    """``(acord-assign "Element.attr" v)`` for native rules: assign by name, as a crisp rule would."""
    cases = " ".join(
        f"(case {quote(name)} then {assignment(target, '?v', touch(target.index))})"
        for name, target in zip(names, targets, strict=True)
    )
    unknown = '(acord-fail (str-cat "acord-assign: unknown variable " ?name)) (acord-report 0)'
    return (
        "(deffunction MAIN::acord-assign (?name ?v)"
        f' (if (multifieldp ?v) then (acord-fail "acord-assign: a value must be one field") (acord-report 0)'
        f" else (switch ?name {cases} (default {unknown}))))"
    )
