"""A container's part of an update is atomic: when a step fails (here a new component whose class
raises when it is made), what the earlier steps did is undone, newest first: the removed monitor is
back and feeds the policy set again, a property holds its old value, the policy set runs its old
rules; the failure names the change that failed and each change rolled back. A part that succeeds
emits one ``model.updated`` event per change, with its plan line, and a default is not set over a
value changed at run time unless ``reset``."""

from __future__ import annotations

from typing import ClassVar

import pytest

from acordcs.descriptor.diff import diff
from acordcs.runtime import events as ev
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.live.apply_update import GivenClasses, UpdateFailed, apply_part
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    policy_set,
    prop,
    ref,
)


def home(*, rule: str, hygro: bool = True, level: int = 0, extra: bool = False):
    hosted = [ref("component", "Heater"), ref("policy-set", "Comfort"), ref("monitor", "Thermo")]
    comps = [component("Heater", properties=(prop("level", level), prop("mode", "")))]
    monitors = [monitor("Thermo", prop("temp", 20.0), feeds=("Comfort",))]
    if hygro:
        hosted.append(ref("monitor", "Hygro"))
        monitors.append(monitor("Hygro", prop("humidity", 0.5)))
    if extra:
        hosted.append(ref("component", "Broken"))
        comps.append(component("Broken", properties=(prop("x", 0),)))
    return application(
        "Home",
        containers=(container("house", *hosted),),
        components=tuple(comps),
        monitors=tuple(monitors),
        policy_sets=(
            policy_set("Comfort", {"rules": [rule]}, adapts=(ref("component", "Heater"),)),
        ),
    )


class Broken(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"x": 0}

    def __init__(self) -> None:
        raise RuntimeError("the driver of this device is missing")


def updated(run) -> list[str]:
    seen: list[str] = []
    run.container("house").subscribe(ev.MODEL_UPDATED, lambda e: seen.append(e.value), name="t")
    return seen


RULE = 'hot: if Thermo.temp > 30 then Heater.mode = "cool"'


def test_a_failing_step_undoes_the_steps_before_it():
    old = home(rule=RULE)
    # the monitor goes (step 3), the level's default changes (step 8, after the failure), the
    # new component fails (step 5), the rule would change (step 9)
    new = home(rule=RULE.replace("> 30", "> 25"), hygro=False, extra=True, level=5)
    plan = diff(old, new)
    assert plan.lines == (
        "~ component Heater: property level: default 0 -> 5",
        "+ component Broken: in container house",
        "- monitor Hygro",
        "~ policy set Comfort: rule hot: ... > 30 ... -> ... > 25 ...",
    )
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        thermo, hygro = house.monitor("Thermo"), house.monitor("Hygro")
        seen = updated(run)
        with pytest.raises(UpdateFailed) as failed:
            apply_part(run, "house", old, new, plan.part("house"),
                       classes=GivenClasses({"Broken": Broken}), touched=lambda e, a: False)  # fmt: skip
        err = failed.value
        assert err.failed == "+ component Broken: in container house"
        assert "the driver of this device is missing" in err.message
        assert err.rolled_back == ("- monitor Hygro",) and not err.unrolled
        # as before: the same monitor back, the set on its old rule
        assert house.monitors() == ["Hygro", "Thermo"] and house.monitor("Hygro") is hygro
        assert hygro.container is house
        assert "Broken" not in house.factories() and not house.find_by_type("Broken")
        assert run.descriptor is old
        thermo.update(temp=28.0)
        assert house.get_property("Heater", "mode") == ""  # the old rule: > 30
        thermo.update(temp=31.0)
        assert house.get_property("Heater", "mode") == "cool"
        assert seen == []  # nothing was applied


def test_an_applied_part_says_each_change_and_keeps_values_changed_at_run_time():
    old = home(rule=RULE)
    new = home(rule=RULE, level=5)
    plan = diff(old, new)
    assert plan.lines == ("~ component Heater: property level: default 0 -> 5",)
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        seen = updated(run)
        house.set_property("Heater", "level", 2)  # changed at run time
        outcome = apply_part(run, "house", old, new, plan.part("house"),
                             classes=GivenClasses(), touched=lambda e, a: (e, a) == ("Heater", "level"))  # fmt: skip
        assert house.get_property("Heater", "level") == 2
        assert outcome.applied == [] and outcome.kept == [
            "~ component Heater: property level: default 0 -> 5: kept at 2, changed at run time "
            "(--reset sets the new default)"
        ]
        assert seen == []
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        seen = updated(run)
        house.set_property("Heater", "level", 2)
        outcome = apply_part(run, "house", old, new, plan.part("house"), classes=GivenClasses(),
                             touched=lambda e, a: True, reset=True)  # fmt: skip
        assert house.get_property("Heater", "level") == 5
        assert outcome.applied == list(plan.lines) and seen == list(plan.lines)
        assert run.descriptor is new
