"""A fuzzy policy set of the descriptor as an FCL function block jFuzzyLogic reads.

The runtime's own FCL writer (:func:`acordcs.runtime.fuzzy.fcl_writer.write_fcl`) writes it, so
reading the file back with :func:`acordcs.runtime.fuzzy.read_fcl` gives an engine with the
same results. The writer reads an engine's variables, rule sets and resolved rules; what it is
given here, :class:`RuleBase`, is made of the runtime's own pieces (variables checked by
``build_variable``, rules resolved by ``resolve_rule``, named semantics) without what an engine
prepares for inference at each ``defrule`` (its defuzzification plans): a third of the time of
building 90 engines, for nothing a file needs.

FCL (and jFuzzyLogic) names are plain identifiers and its keywords are reserved, in any case:
``Locomotion.maxSpeed`` becomes ``Locomotion_maxSpeed``, and a name that is an FCL keyword or
already taken gets ``_`` appended (``min`` -> ``min_``) until it is free. The file's header
comment lists every renaming.
"""

from __future__ import annotations

from dataclasses import dataclass

from acordcs.codegen.targets.names import require_identifiers, rule_line
from acordcs.descriptor import PolicySet, Variable

# Our FCL grammar's keywords and jFuzzyLogic's (its lexer reserves them in any case).
FCL_KEYWORDS = frozenset(
    """ABS ACCU ACT AND ASUM BDIF BSUM COA COG COGF COGS COS COSINE DEFAULT DEFUZZIFY DMAX DMIN
    DSIGM EINSTEIN END_DEFUZZIFY END_FUNCTION_BLOCK END_FUZZIFY END_RULEBLOCK END_VAR EXP FUNCTION
    FUNCTION_BLOCK FUZZIFY GAUSS GAUSS2 GBELL HAMACHER IF IS LM LN LOG MAX METHOD MIN MM NC NIPMAX
    NIPMIN NOT NSUM OR PROBOR PROD RANGE REAL RM RULE RULEBLOCK SIGM SIN SINGLETONS SOMEWHAT SUM
    TAN TERM THEN TRAPE TRIAN VAR_INPUT VAR_OUTPUT VERY WITH""".split()
)


class RuleBase:
    """What :func:`~acordcs.runtime.fuzzy.fcl_writer.write_fcl` reads of a FuzzyEngine:
    ``name``, ``semantics``, ``variables``, ``rulesets()``, ``rules(ruleset)`` (resolved
    entries), ``semantics_of(ruleset)``."""

    def __init__(self, name: str, semantics: str) -> None:
        from acordcs.runtime.fuzzy.semantics import resolve

        self.name = name
        self.semantics = resolve(semantics)
        self.variables: dict = {}
        self._sets: dict[str, dict[str, object]] = {}

    def define_variable(self, name: str, lo: float, hi: float, terms: list) -> None:
        from acordcs.runtime.fuzzy.variable import build_variable

        self.variables[name] = build_variable(name, lo, hi, terms)

    def define_ruleset(self, ruleset: str) -> None:
        self._sets.setdefault(ruleset, {})

    def add_rule(self, rule, ruleset: str) -> None:
        """As FuzzyEngine.add_rule: an unlabelled rule gets ``rule<n>``, n its position."""
        from acordcs.runtime.fuzzy.compiler import resolve_rule

        entries = self._sets[ruleset]
        label = rule.label
        if label is None:
            n = len(entries) + 1
            while f"rule{n}" in entries:
                n += 1
            label = f"rule{n}"
        entries[label] = resolve_rule(rule, label, ruleset, self.variables)

    def rulesets(self) -> list[str]:
        return list(self._sets)

    def rules(self, ruleset: str) -> list:
        return list(self._sets[ruleset].values())

    def semantics_of(self, _ruleset: str):
        return self.semantics


class _Names:
    """Allocates FCL names: free of keywords and of the names already given."""

    def __init__(self) -> None:
        self.used: set[str] = set()

    def take(self, wanted: str) -> str:
        name = wanted
        while name.upper() in FCL_KEYWORDS or name.casefold() in self.used:
            name += "_"
        self.used.add(name.casefold())
        return name


@dataclass(frozen=True)
class FclFile:
    """The FCL text of one policy set, and the renamings (model name -> FCL name) it made."""

    text: str
    renamed: tuple[tuple[str, str, str], ...]  # (what, model name, FCL name)
    hedged: bool  # some rule uses VERY or SOMEWHAT (our extension)


def _check(ps: PolicySet) -> None:
    names: list[tuple[str, object, str, str]] = [("policy set", ps.name, ps.id, ps.qualified_name)]
    for p in ps.policies:
        names.append(("policy", p.name, p.id, p.qualified_name))
        names += [
            ("rule label", r.label, p.id, p.qualified_name) for r in p.rules if r.label is not None
        ]
    for v in ps.variables:
        for part in v.element.split("."):
            names.append(("element", part, v.id, v.qualified_name))
        names.append(("attribute", v.attribute, v.id, v.qualified_name))
        names += [("term", t.name, v.id, v.qualified_name) for t in v.terms]
    require_identifiers(names)


def resolve(variables: dict[str, Variable], written: str) -> Variable | None:
    """The variable a rule's name stands for: ``Element.attribute`` (a port's as ``Port.attr`` or
    ``Component.Port.attr``), or a bare ``attribute`` when exactly one variable has it."""
    found = variables.get(written)
    if found is not None:
        return found
    suffix = "." + written
    candidates = [v for name, v in variables.items() if name.endswith(suffix)]
    return candidates[0] if len(candidates) == 1 else None


def fcl_for(ps: PolicySet) -> FclFile:
    """The FCL function block of a fuzzy policy set. Raises NameRefused (a name that is not an
    identifier) or RuleError (a rule the engine refuses: validate the model first)."""
    from acordcs.rules import BoolOp, Consequent, Is, Name, Not, Rule, TermDef, parse_rule
    from acordcs.runtime.fuzzy.fcl_writer import write_fcl
    from acordcs.runtime.rule_engine import RuleError

    _check(ps)
    blocks = _Names()  # function block, variables and rule blocks share one namespace
    renamed: list[tuple[str, str, str]] = []

    def take(names: _Names, what: str, model: str, wanted: str | None = None) -> str:
        given = names.take(wanted or model)
        if given != model:
            renamed.append((what, model, given))
        return given

    engine = RuleBase(take(blocks, "policy set", ps.name), ps.semantics)
    variables = {v.name: v for v in ps.variables}
    var_names: dict[str, str] = {}
    term_names: dict[str, dict[str, str]] = {}
    for v in ps.variables:
        given = take(blocks, "variable", v.name, v.name.replace(".", "_"))
        var_names[v.name] = given
        terms = _Names()
        term_names[v.name] = {t.name: take(terms, f"term of {v.name}", t.name) for t in v.terms}
        engine.define_variable(
            given,
            v.minimum,
            v.maximum,
            [TermDef(Name(term_names[v.name][t.name], 0), t.shape, t.parameters) for t in v.terms],
        )
    hedged = False

    def rename(node: object, ruleset: str, label: str) -> object:
        nonlocal hedged
        if isinstance(node, Is | Consequent):
            var = resolve(variables, node.var.text)
            if var is None or node.term.text not in term_names[var.name]:
                raise RuleError(
                    f"{node.var.text} is {node.term.text}: no such variable and term in the "
                    f"scope of policy set {ps.name}; validate the model",
                    ruleset=ruleset,
                    rule=label,
                    column=node.var.column or None,
                )
            var_name = Name(var_names[var.name], node.var.column)
            term = Name(term_names[var.name][node.term.text], node.term.column)
            if isinstance(node, Consequent):
                return Consequent(var_name, term)
            hedged = hedged or any(h != "not" for h in node.hedges)
            return Is(var_name, node.hedges, term)
        if isinstance(node, Not):
            return Not(rename(node.operand, ruleset, label))
        if isinstance(node, BoolOp):
            return BoolOp(
                node.op, rename(node.left, ruleset, label), rename(node.right, ruleset, label)
            )
        raise RuleError(f"not a fuzzy rule part: {node!r}", ruleset=ruleset, rule=label)

    for policy in ps.policies:
        ruleset = take(blocks, "policy", policy.name)
        engine.define_ruleset(ruleset)
        labels = _Names()
        for number, rule in enumerate(policy.rules, start=1):
            shown = rule.label or f"#{number}"
            try:
                parsed = parse_rule(rule_line(rule), "fuzzy")
            except Exception as err:  # RuleSyntaxError: the model did not validate
                raise RuleError(
                    f"{getattr(err, 'message', err)}; validate the model",
                    ruleset=policy.name,
                    rule=shown,
                ) from None
            label = take(labels, f"rule label in {policy.name}", rule.label) if rule.label else None
            engine.add_rule(
                Rule(
                    "fuzzy",
                    label,
                    rename(parsed.condition, policy.name, shown),
                    tuple(rename(a, policy.name, shown) for a in parsed.actions),
                    parsed.weight,
                    parsed.text,
                ),
                ruleset,
            )
    return FclFile(write_fcl(engine), tuple(renamed), hedged)
