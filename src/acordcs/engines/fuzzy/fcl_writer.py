"""FCL writer: an engine (or several) as FCL text that :func:`acordcs.engines.fuzzy.fcl.read_fcl`
reads back into the same engine, and that jFuzzyLogic reads too when names are plain identifiers
and no hedge other than NOT is used (see docs/fuzzy-engine.md for the extensions).

Rules are written as the engine resolved them: each name is the variable it was bound to. A
:class:`Names` renames what is written (the generator gives FCL identifiers for names such as
``Locomotion.maxSpeed``); by default everything keeps the engine's names."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from acordcs.engines.fuzzy.membership import fmt_number
from acordcs.engines.fuzzy.semantics import AND_OPS
from acordcs.rules import BoolOp, Consequent, Is, Not

if TYPE_CHECKING:
    from acordcs.engines.fuzzy.fuzzy_engine import FuzzyEngine


def format_condition(node: object, *, fcl: bool = False) -> str:
    """A condition tree as text: the paper's syntax, or FCL (upper-case keywords)."""
    kw = str.upper if fcl else str.lower
    if isinstance(node, Is):
        hedges = " ".join(kw(h) if h == "not" else h for h in node.hedges)
        return f"{node.var.text} {kw('is')} {hedges + ' ' if hedges else ''}{node.term.text}"
    if isinstance(node, Not):
        return f"{kw('not')} ({format_condition(node.operand, fcl=fcl)})"
    if isinstance(node, BoolOp):
        right = format_condition(node.right, fcl=fcl)
        if isinstance(node.right, BoolOp):
            right = f"({right})"
        return f"{format_condition(node.left, fcl=fcl)} {kw(node.op)} {right}"
    raise TypeError(f"not a fuzzy condition: {node!r}")


def format_rule(condition: object, actions: Iterable[Consequent], weight: float = 1.0) -> str:
    """A fuzzy rule in the paper's syntax (without label)."""
    then = " and ".join(f"{a.var.text} is {a.term.text}" for a in actions)
    text = f"if {format_condition(condition)} then {then}"
    return text + (f" with {fmt_number(weight)}" if weight != 1.0 else "")


class Names:
    """How names are written: each method takes the engine's name and returns the one to
    write (here, unchanged)."""

    def block(self, name: str) -> str:
        return name

    def variable(self, name: str) -> str:
        return name

    def term(self, variable: str, term: str) -> str:
        return term

    def ruleset(self, name: str) -> str:
        return name

    def label(self, ruleset: str, label: str) -> str:
        return label


def format_resolved(condition: tuple, names: Names) -> str:
    """A resolved condition (``("is", var, hedges, term)``, ``("not", x)``, ``(op, left,
    right)``) as FCL text."""
    kind = condition[0]
    if kind == "is":
        _, var, hedges, term = condition
        words = " ".join(h.upper() if h == "not" else h for h in hedges)
        return f"{names.variable(var)} IS {words + ' ' if words else ''}{names.term(var, term)}"
    if kind == "not":
        return f"NOT ({format_resolved(condition[1], names)})"
    right = format_resolved(condition[2], names)
    if condition[2][0] in ("and", "or"):
        right = f"({right})"
    return f"{format_resolved(condition[1], names)} {kind.upper()} {right}"


def write_fcl(
    engines: FuzzyEngine | dict[str, FuzzyEngine] | list[FuzzyEngine], names: Names | None = None
) -> str:
    """FCL text for one engine or several (one FUNCTION_BLOCK each); ``names``: see
    :class:`Names`."""
    if isinstance(engines, dict):
        engines = list(engines.values())
    elif not isinstance(engines, list | tuple):
        engines = [engines]
    return "\n".join(_write_block(e, names or Names()) for e in engines)


def _write_block(engine: FuzzyEngine, names: Names) -> str:
    f = fmt_number
    v = names.variable
    variables = engine.variables
    concluded: dict[str, str] = {}
    for rs in engine.rulesets():
        for entry in engine.rules(rs):
            for var, _ in entry.consequents:
                concluded.setdefault(var, rs)
    outputs = [
        n
        for n, v in variables.items()
        if n in concluded or v.default is not None or v.keep_last or v.method
    ]
    inputs = [n for n in variables if n not in outputs]
    block = names.block(engine.name) if engine.name else ""
    out = [f"FUNCTION_BLOCK {block}" if block else "FUNCTION_BLOCK", ""]
    if inputs:
        out.append("VAR_INPUT")
        out += [
            f"    {v(n)} : REAL; RANGE := ({f(variables[n].lo)} .. {f(variables[n].hi)});"
            for n in inputs
        ]
        out += ["END_VAR", ""]
    if outputs:
        out.append("VAR_OUTPUT")
        out += [f"    {v(n)} : REAL;" for n in outputs]
        out += ["END_VAR", ""]
    for n in inputs:
        out.append(f"FUZZIFY {v(n)}")
        out += [
            f"    TERM {names.term(n, t)} := {mf.fcl()};" for t, mf in variables[n].terms.items()
        ]
        out += ["END_FUZZIFY", ""]
    for n in outputs:
        var = variables[n]
        sem = engine.semantics_of(concluded[n]) if n in concluded else engine.semantics
        out.append(f"DEFUZZIFY {v(n)}")
        out += [f"    TERM {names.term(n, t)} := {mf.fcl()};" for t, mf in var.terms.items()]
        if var.method or sem.method != "COG":  # COG is what a reader assumes without METHOD
            out.append(f"    METHOD : {var.method or sem.method};")
        if var.keep_last:
            out.append("    DEFAULT := NC;")
        elif var.default is not None:
            out.append(f"    DEFAULT := {f(var.default)};")
        out.append(f"    RANGE := ({f(var.lo)} .. {f(var.hi)});")
        out += ["END_DEFUZZIFY", ""]
    for rs in engine.rulesets():
        sem = engine.semantics_of(rs)
        out.append(f"RULEBLOCK {names.ruleset(rs)}")
        out.append(f"    AND : {sem.and_};")
        if sem.or_ != AND_OPS[sem.and_]:
            out.append(f"    OR : {sem.or_};")
        out += [f"    ACT : {sem.act};", f"    ACCU : {sem.accu};"]
        if sem.samples:
            out.append(f"    (*@acordcs samples={sem.samples} *)")
        for entry in engine.rules(rs):
            then = ", ".join(f"{v(o)} IS {names.term(o, t)}" for o, t in entry.consequents)
            weight = f" WITH {f(entry.weight)}" if entry.weight != 1.0 else ""
            cond = format_resolved(entry.condition, names)
            out.append(f"    RULE {names.label(rs, entry.label)} : IF {cond} THEN {then}{weight};")
        out += ["END_RULEBLOCK", ""]
    out += ["END_FUNCTION_BLOCK", ""]
    return "\n".join(out)
