"""A fuzzy engine built from a policy set's plan (:mod:`acordcs.engines.plan`).

Each variable the plan's rules use is declared under its canonical name ``Element.attribute`` with
its universe and terms, each policy becomes a rule set (named after it, with the set's
semantics), and the rules are defined in order with the names they write bound to those
variables, so the engine resolves nothing itself.
"""

from __future__ import annotations

from acordcs.engines.fuzzy.fuzzy_engine import FuzzyEngine
from acordcs.engines.plan import PolicyPlan
from acordcs.engines.rule_engine import RuleError


def engine_for_plan(plan: PolicyPlan) -> FuzzyEngine:
    """A new engine holding the plan's policy set (its semantics as the engine's default)."""
    engine = FuzzyEngine(plan.semantics, name=plan.name)
    for name in dict.fromkeys((*plan.inputs, *plan.outputs)):
        found = plan.variables[name].terms
        if found is None:
            raise RuleError(
                f"{name} is not a linguistic variable: give its attribute <<CtxVariable>> with "
                "tags min, max and terms",
                ruleset=plan.name,
            )
        engine.define_variable(name, found.lo, found.hi, found.terms)
    engine.bind_names(plan.names)
    for policy in plan.policies:
        engine.define_ruleset(policy)
    for rule in plan.rules:
        engine.defrule(rule.text, rule.policy)
    return engine
