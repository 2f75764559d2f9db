"""A policy set assembled from a descriptor runs what the descriptor resolved: its engine's
variables and operations are the bound ones, its rules keep their labels and priorities, and a
descriptor whose bindings are missing or do not add up is refused with a message saying so."""

from __future__ import annotations

from dataclasses import replace

import pytest

from acordcs.engines.clips import engine_for_plan
from acordcs.engines.plan import plan_from_descriptor
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.errors import BindingError
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    op,
    policy_set,
    prop,
    ref,
)


def robot(rules: list[str]):
    return application(
        "Robot",
        containers=(
            container(
                "lab",
                ref("component", "Recovery"),
                ref("monitor", "Control"),
                ref("policy-set", "Recovering"),
            ),
        ),
        components=(component("Recovery", properties=(prop("retries", 0),)),),
        monitors=(monitor("Control", prop("speed", 1.0), feeds=("Recovering",)),),
        policy_sets=(
            policy_set(
                "Recovering",
                {"rules": rules},
                engine="clips",
                adapts=(ref("component", "Recovery"),),
            ),
        ),
    )


def test_the_engine_holds_the_bound_variables_under_their_names():
    app = robot(["count: if speed == 0 then retries = retries + 1"])
    (ps,) = app.policy_sets
    plan = plan_from_descriptor(ps)
    assert plan.names == {"speed": "Control.speed", "retries": "Recovery.retries"}
    assert plan.inputs == ("Control.speed", "Recovery.retries")
    assert plan.outputs == ("Recovery.retries",)
    with assemble(app, clock=VirtualClock()) as run:
        lab = run.container("lab")
        lab.monitor("Control").update(speed=0.0)
        assert lab.get_property("Recovery", "retries") == 1
        assert lab.policy_set("Recovering").last_firing.inputs == {
            "Control.speed": 0.0,
            "Recovery.retries": 0,
        }


def test_priority_orders_crisp_rules_whatever_order_they_are_defined_in():
    # the first rule whose condition holds fires first: "first" (priority 1) sets 1, "second" 2
    app = robot(
        [
            "first: if Control.speed == 0 and Recovery.retries == 0 then Recovery.retries = 1",
            "second: if Control.speed == 0 and Recovery.retries == 0 then Recovery.retries = 2",
        ]
    )
    (ps,) = app.policy_sets
    plan = plan_from_descriptor(ps)
    shuffled = replace(plan, rules=tuple(reversed(plan.rules)))
    for each in (plan, shuffled):
        engine = engine_for_plan(each)
        engine.set("Control.speed", 0.0)
        engine.set("Recovery.retries", 0)
        engine.fire("rules")
        assert engine.get("Recovery.retries") == 1
    assert "(salience 9999)" in engine.construct("rules", "first")


def test_a_descriptor_without_bindings_is_refused_with_what_to_do():
    app = robot(["count: if speed == 0 then retries = retries + 1"])
    (ps,) = app.policy_sets
    unbound = replace(app, policy_sets=(replace(ps, bound=(), inputs=(), outputs=()),))
    with pytest.raises(BindingError, match="has rules but no bound names") as caught:
        assemble(unbound, clock=VirtualClock())
    assert "acordcs-gen build" in str(caught.value)
    wrong = replace(app, policy_sets=(replace(ps, inputs=("Control.sped",)),))
    with pytest.raises(BindingError, match=r"reads or writes Control\.sped, which none"):
        assemble(wrong, clock=VirtualClock())


def test_a_bound_element_the_container_lacks_is_refused_at_assembly():
    app = robot(["count: if speed == 0 then retries = retries + 1"])
    (ps,) = app.policy_sets
    elsewhere = replace(
        ps,
        bound=tuple(replace(b, element="Ghost") if b.element == "Control" else b for b in ps.bound),
        inputs=("Ghost.speed", "Recovery.retries"),
        triggers=("Ghost.speed",),
    )
    with pytest.raises(BindingError, match=r"Ghost\.speed, which is not an attribute"):
        assemble(replace(app, policy_sets=(elsewhere,)), clock=VirtualClock())


def test_operations_are_declared_with_their_arity():
    app = application(
        "Robot",
        containers=(
            container("lab", ref("component", "Recovery"), ref("policy-set", "Recovering")),
        ),
        components=(
            component(
                "Recovery",
                properties=(prop("retries", 0),),
                operations=(op("move", ("speed", "double", "in"), ("n", "int", "out")),),
            ),
        ),
        policy_sets=(
            policy_set(
                "Recovering",
                {"rules": ["go: if retries == 0 then move(1.5)"]},
                engine="clips",
                adapts=(ref("component", "Recovery"),),
            ),
        ),
    )
    (ps,) = app.policy_sets
    (call,) = [b for b in ps.bound if b.kind == "operation"]
    assert (call.target, call.arity, call.names) == ("Recovery.move", 1, ("move",))
    plan = plan_from_descriptor(ps)
    assert plan.calls == {"move": "Recovery.move"}
