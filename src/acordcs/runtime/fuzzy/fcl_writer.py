"""FCL writer: an engine (or several) as FCL text that :func:`acordcs.runtime.fuzzy.fcl.read_fcl`
reads back into the same engine, and that jFuzzyLogic reads too when names are plain identifiers
and no hedge other than NOT is used (see docs/fuzzy-engine.md for the extensions)."""

from __future__ import annotations

from collections.abc import Iterable
from typing import TYPE_CHECKING

from acordcs.rules import BoolOp, Consequent, Is, Not
from acordcs.runtime.fuzzy.membership import fmt_number
from acordcs.runtime.fuzzy.semantics import AND_OPS

if TYPE_CHECKING:
    from acordcs.runtime.fuzzy.fuzzy_engine import FuzzyEngine


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


def write_fcl(engines: FuzzyEngine | dict[str, FuzzyEngine] | list[FuzzyEngine]) -> str:
    """FCL text for one engine or several (one FUNCTION_BLOCK each)."""
    if isinstance(engines, dict):
        engines = list(engines.values())
    elif not isinstance(engines, list | tuple):
        engines = [engines]
    return "\n".join(_write_block(e) for e in engines)


def _write_block(engine: FuzzyEngine) -> str:
    f = fmt_number
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
    out = [f"FUNCTION_BLOCK {engine.name}" if engine.name else "FUNCTION_BLOCK", ""]
    if inputs:
        out.append("VAR_INPUT")
        out += [
            f"    {n} : REAL; RANGE := ({f(variables[n].lo)} .. {f(variables[n].hi)});"
            for n in inputs
        ]
        out += ["END_VAR", ""]
    if outputs:
        out.append("VAR_OUTPUT")
        out += [f"    {n} : REAL;" for n in outputs]
        out += ["END_VAR", ""]
    for n in inputs:
        out.append(f"FUZZIFY {n}")
        out += [f"    TERM {t} := {mf.fcl()};" for t, mf in variables[n].terms.items()]
        out += ["END_FUZZIFY", ""]
    for n in outputs:
        var = variables[n]
        sem = engine.semantics_of(concluded[n]) if n in concluded else engine.semantics
        out.append(f"DEFUZZIFY {n}")
        out += [f"    TERM {t} := {mf.fcl()};" for t, mf in var.terms.items()]
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
        out.append(f"RULEBLOCK {rs}")
        out.append(f"    AND : {sem.and_};")
        if sem.or_ != AND_OPS[sem.and_]:
            out.append(f"    OR : {sem.or_};")
        out += [f"    ACT : {sem.act};", f"    ACCU : {sem.accu};"]
        if sem.samples:
            out.append(f"    (*@acordcs samples={sem.samples} *)")
        for entry in engine.rules(rs):
            rule = entry.rule
            then = ", ".join(f"{a.var.text} IS {a.term.text}" for a in rule.actions)
            weight = f" WITH {f(rule.weight)}" if rule.weight != 1.0 else ""
            cond = format_condition(rule.condition, fcl=True)
            out.append(f"    RULE {entry.label} : IF {cond} THEN {then}{weight};")
        out += ["END_RULEBLOCK", ""]
    out += ["END_FUNCTION_BLOCK", ""]
    return "\n".join(out)
