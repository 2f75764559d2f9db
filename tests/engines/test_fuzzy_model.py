"""The oracle that builds a fuzzy engine straight from a pyecore model (tests/support/ecore_fuzzy_engine)
is itself right: it declares the scope's variables with their defaults, keeps the set's semantics and
infers what the hand-built engine of the same rules infers; rules outside the scope fail."""

from __future__ import annotations

import numpy as np
import pytest

from acordcs.engines.rule_engine import RuleError
from acordcs.metamodel import create, load
from acordcs.rules import parse_terms
from tests.support.ecore_fuzzy_engine import engine_for_policy_set
from tests.support.fuzzy_bases import SPEED_RULES, SPEED_VARIABLES, speed_engine


def _literal(enum: str, name: str):
    return load().getEClassifier(enum).getEEnumLiteral(name)


def _variable(name: str, lo: float, hi: float, terms: str, default: str | None = None):
    terms_ = [
        create(
            "LinguisticTerm",
            name=t.name.text,
            shape=_literal("MembershipShape", t.shape),
            parameters=list(t.parameters),
        )
        for t in parse_terms(terms)
    ]
    var = create("CtxVariable", rangeMin=lo, rangeMax=hi, terms=terms_)
    return create("Attribute", name=name, type="double", defaultValue=default, variable=var)


def speed_model(semantics: str = "mamdani", rules: list[str] | None = None):
    """The case study's speed policy: ControlMonitor feeds SpeedLimits, which adapts Locomotion."""
    monitor = create(
        "CtxMonitor",
        name="ControlMonitor",
        attributes=[_variable(n, *SPEED_VARIABLES[n]) for n in ("cycleRate", "angle")],
    )
    robot = create(
        "CtxComponent",
        name="Locomotion",
        attributes=[_variable("speed", *SPEED_VARIABLES["speed"], "100")],
    )
    policy = create(
        "CtxPolicy",
        name="speedPolicy",
        rules=[
            create("Rule", name=f"r{i}", label=None, text=t)
            for i, t in enumerate(rules or SPEED_RULES)
        ],
    )
    ps = create(
        "CtxPolicySet",
        name="SpeedLimits",
        semantics=_literal("FuzzySemantics", semantics),
        policies=[policy],
    )
    ps.adapts.append(robot)
    monitor.feeds.append(ps)
    create("Application", name="robotLab", monitors=[monitor], components=[robot], policySets=[ps])
    return ps


@pytest.mark.parametrize("semantics", ["mamdani", "sazonov"])
def test_policy_set_from_the_model_behaves_like_the_helper(semantics):
    ps = speed_model(semantics)
    engine = engine_for_policy_set(ps)
    assert sorted(engine.variables) == [
        "ControlMonitor.angle",
        "ControlMonitor.cycleRate",
        "Locomotion.speed",
    ]
    assert (
        engine.rulesets() == ["speedPolicy"]
        and engine.semantics_of("speedPolicy").name == semantics
    )
    assert engine.get("speed") == 100.0  # the attribute's default value is the initial value
    rng = np.random.default_rng(2)
    cols = {"cycleRate": rng.uniform(0, 3, 200), "angle": rng.uniform(0, 90, 200)}
    np.testing.assert_allclose(
        engine.batch("speedPolicy", cols)["Locomotion.speed"],
        speed_engine(semantics).batch("speed", cols)["speed"],
    )


def test_rules_out_of_scope_and_other_engines_are_errors():
    ps = speed_model(rules=["if cycleRate is small then Recovery.retries is slow"])
    with pytest.raises(RuleError, match=r"unknown variable 'Recovery\.retries'") as info:
        engine_for_policy_set(ps)
    assert info.value.ruleset == "speedPolicy"
    clips = speed_model()
    clips.engine = _literal("EngineKind", "clips")
    with pytest.raises(RuleError, match="uses engine 'clips'"):
        engine_for_policy_set(clips)
