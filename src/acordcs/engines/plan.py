"""A policy set's plan: its rules resolved, as its engine loads them and the generator writes them.

A :class:`PolicyPlan` says everything about one policy set that an engine needs: each rule with
its label and priority, the variables (``Element.attribute``) the engine is given before each
firing and reads back after it, how each is typed (and, for a fuzzy engine, its universe and
terms), the operations the rules call, and how the rules write each name (``cycleRate`` for
``Control.cycleRate``). The engine packages build their engines from it
(:func:`acordcs.engines.fuzzy.engine_for_plan`, :func:`acordcs.engines.clips.engine_for_plan`), the
runtime's :class:`~acordcs.runtime.policy.PolicySet` drives them with it, and the generator's
``rules`` target writes those engines as FCL and CLIPS files.

A plan comes from the application descriptor (:func:`plan_from_descriptor`), where the model's
resolution was written down once (:mod:`acordcs.rules.binding`); nothing here resolves a name
again. A policy set made by hand in Python gets its plan from the same resolution over its
container's elements (:func:`plan_by_hand`).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from acordcs.engines.errors import BindingError
from acordcs.engines.rule_engine import RuleError
from acordcs.rules import Name, RuleSyntaxError, TermDef, parse_rule
from acordcs.rules.binding import (
    Ambiguous,
    Scope,
    ScopeElement,
    Unresolved,
    bind,
    default_label,
    rule_syntax,
)

if TYPE_CHECKING:
    from acordcs.descriptor.application import PolicySet as PolicySetDescription


@dataclass(frozen=True, slots=True)
class Terms:
    """A linguistic variable's universe [``lo``, ``hi``] and terms (FCL-style text, or parsed)."""

    lo: float
    hi: float
    terms: str | tuple[TermDef, ...] = ""


@dataclass(frozen=True, slots=True)
class PlannedRule:
    """A rule of policy ``policy``: ``text`` as ``defrule`` takes it (``label: if ...``), and its
    1-based ``priority`` in the policy."""

    policy: str
    label: str
    text: str
    priority: int


@dataclass(frozen=True, slots=True)
class PlannedVariable:
    """A variable of the engine: ``element.attribute``, its value kind (``int``, ``double``,
    ``bool``, ``string``; None when unknown), UML type and default; ``terms`` for a linguistic
    variable."""

    element: str
    attribute: str
    kind: str | None = None
    type: str = ""
    default: object = None
    terms: Terms | None = None

    @property
    def name(self) -> str:
        return f"{self.element}.{self.attribute}"


@dataclass(frozen=True, slots=True)
class PlannedOperation:
    """An operation the rules call: ``element.operation`` with ``arity`` inputs (None: any)."""

    element: str
    operation: str
    arity: int | None = None

    @property
    def name(self) -> str:
        return f"{self.element}.{self.operation}"


@dataclass(frozen=True)
class PolicyPlan:
    """One policy set's rules, resolved (see the module docstring). ``variables`` and
    ``operations`` are keyed by their canonical names; ``syntax`` is how the rules are written
    (``fuzzy`` or ``crisp``); ``names`` and ``calls`` map each name as the
    rules write it to its canonical name; ``inputs``, ``outputs`` and ``triggers`` are canonical
    variable names in the order the engine is given, read back and subscribed."""

    name: str
    engine: str
    semantics: str
    policies: tuple[str, ...]
    syntax: str
    rules: tuple[PlannedRule, ...]
    variables: Mapping[str, PlannedVariable] = field(default_factory=dict)
    operations: Mapping[str, PlannedOperation] = field(default_factory=dict)
    names: Mapping[str, str] = field(default_factory=dict)
    calls: Mapping[str, str] = field(default_factory=dict)
    inputs: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()
    triggers: tuple[str, ...] = ()

    def rules_of(self, policy: str) -> list[PlannedRule]:
        return [r for r in self.rules if r.policy == policy]


def plan_from_descriptor(ps: PolicySetDescription) -> PolicyPlan:
    """The plan of a policy set of the application descriptor: its bindings as written there.
    Raises BindingError for a set whose rules name nothing bound (a descriptor not made by
    :func:`acordcs.generator.describe.describe`: every rule names a variable or an operation)."""
    if ps.rules() and not ps.bound:
        raise BindingError(
            f"policy set {ps.name!r} of the descriptor has rules but no bound names: what its "
            "rules name was never resolved",
            hint="make the descriptor from the model (acordcs-gen build, or "
            "acordcs.generator.describe.describe), which resolves them",
        )
    linguistic = {
        v.name: Terms(
            v.minimum,
            v.maximum,
            tuple(TermDef(Name(t.name, 0), t.shape, t.parameters) for t in v.terms),
        )
        for v in ps.variables
    }
    variables: dict[str, PlannedVariable] = {}
    operations: dict[str, PlannedOperation] = {}
    names: dict[str, str] = {}
    calls: dict[str, str] = {}
    for b in ps.bound:
        if b.kind == "operation":
            operations[b.target] = PlannedOperation(b.element, b.member, b.arity)
            calls.update(dict.fromkeys(b.names, b.target))
        else:
            variables[b.target] = PlannedVariable(
                b.element, b.member, b.value_kind, b.type, b.default, linguistic.get(b.target)
            )
            names.update(dict.fromkeys(b.names, b.target))
    unbound = [n for n in (*ps.inputs, *ps.outputs, *ps.triggers) if n not in variables]
    if unbound:
        raise BindingError(
            f"policy set {ps.name!r} of the descriptor reads or writes {unbound[0]}, which none of "
            "its bound names is",
            hint="make the descriptor from the model (acordcs-gen build, or "
            "acordcs.generator.describe.describe) rather than by hand",
        )
    rules = tuple(
        PlannedRule(p.name, r.label, r.line, r.priority) for p in ps.policies for r in p.rules
    )
    return PolicyPlan(
        ps.name,
        ps.engine,
        ps.semantics,
        tuple(p.name for p in ps.policies),
        rule_syntax(ps.engine),
        rules,
        variables,
        operations,
        names,
        calls,
        ps.inputs,
        ps.outputs,
        ps.triggers,
    )


# ------------------------------------------------------------------------------- made by hand
def plan_by_hand(
    name: str,
    rules: Mapping[str, Sequence[Any]],
    *,
    engine: str,
    syntax: str,
    semantics: str,
    scope: Iterable[ScopeElement],
    where: str,
    variables: Mapping[str, Terms] | None = None,
    bindings: Mapping[str, str] | None = None,
) -> PolicyPlan:
    """The plan of a policy set built in Python: ``rules`` (policy -> its RuleLines) resolved by
    :func:`acordcs.rules.binding.bind` over ``scope`` (the container's elements in the set's
    scope); ``bindings`` names some variables by hand (written name -> ``Element.attribute``);
    ``variables`` gives linguistic variables by canonical or written name. Raises RuleError for a
    rule that does not parse and BindingError for a name that does not resolve (``where`` says
    which container, for the message); ``syntax``: how its engine's rules are written."""
    planned: list[PlannedRule] = []
    parsed = []
    for policy, lines in rules.items():
        mine = []
        for line in lines:
            try:
                mine.append((policy, line, parse_rule(line.text, syntax)))  # type: ignore[arg-type]
            except RuleSyntaxError as exc:
                raise RuleError(
                    exc.message,
                    ruleset=f"{name}.{policy}",
                    rule=line.label or f"line {line.line}",
                    column=exc.column,
                ) from None
        taken = {r.label for _, _, r in mine if r.label}
        for position, (_, line, rule) in enumerate(mine, start=1):
            label = rule.label
            if label is None:
                label = default_label(position, taken)
                taken.add(label)
                text = f"{label}: {line.text}"
            else:
                text = line.text
            planned.append(PlannedRule(policy, label, text, position))
        parsed += mine
    resolver = Scope(scope)
    found = bind(resolver, (r for _, _, r in parsed), syntax, aliases=bindings)  # type: ignore[arg-type]
    if found.problems:
        rule, written, use, why = found.problems[0]
        policy, line, _ = next(p for p in parsed if p[2] is rule)
        raise _binding_error(
            name, policy, rule.label or line.line, written, use, why, resolver, where
        )
    given = dict(variables or {})
    planned_vars: dict[str, PlannedVariable] = {}
    for written, target in found.variables.items():
        terms = given.get(target.name) or given.get(written)
        old = planned_vars.get(target.name)
        if old is None or (old.terms is None and terms is not None):
            planned_vars[target.name] = PlannedVariable(
                target.element.name, target.member, terms=terms
            )
    operations = {
        t.name: PlannedOperation(t.element.name, t.member, None) for t in found.calls.values()
    }
    return PolicyPlan(
        name,
        engine,
        semantics,
        tuple(rules),
        syntax,
        tuple(planned),
        planned_vars,
        operations,
        {w: t.name for w, t in found.variables.items()},
        {w: t.name for w, t in found.calls.items()},
        found.inputs,
        found.outputs,
        found.triggers,
    )


def _binding_error(
    name: str,
    policy: str,
    rule: object,
    written: Name,
    use: str,
    why: Ambiguous | Unresolved,
    scope: Scope,
    where: str,
) -> BindingError:
    at = f"policy {name}.{policy}, rule {rule}"
    if use == "call":
        found = (
            ", ".join(t.element.name for t in why.candidates)
            if isinstance(why, Ambiguous)
            else "no component"
        )
        return BindingError(
            f"{at}: operation {written.text!r} (column {written.column}) matches {found}",
            where=where,
            hint="write Component.operation for an operation of a component in scope",
        )
    if isinstance(why, Ambiguous):
        owners = ", ".join(sorted(t.element.name for t in why.candidates))
        return BindingError(
            f"{at}: {owners} all have an attribute {written.member!r} (column {written.column})",
            where=where,
            hint="qualify the variable as Element.attribute, or bind it with bindings={...}",
        )
    if why.element is not None:
        return BindingError(
            f"{at}: variable {written.text!r} (column {written.column}) is not an attribute in scope",
            where=where,
            hint=f"in scope: {', '.join(sorted(scope.names()))}; check the element and attribute names",
        )
    return BindingError(
        f"{at}: no element in scope has an attribute {written.member!r} (column {written.column})",
        where=where,
        hint="qualify the variable as Element.attribute, or bind it with bindings={...}",
    )
