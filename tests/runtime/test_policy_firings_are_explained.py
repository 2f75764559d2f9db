"""What a policy set's last firing says (for the WebLab console): the fuzzy engine's per-rule firing
strengths (``FuzzyEngine.explain``) agree with scikit-fuzzy's, an independent implementation; the
CLIPS engine says which crisp rules fired in its last fire; a policy set keeps its last firing
(time, inputs, outputs, rule degrees) and emits ``policy.fired``."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from acordcs.engines.engine_registry import Variable
from acordcs.engines.fuzzy import FuzzyEngine
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.policy import PolicySet

RULES = {
    "r1": "r1: if rate is small and angle is narrow then speed is slow",
    "r2": "r2: if rate is large or not (angle is wide) then speed is fast",
    "r3": "r3: if (rate is small or rate is large) and not (angle is narrow) then speed is slow with 0.5",
}


def engine() -> FuzzyEngine:
    e = FuzzyEngine("mamdani")
    e.define_variable("rate", 0, 3, "small := trape 0 0 0.8 1.2; large := trape 1 2 3 3")
    e.define_variable("angle", 0, 90, "narrow := trape 0 0 5 15; wide := trian 10 45 80")
    e.define_variable("speed", 0, 200, "slow := trian 0 50 100; fast := trian 80 150 200")
    for rule in RULES.values():
        e.defrule(rule, "main")
    return e


def skfuzzy_strengths(rate: float, angle: float) -> dict[str, float]:
    """The same rules in scikit-fuzzy's control API; each rule's firing after a simulation."""
    fuzz = pytest.importorskip("skfuzzy")
    from skfuzzy import control as ctrl

    ur = np.round(np.arange(0, 3.0001, 0.01), 2)
    ua = np.round(np.arange(0, 90.0001, 0.5), 1)
    r = ctrl.Antecedent(ur, "rate")
    r["small"], r["large"] = fuzz.trapmf(ur, [0, 0, 0.8, 1.2]), fuzz.trapmf(ur, [1, 2, 3, 3])
    a = ctrl.Antecedent(ua, "angle")
    a["narrow"], a["wide"] = fuzz.trapmf(ua, [0, 0, 5, 15]), fuzz.trimf(ua, [10, 45, 80])
    s = ctrl.Consequent(np.arange(0, 201, 1.0), "speed")
    s["slow"], s["fast"] = (
        fuzz.trimf(s.universe, [0, 50, 100]),
        fuzz.trimf(s.universe, [80, 150, 200]),
    )
    rules = {
        "r1": ctrl.Rule(r["small"] & a["narrow"], s["slow"]),
        "r2": ctrl.Rule(r["large"] | ~a["wide"], s["fast"]),
        "r3": ctrl.Rule((r["small"] | r["large"]) & ~a["narrow"], s["slow"]),
    }
    sim = ctrl.ControlSystemSimulation(ctrl.ControlSystem(list(rules.values())))
    sim.input["rate"], sim.input["angle"] = rate, angle
    sim.compute()
    out = {k: float(rule.aggregate_firing[sim]) for k, rule in rules.items()}
    out["r3"] *= 0.5  # the rule's weight (scikit-fuzzy's rules have none)
    return out


# Inputs on scikit-fuzzy's universes' grid points, where its interpolation is exact.
@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # scikit-fuzzy's own use of numpy
@settings(max_examples=40, deadline=None)
@given(st.integers(0, 300), st.integers(0, 180))
def test_fuzzy_rule_strengths_agree_with_scikit_fuzzy(rate_cents, angle_halves):
    rate, angle = rate_cents / 100, angle_halves / 2
    e = engine()
    e.set("rate", rate)
    e.set("angle", angle)
    assert e.explain("main") == pytest.approx(skfuzzy_strengths(rate, angle), abs=1e-9)


def test_explain_on_given_values_changes_nothing_and_gives_zero_for_unset_inputs():
    e = engine()
    assert e.explain("main") == {"r1": 0.0, "r2": 0.0, "r3": 0.0}  # nothing set yet
    e.set("rate", 0.5)
    e.set("angle", 3.0)
    e.fire("main")
    speed = e.get("speed")
    asked = e.explain("main", {"rate": 2.5, "angle": 60.0})
    assert asked == pytest.approx({"r1": 0.0, "r2": 1.0, "r3": 0.5})
    assert e.explain("main") == pytest.approx({"r1": 1.0, "r2": 1.0, "r3": 0.0})
    assert e.get("speed") == speed  # read-only


def test_a_rule_at_the_depth_limit_is_explained_without_recursion():
    from acordcs.rules.tree import MAX_DEPTH

    e = engine()
    # "not (not (... rate is small))": the deepest nesting the parser accepts.
    depth = MAX_DEPTH - 2
    e.defrule(
        "deep: if " + "not (" * depth + "rate is small" + ")" * depth + " then speed is slow",
        "deep",
    )
    e.set("rate", 1.1)
    expected = 0.25 if depth % 2 == 0 else 0.75
    assert e.explain("deep")["deep"] == pytest.approx(expected)


def test_the_clips_engine_says_which_crisp_rules_fired():
    from acordcs.engines.clips.clips_engine import ClipsEngine

    e = ClipsEngine()
    e.declare("Control.speed", 1.0, type="double")
    e.declare("Recovery.retries", 0, type="int")
    e.declare("Recovery.asked", 0, type="int")
    for rule in (
        "count: if Control.speed == 0 then Recovery.retries = Recovery.retries + 1",
        "retry: if Control.speed == 0 and Recovery.retries <= 3 then Recovery.retries = Recovery.retries",
        "giveUp: if Control.speed == 0 and Recovery.retries == 4 then Recovery.asked = 1",
        "recovered: if Control.speed > 0 and Recovery.retries > 0 then Recovery.retries = 0",
    ):
        e.defrule(rule, "recovery")
    assert set(e.explain("recovery").values()) == {0.0}  # before any fire
    e.set("Control.speed", 0.0)
    e.fire("recovery")
    assert e.explain("recovery") == {"count": 1.0, "retry": 1.0, "giveUp": 0.0, "recovered": 0.0}
    e.set("Recovery.retries", 3)
    e.fire("recovery")
    assert e.explain("recovery") == {"count": 1.0, "retry": 0.0, "giveUp": 1.0, "recovered": 0.0}
    e.set("Control.speed", 50.0)
    e.fire("recovery")  # retries was 4
    assert e.explain("recovery") == {"count": 0.0, "retry": 0.0, "giveUp": 0.0, "recovered": 1.0}
    e.fire("recovery")  # retries is 0 now: nothing holds
    assert e.explain("recovery") == {"count": 0.0, "retry": 0.0, "giveUp": 0.0, "recovered": 0.0}


class Locomotion(CtxComponent):
    properties = {"speed": 100.0, "retries": 0}  # noqa: RUF012


class Control(Monitor):
    pass


@pytest.fixture
def robot():
    with Container("robot", clock=VirtualClock()) as c:
        c.install_factory(ComponentFactory("Locomotion", Locomotion))
        c.create("Locomotion", "Locomotion")
        control = Control("control", attributes={"rate": 1.0, "angle": 0.0})
        c.add_monitor(control)
        yield c, control


@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_a_fuzzy_policy_set_keeps_its_last_firing_and_emits_policy_fired(robot):
    c, control = robot
    c.add_policy_set(
        PolicySet(
            "limit",
            {
                "main": [
                    RULES["r1"].replace("speed", "Locomotion.speed"),
                    RULES["r2"].replace("speed", "Locomotion.speed"),
                ]
            },
            engine="fuzzy",
            adapts=["Locomotion"],
            fed_by=["control"],
            variables={
                "control.rate": Variable(
                    0, 3, "small := trape 0 0 0.8 1.2; large := trape 1 2 3 3"
                ),
                "control.angle": Variable(
                    0, 90, "narrow := trape 0 0 5 15; wide := trian 10 45 80"
                ),
                "Locomotion.speed": Variable(
                    0, 200, "slow := trian 0 50 100; fast := trian 80 150 200"
                ),
            },
        )
    )
    seen = []
    c.subscribe("policy.fired", lambda event: seen.append(event), name="console")
    c.clock.run_until(2.5)
    control.update(rate=1.1, angle=12.0)
    ps = c.policy_set("limit")
    firing = ps.last_firing
    assert firing is not None and firing.time == 2.5
    assert firing.inputs == {"control.rate": 1.1, "control.angle": 12.0}  # the variables' names
    assert firing.outputs == {"Locomotion.speed": c.get_property("Locomotion", "speed")}
    want = skfuzzy_strengths(1.1, 12.0)
    assert firing.rules == pytest.approx({("main", "r1"): want["r1"], ("main", "r2"): want["r2"]})
    assert [(e.kind, e.element) for e in seen] == [("policy.fired", "limit")]
    assert ps.last_firing is firing  # the same until the set fires again


def test_a_clips_policy_set_records_the_rules_that_fired_when_tracing(robot):
    c, control = robot
    rules = [
        "stopped: if control.rate < 0.5 then Locomotion.retries = Locomotion.retries + 1",
        "moving: if control.rate >= 0.5 then Locomotion.retries = 0",
    ]
    c.add_policy_set(
        PolicySet(
            "count", {"main": rules}, engine="clips", adapts=["Locomotion"], fed_by=["control"]
        )
    )
    ps = c.policy_set("count")
    control.update(rate=0.2)
    assert ps.last_firing.rules == {}  # not traced: nothing read back from CLIPS
    ps.trace_rules = True
    control.update(rate=0.1)
    assert ps.last_firing.rules == {("main", "stopped"): 1.0, ("main", "moving"): 0.0}
    assert ps.last_firing.outputs == {"Locomotion.retries": 2}
    control.update(rate=1.0)
    assert ps.last_firing.rules == {("main", "stopped"): 0.0, ("main", "moving"): 1.0}
