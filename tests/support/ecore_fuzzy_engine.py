"""An oracle: a FuzzyEngine built straight from the pyecore model (``acordcs.ecore`` instances, as
``acordcs.model.ecore_builder.to_ecore`` makes them), resolving a policy set's scope on its own.

The runtime builds its engines from the descriptor; this builds one from the other representation
of the same model, so that tests can hold the two (and the FCL files of the ``rules`` target) to
each other. Scope of a policy set's rules: the attributes of the monitors that feed the set, of the
elements it adapts and, for an adapted component, of its ports. Every such attribute that is a
linguistic variable (``Attribute.variable``, a CtxVariable) is declared as ``Element.attribute``;
rules may write it unqualified where that is unambiguous. Each CtxPolicy becomes one rule set,
named after the policy; the set's ``semantics`` tag chooses the inference semantics.

``policy_set`` arguments are CtxPolicySet objects of a pyecore model (typed ``Any``: pyecore's
dynamic classes have no static types).
"""

from __future__ import annotations

from typing import Any

from acordcs.engines.fuzzy.fuzzy_engine import FuzzyEngine
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import Name, RuleSyntaxError, TermDef, parse_rule


def _literal(value: object, default: str) -> str:
    if value is None:
        return default
    return str(getattr(value, "name", value))


def scope_elements(policy_set: Any) -> list[Any]:
    """The model elements whose attributes the policy set's rules may use, in a stable order."""
    out: list[Any] = []
    app = policy_set.eContainer()
    for monitor in getattr(app, "monitors", ()) or ():
        if policy_set in monitor.feeds:
            out.append(monitor)
    for element in policy_set.adapts:
        out.append(element)
        out.extend(getattr(element, "ports", ()) or ())
    seen: set[int] = set()
    return [e for e in out if not (id(e) in seen or seen.add(id(e)))]


def declare_variables(engine: FuzzyEngine, policy_set: Any) -> list[str]:
    """Declare every linguistic variable in the set's scope; returns their qualified names."""
    names = []
    for element in scope_elements(policy_set):
        for attr in element.attributes:
            var = attr.variable
            if var is None:
                continue
            name = f"{element.name}.{attr.name}"
            terms = [
                TermDef(
                    Name(t.name, 0),
                    _literal(t.shape, "trapezoid"),
                    tuple(float(p) for p in t.parameters),
                )
                for t in var.terms
            ]
            try:
                initial = float(attr.defaultValue) if attr.defaultValue not in (None, "") else None
            except ValueError:
                initial = None
            lo, hi = var.rangeMin, var.rangeMax
            if lo is None or hi is None:
                raise RuleError(
                    f"linguistic variable {name} has no min/max; set the CtxVariable tags min and max",
                    ruleset=policy_set.name,
                )
            engine.define_variable(name, lo, hi, terms, initial=initial)
            names.append(name)
    return names


def load_policy_set(engine: FuzzyEngine, policy_set: Any) -> list[str]:
    """Declare the set's variables and define its policies' rules; returns the rule set names."""
    kind = _literal(policy_set.engine, "fuzzy")
    if kind != "fuzzy":
        raise RuleError(
            f"policy set {policy_set.name} uses engine {kind!r}; load it into that engine, not the fuzzy one",
            ruleset=policy_set.name,
        )
    declare_variables(engine, policy_set)
    semantics = _literal(policy_set.semantics, "mamdani")
    names = []
    for policy in policy_set.policies:
        engine.define_ruleset(policy.name, semantics)
        for rule in policy.rules:
            text = (rule.text or "").strip()
            if rule.label:
                try:
                    has_label = parse_rule(text, "fuzzy").label is not None
                except RuleSyntaxError:
                    has_label = True  # defrule reports the syntax error with its column
                if not has_label:
                    text = f"{rule.label}: {text}"
            engine.defrule(text, policy.name)
        names.append(policy.name)
    return names


def engine_for_policy_set(policy_set: Any) -> FuzzyEngine:
    """A new engine holding one policy set (its ``semantics`` tag as the engine's default)."""
    engine = FuzzyEngine(_literal(policy_set.semantics, "mamdani"), name=policy_set.name)
    load_policy_set(engine, policy_set)
    return engine
