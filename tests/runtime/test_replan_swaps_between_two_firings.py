"""``PolicySet.replan``: a running policy set takes a new plan between two firings. Firings that run
while plans are swapped from another thread each run wholly on one plan (never the old engine
with the new plan's outputs); a crisp engine keeps the values of the variables both plans have;
what fires the set changes with the plan (an event fires it once, whichever plan), and the undo
returns the old engine as it was."""

from __future__ import annotations

import sys
import threading
import time
from dataclasses import replace
from typing import ClassVar

from acordcs.engines.plan import plan_from_descriptor
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import RealClock, VirtualClock
from acordcs.runtime.component import CtxComponent
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    op,
    policy_set,
    prop,
    ref,
    variable,
)

TEMP = variable("Thermo", "temp", 0, 40, cold="trapezoid 0 0 10 20", warm="trapezoid 15 25 40 40")
POWER = variable("Heater", "power", 0, 100, low="triangle 0 0 50", high="triangle 50 100 100")
FAN = variable("Heater", "fan", 0, 100, low="triangle 0 0 50", high="triangle 50 100 100")


def heating(
    rules: list[str], *, engine: str = "fuzzy", trigger: str = "event", operations=(), **more
):
    # each fuzzy plan declares the output variable its rules write, and only that one
    output = FAN if any("fan" in r for r in rules) else POWER
    return application(
        "Home",
        containers=(
            container(
                "house",
                ref("component", "Heater"),
                ref("monitor", "Thermo"),
                ref("policy-set", "Comfort"),
            ),
        ),
        components=(
            component(
                "Heater",
                properties=(
                    prop("power", 0.0),
                    prop("fan", 0.0),
                    prop("level", 0),
                    prop("mode", ""),
                ),
                operations=operations,
            ),
        ),
        monitors=(monitor("Thermo", prop("temp", 20.0), feeds=("Comfort",)),),
        policy_sets=(
            policy_set(
                "Comfort",
                {"rules": rules},
                engine=engine,
                trigger=trigger,
                adapts=(ref("component", "Heater"),),
                variables=(TEMP, output) if engine == "fuzzy" else (),
                **more,
            ),
        ),
    )


POWER_RULES = [
    "if temp is cold then Heater.power is high",
    "if temp is warm then Heater.power is low",
]
FAN_RULES = ["if temp is cold then Heater.fan is low", "if temp is warm then Heater.fan is high"]


def test_concurrent_firings_each_run_on_one_plan():
    # The two plans write different properties: a firing that took the old engine and the new
    # plan's outputs (or the reverse) would ask the engine for a variable it does not have: a
    # fault. Firings run on one thread while another swaps the plans back and forth.
    old, new = heating(POWER_RULES), heating(FAN_RULES)
    plans = [plan_from_descriptor(a.policy_sets[0]) for a in (old, new)]
    with assemble(old, clock=RealClock()) as run:
        house = run.container("house")
        comfort = house.policy_set("Comfort")
        thermo = house.monitor("Thermo")
        stop = threading.Event()
        temps = [5.0, 30.0]

        def drive() -> None:
            i = 0
            while not stop.is_set():
                thermo.update(temp=temps[i % 2])
                i += 1

        driver = threading.Thread(target=drive)
        interval = sys.getswitchinterval()
        sys.setswitchinterval(1e-6)  # threads take turns often: a firing is swapped under often
        driver.start()
        # swaps go on until the firings number over 300, however slowly a loaded host lets the
        # driver run; an even number of swaps ends on the first plan
        swaps, deadline = 0, time.monotonic() + 120
        try:
            while (
                swaps < 300 or comfort.fires <= 300 or swaps % 2
            ) and time.monotonic() < deadline:
                comfort.replan(plans[(swaps + 1) % 2], trigger="event", frequency=None,
                               adapts=["Heater"], fed_by=["Thermo"])  # fmt: skip
                swaps += 1
        finally:
            stop.set()
            driver.join()
            sys.setswitchinterval(interval)
        assert comfort.fires > 300
        assert house.faults.counts["total"] == 0, list(house.faults.recent)[:3]
        # each plan wrote its own property, with its own rules' values
        assert house.get_property("Heater", "power") > 0
        assert house.get_property("Heater", "fan") > 0
        assert comfort.plan is plans[0]  # an even number of swaps: back to the first


class SwappingHeater(CtxComponent):
    """A heater whose ``swap`` operation, called by the set's rule while the set fires, gives
    the set another plan (``PLAN``) mid-firing."""

    properties: ClassVar[dict[str, object]] = {"power": 0.0, "fan": 0.0, "level": 0, "mode": ""}
    PLAN: ClassVar[list] = []

    def swap(self) -> None:
        self.container.policy_set("Comfort").replan(
            self.PLAN[0], trigger="event", frequency=None, adapts=["Heater"], fed_by=["Thermo"]
        )


def test_a_firing_under_way_ends_on_the_plan_it_started_with():
    # The old plan's rule calls swap(), which replans the set while it fires; the firing then
    # writes back the old plan's outputs (Heater.level) with the old engine. Were it to read the
    # new plan's outputs (Heater.mode, which the old engine does not have), that is a fault.
    def app(rule: str):
        return heating([rule], engine="clips", operations=(op("swap"),))

    old = app("go: if Thermo.temp > 30 then Heater.level = 1 and Heater.swap()")
    new = app('go: if Thermo.temp > 30 then Heater.mode = "new"')
    SwappingHeater.PLAN[:] = [plan_from_descriptor(new.policy_sets[0])]
    with assemble(old, clock=VirtualClock(), factories={"Heater": SwappingHeater}) as run:
        house = run.container("house")
        house.monitor("Thermo").update(temp=35.0)
        assert house.faults.counts["total"] == 0, list(house.faults.recent)
        assert house.get_property("Heater", "level") == 1
        assert house.get_property("Heater", "mode") == ""
        assert house.policy_set("Comfort").plan is SwappingHeater.PLAN[0]
        house.monitor("Thermo").update(temp=36.0)  # the next firing: the new plan
        assert house.get_property("Heater", "mode") == "new"


def test_the_next_firing_runs_the_new_rules_and_undo_returns_the_old():
    old = heating(POWER_RULES)
    new = heating(
        ["if temp is cold then Heater.power is low", "if temp is warm then Heater.power is high"]
    )
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        comfort = house.policy_set("Comfort")
        thermo = house.monitor("Thermo")
        thermo.update(temp=5.0)
        high = house.get_property("Heater", "power")
        assert high > 60
        engine = comfort.engine
        undo = comfort.replan(plan_from_descriptor(new.policy_sets[0]), trigger="event",
                              frequency=None, adapts=["Heater"], fed_by=["Thermo"])  # fmt: skip
        thermo.update(temp=5.0)
        assert house.get_property("Heater", "power") < 40  # cold -> low now
        undo()
        assert comfort.engine is engine
        thermo.update(temp=5.0)
        assert house.get_property("Heater", "power") == high


def test_a_crisp_engine_keeps_the_values_both_plans_have():
    rules = ['if Thermo.temp > 30 then Heater.mode = "cool" and Heater.level = Heater.level + 1']
    old = heating(rules, engine="clips")
    new = heating([rules[0].replace("> 30", "> 25")], engine="clips")
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        comfort = house.policy_set("Comfort")
        house.monitor("Thermo").update(temp=35.0)
        assert comfort.engine.get("Heater.mode") == "cool"
        comfort.replan(plan_from_descriptor(new.policy_sets[0]), trigger="event",
                       frequency=None, adapts=["Heater"], fed_by=["Thermo"])  # fmt: skip
        # the new engine starts with the values the old one held, not unset
        assert comfort.engine.get("Heater.mode") == "cool"
        assert comfort.engine.get("Thermo.temp") == 35.0
        house.monitor("Thermo").update(temp=27.0)
        assert house.get_property("Heater", "level") == 2


def test_an_event_fires_the_set_once_when_what_fires_it_changes():
    old = heating(POWER_RULES)
    periodic = heating(POWER_RULES, trigger="periodic", frequency=2.0)
    with assemble(old, clock=VirtualClock()) as run:
        house, clock = run.container("house"), run.clock
        comfort = house.policy_set("Comfort")
        thermo = house.monitor("Thermo")
        thermo.update(temp=5.0)
        assert comfort.fires == 1
        undo = comfort.replan(plan_from_descriptor(periodic.policy_sets[0]), trigger="periodic",
                              frequency=2.0, adapts=["Heater"], fed_by=["Thermo"])  # fmt: skip
        thermo.update(temp=6.0)
        assert comfort.fires == 1  # periodic now: a reading does not fire it
        clock.run_for(1.0)
        assert comfort.fires == 3  # 2 Hz
        undo()
        clock.run_for(1.0)
        assert comfort.fires == 3  # the timer went with the periodic plan
        thermo.update(temp=7.0)
        assert comfort.fires == 4  # once per reading, as before


def test_a_set_resubscribes_only_when_its_triggers_change():
    old = heating(POWER_RULES)
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("house")
        comfort = house.policy_set("Comfort")
        plan = plan_from_descriptor(old.policy_sets[0])
        same = replace(plan, rules=tuple(reversed(plan.rules)))
        comfort.replan(same, trigger="event", frequency=None, adapts=["Heater"], fed_by=["Thermo"])
        house.monitor("Thermo").update(temp=5.0)
        assert comfort.fires == 1
        comfort.detach()  # unsubscribes under the label it has: nothing left firing it
        house.monitor("Thermo").update(temp=6.0)
        assert comfort.fires == 1
