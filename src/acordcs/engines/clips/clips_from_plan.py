"""A CLIPS engine built from a policy set's plan (:mod:`acordcs.engines.plan`).

Each variable the plan's rules use is declared under its canonical name ``Element.attribute``,
typed as its attribute and holding the model's default; each operation they call is declared with
its number of arguments (and bound to ``call`` when given); each policy becomes a rule set (a CLIPS
module named after it) and the rules are defined in their order of priority, with the names they
write bound to those declarations, so the engine resolves nothing itself. The engine is strict:
setting a variable the plan does not declare is refused.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from acordcs.engines.clips.clips_engine import ClipsEngine
from acordcs.engines.plan import PolicyPlan


def engine_for_plan(
    plan: PolicyPlan,
    *,
    call: Callable[[str, tuple[Any, ...]], Any] | None = None,
    max_firings: int = 10_000,
) -> ClipsEngine:
    """A new engine holding the plan's policy set; rules call operations through ``call(name,
    args)`` (``name`` as ``Element.operation``)."""
    engine = ClipsEngine(max_firings=max_firings, strict=True)
    for name in dict.fromkeys((*plan.inputs, *plan.outputs)):
        var = plan.variables[name]
        engine.declare(name, var.default, type=var.kind)
    for op in plan.operations.values():
        arity = None if op.arity is None else tuple(f"argument {n}" for n in range(1, op.arity + 1))
        engine.declare_operation(op.name, arity)
        if call is not None:
            engine.bind_operation(op.name, lambda *args, _name=op.name: call(_name, args))
    engine.bind_names(plan.names, plan.calls)
    for policy in plan.policies:
        engine.define_ruleset(policy)
    for rule in sorted(plan.rules, key=lambda r: (plan.policies.index(r.policy), r.priority)):
        engine.defrule(rule.text, rule.policy, priority=rule.priority)
    return engine
