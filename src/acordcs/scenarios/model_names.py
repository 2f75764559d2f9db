"""What a scenario may name in a model, from its application descriptor: the attributes of its
components and monitors (with their value kinds), the linguistic variables of its policy sets
(range and terms, the terms' membership functions built by the fuzzy engine's own
:func:`~acordcs.engines.fuzzy.make_membership`), each policy set's plan
(:func:`~acordcs.engines.plan.plan_from_descriptor`: its rules, as the runtime loads them) and
the operations of its components."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

from acordcs.engines.fuzzy import Membership, make_membership
from acordcs.engines.plan import PolicyPlan, plan_from_descriptor

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application


@dataclass(frozen=True, slots=True)
class Linguistic:
    """A linguistic variable of the model: its universe [``lo``, ``hi``] and its terms."""

    lo: float
    hi: float
    terms: dict[str, Membership]

    def memberships(self, value: float) -> dict[str, float]:
        """Each term's degree at ``value`` (clipped into the universe, as the engine clips it)."""
        x = min(max(value, self.lo), self.hi)
        return {name: float(m(x)) for name, m in self.terms.items()}


@dataclass
class ModelNames:
    """The names of ``app`` a scenario may use (see the module's docstring)."""

    app: Application
    attributes: dict[str, str] = field(default_factory=dict)  # Element.attribute -> value kind
    monitors: set[str] = field(default_factory=set)
    variables: dict[str, Linguistic] = field(default_factory=dict)
    plans: dict[str, PolicyPlan] = field(default_factory=dict)
    operations: dict[str, int] = field(default_factory=dict)  # Component.operation -> inputs
    periodic: dict[str, float] = field(default_factory=dict)  # policy set -> its frequency (Hz)
    containers: dict[str, tuple[str, ...]] = field(default_factory=dict)  # -> its policy sets

    @classmethod
    def of(cls, app: Application) -> ModelNames:
        names = cls(app)
        for comp in app.components:
            for p in comp.properties:
                names.attributes[f"{comp.name}.{p.name}"] = p.kind
            for port in comp.ports:
                for p in port.properties:
                    names.attributes[f"{comp.name}.{port.name}.{p.name}"] = p.kind
            for op in comp.operations:
                inputs = sum(1 for a in op.parameters if a.direction in ("in", "inout"))
                names.operations[f"{comp.name}.{op.name}"] = inputs
        for container in app.containers:
            names.containers[container.name] = container.hosted("policy-set")
        for mon in app.monitors:
            names.monitors.add(mon.name)
            for p in mon.properties:
                names.attributes[f"{mon.name}.{p.name}"] = p.kind
        for ps in app.policy_sets:
            names.plans[ps.name] = plan_from_descriptor(ps)
            if ps.trigger == "periodic" and ps.frequency:
                names.periodic[ps.name] = ps.frequency
            for v in ps.variables:
                key = f"{v.element}.{v.attribute}"
                if key not in names.variables:
                    names.variables[key] = Linguistic(
                        v.minimum,
                        v.maximum,
                        {
                            t.name: make_membership(t.shape, t.parameters, where=f"term {t.name!r}")
                            for t in v.terms
                        },
                    )
        return names

    def rules(self, sets: tuple[str, ...]) -> list[tuple[str, str, str]]:
        """Every rule of the policy sets ``sets``: (policy set, policy, label)."""
        return [(s, r.policy, r.label) for s in sets for r in self.plans[s].rules]
