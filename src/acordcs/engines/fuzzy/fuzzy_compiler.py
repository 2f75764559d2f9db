"""From parsed rules to a rule set that fires fast.

At ``defrule`` time a rule is resolved (:func:`resolve_rule`): every variable bound to a declared
one, every term checked. At the first ``fire`` after a change, the whole rule set is compiled
(:func:`compile_ruleset`) into ONE generated Python function: memberships inlined as comparisons
and arithmetic, rule degrees as straight-line code, conclusions folded per output term, then one
call per output into its defuzzifier (:mod:`acordcs.engines.fuzzy.defuzz`). The generated text only
contains identifiers we make and numbers we format, never user text.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace

from acordcs.engines.fuzzy.defuzz import OutputShape, make_defuzzifier
from acordcs.engines.fuzzy.semantics import Semantics, collapses
from acordcs.engines.fuzzy.variable import LinguisticVariable
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import BoolOp, Consequent, Is, Name, Not, Rule, depth_message, rule_too_deep


@dataclass(frozen=True)
class RuleEntry:
    """A resolved rule. ``condition`` uses canonical variable names:
    ``("is", var, hedges, term)``, ``("not", x)``, ``("and"|"or", left, right)``."""

    label: str
    text: str
    rule: Rule
    condition: tuple
    consequents: tuple[tuple[str, str], ...]
    weight: float
    file: str | None = None
    line: int | None = None

    def inputs(self) -> list[str]:
        out: list[str] = []
        stack = [self.condition]
        while stack:
            node = stack.pop()
            if node[0] == "is":
                out.append(node[1])
            elif node[0] == "not":
                stack.append(node[1])
            else:
                stack.extend((node[2], node[1]))
        return out


def resolve_name(variables: dict[str, LinguisticVariable], written: str) -> str | list[str]:
    """The canonical name ``written`` stands for, or the list of candidates (empty: unknown).

    ``Element.attribute`` must match exactly; a bare ``attribute`` matches itself or the one
    declared ``X.attribute``."""
    if written in variables:
        return written
    if "." in written:
        return []
    return [n for n in variables if n.rpartition(".")[2] == written]


def unknown_variable_message(
    variables: dict[str, LinguisticVariable], written: str, found: list[str]
) -> str:
    if found:
        return (
            f"variable {written!r} is ambiguous: it may be {', '.join(sorted(found))}; "
            "write it qualified as Element.attribute"
        )
    known = sorted(variables)
    shown = ", ".join(known[:12]) + (", ..." if len(known) > 12 else "")
    return f"unknown variable {written!r} (declared: {shown or 'none'}); declare it or fix the name"


def resolve_rule(
    rule: Rule,
    label: str,
    ruleset: str,
    variables: dict[str, LinguisticVariable],
    *,
    file: str | None = None,
    line: int | None = None,
    names: Mapping[str, str] | None = None,
) -> RuleEntry:
    """Bind a parsed fuzzy rule to declared variables (``names``: names as written bound to them,
    used first); RuleError names the rule set, rule, column."""

    def fail(msg: str, name: Name) -> RuleError:
        return RuleError(
            msg, ruleset=ruleset, rule=label, column=name.column or None, file=file, line=line
        )

    def var_of(name: Name) -> LinguisticVariable:
        bound = names.get(name.text) if names else None
        if bound is not None and bound in variables:
            return variables[bound]
        found = resolve_name(variables, name.text)
        if isinstance(found, str):
            return variables[found]
        if len(found) == 1:
            return variables[found[0]]
        raise fail(unknown_variable_message(variables, name.text, found), name)

    def term_of(var: LinguisticVariable, term: Name) -> str:
        if term.text not in var.terms:
            raise fail(
                f"variable {var.name!r} has no term {term.text!r} (terms: {', '.join(var.terms) or 'none'})",
                term,
            )
        return term.text

    def walk(node: object) -> tuple:
        if isinstance(node, Is):
            var = var_of(node.var)
            term = term_of(var, node.term)
            if var.terms[term].shape == "function":
                raise fail(
                    f"term {term!r} of {var.name!r} is a FUNCTION term, a point an output takes: "
                    "a condition cannot test it",
                    node.term,
                )
            return ("is", var.name, node.hedges, term)
        if isinstance(node, Not):
            return ("not", walk(node.operand))
        if isinstance(node, BoolOp):
            return (node.op, walk(node.left), walk(node.right))
        raise RuleError(
            f"not a fuzzy condition: {node!r}", ruleset=ruleset, rule=label, file=file, line=line
        )

    if rule.kind != "fuzzy":
        raise RuleError(
            "the fuzzy engine takes fuzzy rules only",
            ruleset=ruleset,
            rule=label,
            file=file,
            line=line,
        )
    if rule_too_deep(rule):  # a tree built in Python: the parser refuses these in text
        raise RuleError(depth_message(), ruleset=ruleset, rule=label, file=file, line=line)
    condition = walk(rule.condition)
    consequents = []
    for action in rule.actions:
        if not isinstance(action, Consequent):
            raise RuleError(
                f"not a fuzzy conclusion: {action!r}",
                ruleset=ruleset,
                rule=label,
                file=file,
                line=line,
            )
        var = var_of(action.var)
        consequents.append((var.name, term_of(var, action.term)))
    if not 0.0 <= rule.weight <= 1.0 or math.isnan(rule.weight):
        raise RuleError(
            f"weight {rule.weight!r} is outside 0..1",
            ruleset=ruleset,
            rule=label,
            file=file,
            line=line,
        )
    return RuleEntry(label, rule.text, rule, condition, tuple(consequents), rule.weight, file, line)


# ---------------------------------------------------------------------------------- compiling
@dataclass
class OutputPlan:
    """How one output of a rule set is computed."""

    name: str
    variable: LinguisticVariable
    defuzzifier: Callable
    collapsed: bool
    sources: list[tuple[int, int]] = field(default_factory=list)  # (rule index, term index)


@dataclass
class CompiledRuleSet:
    name: str
    semantics: Semantics
    entries: list[RuleEntry]
    inputs: list[str]
    outputs: list[OutputPlan]
    run: Callable[[dict], tuple[str, ...]]
    source: str
    variables: dict[str, LinguisticVariable]


class _Emitter:
    def __init__(self, sem: Semantics) -> None:
        self.sem = sem
        self.lines: list[str] = []
        self.count = 0

    def tmp(self) -> str:
        self.count += 1
        return f"t{self.count}"

    def emit(self, text: str) -> None:
        self.lines.append("    " + text)


def compile_ruleset(
    name: str,
    entries: list[RuleEntry],
    variables: dict[str, LinguisticVariable],
    sem: Semantics,
    plan: Callable[[str, LinguisticVariable, Semantics], OutputPlan] | None = None,
) -> CompiledRuleSet:
    """Generate and compile the rule set's fire function (see module doc). ``plan`` gives an
    output's plan (default :func:`output_plan`; an engine passes the plans it already built)."""
    plan = plan or output_plan
    # dicts as ordered sets: membership tests stay O(1) with thousands of rules and terms
    inputs = list(dict.fromkeys(v for e in entries for v in e.inputs()))
    out_names = list(dict.fromkeys(v for e in entries for v, _ in e.consequents))
    out_index = {v: o for o, v in enumerate(out_names)}
    outputs = [replace(plan(name, variables[v], sem), sources=[]) for v in out_names]
    # The inputs FUNCTION terms of the outputs read are inputs of the rule set too: set, checked.
    for out in outputs:
        for _, expr in getattr(out.defuzzifier, "functions", ()):
            for v in expr.variables:
                if v not in variables:
                    raise RuleError(
                        f"output {out.name!r}: a FUNCTION term reads {v!r}, which is not a "
                        "declared variable; declare it as an input",
                        ruleset=name,
                    )
                if v not in inputs:
                    inputs.append(v)
    term_index = [{t: k for k, t in enumerate(o.variable.terms)} for o in outputs]

    em = _Emitter(sem)
    em.emit("missed = ()")
    xloc = {}
    for i, v in enumerate(inputs):
        xloc[v] = f"x{i}"
        em.emit(f"x{i} = V[{v!r}]")
        em.emit(f"if x{i} is None: _unset({v!r})")
    mem: dict[tuple, str] = {}

    def degree(node: tuple) -> str:
        kind = node[0]
        if kind == "is":
            _, var, hedges, term = node
            key = (var, term)
            if key not in mem:
                loc = mem[key] = f"m{len(mem)}"
                body = variables[var].terms[term].code(xloc[var], loc)
                em.emit(body[0])
                em.lines.extend("    " + line for line in body[1:])
            cur = mem[key]
            for h in reversed(hedges):
                hkey = (var, term, h, cur)
                if hkey not in mem:
                    loc = mem[hkey] = em.tmp()
                    expr = {
                        "very": f"{cur} * {cur}",
                        "somewhat": f"_sqrt({cur})",
                        "not": f"1.0 - {cur}",
                    }[h]
                    em.emit(f"{loc} = {expr}")
                cur = mem[hkey]
            return cur
        if kind == "not":
            inner = degree(node[1])
            t = em.tmp()
            em.emit(f"{t} = 1.0 - {inner}")
            return t
        a, b = degree(node[1]), degree(node[2])
        t = em.tmp()
        op = sem.and_ if kind == "and" else sem.or_
        em.emit(_binary(op, t, a, b))
        return t

    dloc = []
    for r, e in enumerate(entries):
        d = degree(e.condition)
        if e.weight != 1.0:
            t = em.tmp()
            em.emit(f"{t} = {d} * {e.weight!r}")
            d = t
        dloc.append(d)
        for v, term in e.consequents:
            o = out_index[v]
            outputs[o].sources.append((r, term_index[o][term]))

    namespace: dict[str, object] = {
        "_exp": math.exp,
        "_sqrt": math.sqrt,
        "_unset": _unset_raiser(name),
    }
    for o, out in enumerate(outputs):
        namespace[f"D{o}"] = out.defuzzifier
        namespace[f"F{o}"] = out.variable.fallback
        if out.collapsed:
            by_term: list[list[str]] = [[] for _ in out.variable.terms]
            for r, k in out.sources:
                by_term[k].append(dloc[r])
            folded = [_fold(em, sem.accu, ds) for ds in by_term]
            arg = "(" + ", ".join(folded) + ("," if len(folded) == 1 else "") + ")"
        else:
            arg = "(" + "".join(f"({k}, {dloc[r]}), " for r, k in out.sources) + ")"
        em.emit(
            f"r = D{o}({arg}, V)"
            if getattr(out.defuzzifier, "needs_values", False)
            else f"r = D{o}({arg})"
        )
        em.emit(f"if r is None: r = F{o}(V[{out.name!r}]); missed += ({out.name!r},)")
        em.emit(f"V[{out.name!r}] = r")
    em.emit("return missed")
    source = "def _run(V):\n" + "\n".join(em.lines) + "\n"
    exec(compile(source, f"<fuzzy rule set {name}>", "exec"), namespace)
    used = {v: variables[v] for v in [*inputs, *out_names]}
    return CompiledRuleSet(name, sem, entries, inputs, outputs, namespace["_run"], source, used)  # type: ignore[arg-type]


def output_plan(ruleset: str, var: LinguisticVariable, sem: Semantics) -> OutputPlan:
    """The defuzzifier for ``var`` in a rule set; RuleError if the method does not fit its terms."""
    shape = OutputShape(var.lo, var.hi, list(var.terms.values()))
    method = var.method or sem.method
    where = f"rule set {ruleset!r}, output {var.name!r}"
    dz = make_defuzzifier(shape, sem, method, where=where)
    return OutputPlan(var.name, var, dz, collapses(sem, shape.singletons))


def _binary(op: str, t: str, a: str, b: str) -> str:
    return {
        "MIN": f"{t} = {a} if {a} < {b} else {b}",
        "MAX": f"{t} = {a} if {a} > {b} else {b}",
        "PROD": f"{t} = {a} * {b}",
        "ASUM": f"{t} = {a} + {b} - {a} * {b}",
        "BDIF": f"{t} = {a} + {b} - 1.0; {t} = {t} if {t} > 0.0 else 0.0",
        "BSUM": f"{t} = {a} + {b}; {t} = {t} if {t} < 1.0 else 1.0",
        "DMIN": f"{t} = {b} if {a} == 1.0 else {a} if {b} == 1.0 else 0.0",
        "DMAX": f"{t} = {b} if {a} == 0.0 else {a} if {b} == 0.0 else 1.0",
        "NIPMIN": f"{t} = ({a} if {a} < {b} else {b}) if {a} + {b} > 1.0 else 0.0",
        "NIPMAX": f"{t} = ({a} if {a} > {b} else {b}) if {a} + {b} < 1.0 else 1.0",
        "HAMACHER": f"{t} = 0.0 if {a} == 0.0 and {b} == 0.0 else {a} * {b} / ({a} + {b} - {a} * {b})",
        "EINSTEIN": f"{t} = ({a} + {b}) / (1.0 + {a} * {b})",
    }[op]


def _fold(em: _Emitter, accu: str, ds: list[str]) -> str:
    """Fold the degrees of the rules concluding one term (the accumulation of equal shapes)."""
    if not ds:
        return "0.0"
    if len(ds) == 1:
        return ds[0]
    t = em.tmp()
    if accu == "MAX":
        em.emit(f"{t} = {ds[0]}")
        for d in ds[1:]:
            em.emit(f"if {d} > {t}: {t} = {d}")
    elif accu in ("SUM", "NSUM"):
        em.emit(f"{t} = {' + '.join(ds)}")
    elif accu == "BSUM":
        em.emit(f"{t} = {' + '.join(ds)}; {t} = {t} if {t} < 1.0 else 1.0")
    else:  # PROBOR
        em.emit(f"{t} = {ds[0]}")
        for d in ds[1:]:
            em.emit(f"{t} = {t} + {d} - {t} * {d}")
    return t


def _unset_raiser(ruleset: str) -> Callable[[str], None]:
    def unset(var: str) -> None:
        raise RuleError(
            f"input {var!r} has no value; call set({var!r}, value) before fire({ruleset!r}), "
            "or give the variable an initial value",
            ruleset=ruleset,
        )

    return unset
