"""Rule coverage of a test run, as line coverage is for code: the rules of the model's policy sets
that no scenario fired (degree above 0 in some firing), and the terms of the fuzzy sets' inputs
that no input reached (membership above 0 at some firing's input value)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from acordcs.scenarios.model_names import ModelNames
from acordcs.scenarios.scenario_run import Outcome


@dataclass(frozen=True)
class Coverage:
    rules: tuple[str, ...]  # PolicySet.Policy.label, every rule of the model
    fired: frozenset[str]
    terms: tuple[tuple[str, str], ...]  # (Element.attribute, term) of every fuzzy input
    reached: frozenset[tuple[str, str]]

    @property
    def percent(self) -> float:
        """Rules fired, in % of the model's rules (100 for a model without rules)."""
        return 100.0 * len(self.fired) / len(self.rules) if self.rules else 100.0

    @property
    def unfired(self) -> list[str]:
        return [r for r in self.rules if r not in self.fired]

    @property
    def unreached(self) -> list[tuple[str, str]]:
        return [t for t in self.terms if t not in self.reached]


def coverage(names: ModelNames, outcomes: Iterable[Outcome]) -> Coverage:
    rules = tuple(f"{s}.{p}.{label}" for s, p, label in names.rules(tuple(names.plans)))
    terms: list[tuple[str, str]] = []
    for plan in names.plans.values():
        for variable in plan.inputs:
            linguistic = names.variables.get(variable)
            if plan.syntax == "fuzzy" and linguistic is not None:
                terms += [(variable, t) for t in linguistic.terms if (variable, t) not in terms]
    fired: set[str] = set()
    reached: set[tuple[str, str]] = set()
    wanted = {v for v, _ in terms}
    for outcome in outcomes:
        for policy_set, firing in outcome.run.firings:
            fired.update(
                f"{policy_set}.{p}.{label}" for (p, label), d in firing.rules.items() if d > 0
            )
            for variable, value in firing.inputs.items():
                if variable in wanted and isinstance(value, int | float):
                    degrees = names.variables[variable].memberships(float(value))
                    reached.update((variable, t) for t, d in degrees.items() if d > 0)
    return Coverage(rules, frozenset(fired), tuple(terms), frozenset(reached))
