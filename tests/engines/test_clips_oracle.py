"""CLIPS results against an independent plain-Python evaluation of the same crisp rules (the
oracle and the random rule sets are in ``tests/support/clips_oracle.py``)."""

from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from acordcs.engines.clips import ClipsEngine
from tests.support.clips_oracle import (
    NAMES,
    Oracle,
    check_fire,
    recorder,
    rule_sets,
    same,
    values,
)

# ------------------------------------------------------------------------ the paper's recovery policy
RECOVERY = [
    "count: if Control.speed == 0 then Recovery.zeros = Recovery.zeros + 1",
    "retry: if Control.speed == 0 and Recovery.zeros <= 3 then Recovery.recover()",
    "giveup: if Control.speed == 0 and Recovery.zeros == 4 then Recovery.askUser(Recovery.zeros)",
    "reset: if Control.speed > 0 then Recovery.zeros = 0",
]
speeds = st.one_of(
    st.sampled_from([0, 0.0, 5, -1]),
    st.integers(-3, 300),
    st.floats(allow_nan=True, allow_infinity=True),
)


@settings(max_examples=60, deadline=None)
@given(st.lists(speeds, min_size=1, max_size=25))
def test_recovery_policy_matches_oracle(sequence):
    engine = ClipsEngine()
    engine.declare("Control.speed", 0.0)
    engine.declare("Recovery.zeros", 0)
    for rule in RECOVERY:
        engine.defrule(rule, "recovery")
    calls = recorder(engine, ["Recovery.recover", "Recovery.askUser"])
    oracle = Oracle([r.split(": ", 1)[1] for r in RECOVERY], ["Control.speed", "Recovery.zeros"])
    env = {"Control.speed": 0.0, "Recovery.zeros": 0}
    for speed in sequence:
        engine.set("Control.speed", speed)
        env["Control.speed"] = speed
        engine.fire("recovery")
        expected_calls, _ = oracle.fire(env)
        assert [c[0] for c in calls] == [c[0] for c in expected_calls]
        assert same(engine.get("Recovery.zeros"), env["Recovery.zeros"])
        calls.clear()


@settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rule_sets(), st.lists(values, min_size=1, max_size=3))
def test_random_rule_sets_match_oracle(rules, rounds):
    engine = ClipsEngine()
    for name, value in rounds[0].items():
        engine.declare(name, value)
    for i, text in enumerate(rules):
        engine.defrule(f"r{i}: {text}", "random")
    calls = recorder(engine, ["Trace.fired"])
    oracle = Oracle(rules, NAMES)
    env = dict(rounds[0])
    for i, round_values in enumerate(rounds):
        if i:
            for name, value in round_values.items():
                engine.set(name, value)
            env.update(round_values)
        check_fire(engine, oracle, env, calls, "random")
        # A second fire on the values the rules left: the rules run again, from those values.
        check_fire(engine, oracle, env, calls, "random")
