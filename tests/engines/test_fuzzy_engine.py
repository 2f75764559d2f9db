"""The fuzzy engine behind the paper's four calls: contract, hedges, weights, methods, bad input."""

from __future__ import annotations

import logging
import math

import pytest

from acordcs.engines.fuzzy import FuzzyEngine, Semantics
from acordcs.engines.rule_engine import RuleEngine, RuleError
from tests.support.fuzzy_bases import speed_engine


def tiny(semantics="mamdani", **out_kwargs) -> FuzzyEngine:
    e = FuzzyEngine(semantics)
    e.define_variable("Sensor.level", 0, 10, "low := trape 0 0 2 6; high := trape 4 8 10 10")
    e.define_variable(
        "Pump.flow", 0, 100, "low := trian 0 0 50; high := trian 50 100 100", **out_kwargs
    )
    return e


def run(e: FuzzyEngine, ruleset: str, **inputs) -> float:
    for k, v in inputs.items():
        e.set(k, v)
    e.fire(ruleset)
    return e.get("Pump.flow")


def test_implements_the_protocol_and_the_paper_example():
    e = speed_engine()
    assert isinstance(e, RuleEngine)
    e.set("cycleRate", 0.3)
    e.set("angle", 5)
    e.fire("speed")
    # only "small and narrow -> fast" fires, fully: the centroid of trape 130 170 200 200
    fast_area = 20 + 30 + 0  # 130..170 ramp (20) + 170..200 flat (30)
    fast_moment = 20 * (130 + 2 / 3 * 40) + 30 * 185
    assert e.get("speed") == pytest.approx(fast_moment / fast_area, abs=1e-9)


def test_defrule_returns_labels_and_replaces_by_label():
    e = tiny()
    assert e.defrule("up: if level is low then flow is high", "p") == "up"
    assert run(e, "p", level=1) == pytest.approx(250 / 3)  # centroid of trian 50 100 100
    assert e.defrule("up: if level is low then flow is low", "p") == "up"  # replaced, not added
    assert [r.label for r in e.rules("p")] == ["up"]
    assert run(e, "p", level=1) == pytest.approx(50 / 3)


def test_unlabelled_rules_get_stable_labels():
    labels = []
    for _ in range(2):
        e = tiny()
        labels.append(
            [
                e.defrule("if level is low then flow is high", "p"),
                e.defrule("if level is high then flow is low", "p"),
            ]
        )
    assert labels[0] == labels[1] == ["rule1", "rule2"]
    e.remove_rule("rule1", "p")
    assert e.defrule("if level is low then flow is high", "p") == "rule3"  # the first free label
    assert [r.label for r in e.rules("p")] == ["rule2", "rule3"]


def test_qualified_and_unqualified_names():
    e = tiny()
    e.defrule("if Sensor.level is high then flow is high", "p")
    e.set("Sensor.level", 9)
    e.fire("p")
    assert e.get("flow") == e.get("Pump.flow")


def test_ambiguous_unqualified_name_lists_the_candidates():
    e = tiny()
    e.define_variable("Tank.level", 0, 5, "low := trian 0 0 5")
    with pytest.raises(RuleError, match=r"ambiguous.*Sensor\.level, Tank\.level") as info:
        e.defrule("r: if level is low then flow is high", "p")
    assert info.value.column == 7 and info.value.rule == "r" and info.value.ruleset == "p"
    with pytest.raises(RuleError, match="ambiguous"):
        e.set("level", 1)


@pytest.mark.parametrize(
    ("rule", "words", "column"),
    [
        ("r: if level is lowish then flow is high", "no term 'lowish'", 16),
        ("r: if depth is low then flow is high", "unknown variable 'depth'", 7),
        ("r: if level is low then flow is fast", "no term 'fast'", 33),
        ("r: if level low then flow is high", "unexpected 'low'", 13),
        ("r: if level is low then", "unexpected end of rule", 24),
    ],
)
def test_rule_errors_name_ruleset_rule_and_column(rule, words, column):
    e = tiny()
    with pytest.raises(RuleError, match=words) as info:
        e.defrule(rule, "pumping")
    err = info.value
    assert (err.ruleset, err.rule, err.column) == ("pumping", "r", column)
    assert "rule set 'pumping'" in str(err) and f"column {column}" in str(err)
    assert e.rulesets() == []  # nothing half-defined


def test_hedges_stack_innermost_last():
    e = FuzzyEngine()
    e.define_variable("x", 0, 10, "high := trian 0 10 10")
    e.define_variable(
        "y", 0, 1, "one := 1"
    )  # a singleton output: the crisp value is the degree * 1 / degree
    e.define_variable("d", 0, 1, "lo := 0; hi := 1", method="COGS")
    cases = {
        "very high": 0.6**2,
        "somewhat high": math.sqrt(0.6),
        "not very high": 1 - 0.6**2,
        "very not high": (1 - 0.6) ** 2,
        "not high": 0.4,
    }
    for text, degree in cases.items():
        e.defrule(f"a: if x is {text} then d is hi", text)
        e.defrule(f"b: if not (x is {text}) then d is lo", text)
        e.set("x", 6)
        e.fire(text)
        # COGS of hi at degree and lo at 1 - degree: exactly the degree
        assert e.get("d") == pytest.approx(degree, abs=1e-12), text


def test_weights_scale_the_degree():
    e = FuzzyEngine()
    e.define_variable("x", 0, 10, "high := trian 0 10 10")
    e.define_variable("d", 0, 1, "lo := 0; hi := 1")
    e.defrule("if x is high then d is hi with 0.5", "w")
    e.defrule("if x is high then d is lo", "w")
    e.set("x", 10)
    e.fire("w")
    assert e.get("d") == pytest.approx(0.5 / 1.5)
    with pytest.raises(RuleError, match=r"outside 0\.\.1"):
        e.defrule("if x is high then d is hi with 1.5", "w")


def test_no_rule_fired_takes_default_keeps_last_or_low_end():
    e = tiny(default=42)
    e.defrule("if level is high then flow is high", "p")
    assert run(e, "p", level=0) == 42 and e.defaulted("p") == ("Pump.flow",)
    assert run(e, "p", level=10) == pytest.approx(250 / 3) and e.defaulted("p") == ()

    nc = tiny(keep_last=True)
    nc.defrule("if level is high then flow is high", "p")
    assert run(nc, "p", level=0) == 0.0  # never had a value: the low end of the range
    high = run(nc, "p", level=10)
    assert run(nc, "p", level=0) == high  # NC: keeps its last value

    plain = tiny()  # no DEFAULT: jFuzzyLogic keeps the last value too
    plain.defrule("if level is high then flow is high", "p")
    assert run(plain, "p", level=10) == run(plain, "p", level=1)


def test_nan_and_inf_are_rejected_and_the_value_kept():
    e = tiny()
    e.set("level", 3)
    for bad in (float("nan"), float("inf"), -math.inf):
        with pytest.raises(RuleError, match="not a finite number"):
            e.set("level", bad)
    assert e.get("level") == 3
    with pytest.raises(RuleError, match="must be a number"):
        e.set("level", "high")


@pytest.mark.parametrize(
    ("bad", "words"),
    [
        (10**400, "beyond a float's range"),
        (-(10**5000), "beyond a float's range"),
        ("5", "must be a number, got str '5'"),
        (b"5", "must be a number, got bytes"),
        (None, "must be a number, got NoneType"),
        ("9" * 100, "got str '99999"),
    ],
    ids=["1e400", "-1e5000", "text 5", "bytes", "None", "long text"],
)
def test_huge_numbers_and_text_are_one_rule_error_and_the_value_kept(bad, words):
    e = tiny()
    e.set("level", 3)
    with pytest.raises(RuleError, match=words) as caught:
        e.set("level", bad)
    assert len(str(caught.value)) < 200
    assert e.get("level") == 3


def test_out_of_range_is_clamped_and_said_once(caplog):
    e = tiny()
    e.defrule("if level is high then flow is high", "p")
    with caplog.at_level(logging.WARNING, logger="acordcs.engines.fuzzy"):
        e.set("level", 25)
        e.set("level", 30)
        e.set("level", -4)
    assert e.get("level") == 0
    warnings = [r for r in caplog.records if "outside its range" in r.getMessage()]
    assert len(warnings) == 1 and "Sensor.level" in warnings[0].getMessage()
    e.set("level", 99)
    e.fire("p")
    assert e.get("flow") == pytest.approx(250 / 3)


def test_unset_input_and_unknown_ruleset_are_clear():
    e = tiny()
    e.defrule("if level is high then flow is high", "p")
    with pytest.raises(RuleError, match=r"input 'Sensor.level' has no value; call set"):
        e.fire("p")
    with pytest.raises(RuleError, match="no rule set 'q'"):
        e.fire("q")
    with pytest.raises(RuleError, match="has no value yet"):
        e.get("flow")
    with pytest.raises(RuleError, match="unknown variable 'depth'"):
        e.get("depth")


def test_semantics_per_ruleset():
    e = speed_engine()
    for r in e.rules("speed"):
        e.defrule(f"{r.label}: {r.text.split(': ', 1)[1]}", "paper")
    e.define_ruleset("paper", "sazonov")
    e.set("cycleRate", 1.4)
    e.set("angle", 41)
    e.fire("speed")
    mamdani = e.get("speed")
    e.fire("paper")
    assert e.get("speed") != pytest.approx(mamdani, abs=0.5)
    assert e.semantics_of("paper").name == "sazonov" and e.semantics_of("speed").name == "mamdani"
    with pytest.raises(RuleError, match="unknown fuzzy semantics 'fuzzy-ish'"):
        FuzzyEngine("fuzzy-ish")
    with pytest.raises(RuleError, match="unknown ACCU operator 'AVG'"):
        Semantics(accu="AVG")


def test_redefining_a_variable_rechecks_rules():
    e = tiny()
    e.defrule("if level is high then flow is high", "p")
    with pytest.raises(RuleError, match="no term 'high'"):
        e.define_variable("Sensor.level", 0, 10, "low := trian 0 0 10")
    with pytest.raises(RuleError, match="COGS needs singleton terms"):
        e.define_variable(
            "Pump.flow", 0, 100, "low := trian 0 0 50; high := trian 50 100 100", method="COGS"
        )
    e.define_variable("Sensor.level", 0, 20, "low := trian 0 0 10; high := trian 10 20 20")
    assert run(e, "p", level=20) == pytest.approx(250 / 3)


@pytest.mark.parametrize(
    ("method", "expected"),
    [
        ("LM", 20.0),  # the left end of the top plateau of the clipped 'high' triangle
        ("RM", 100.0),
        ("MM", 60.0),
        ("COA", None),
    ],
)
def test_maximum_methods_and_coa_exactly(method, expected):
    e = FuzzyEngine()
    e.define_variable("x", 0, 1, "a := trian 0 1 1")
    e.define_variable("y", 0, 100, "high := trian 0 100 100", method=method)
    e.defrule("if x is a then y is high", "m")
    e.set("x", 0.2)  # clips 'high' at 0.2: plateau 20..100
    e.fire("m")
    if expected is None:
        # min(0.2, y/100) over 0..100: area 2 up to y=20, then 0.2 per unit; half of 18 is at y=55
        assert e.get("y") == pytest.approx(55.0, abs=1e-12)
    else:
        assert e.get("y") == pytest.approx(expected, abs=1e-12)


def test_singleton_outputs_and_method_mismatch(caplog):
    e = FuzzyEngine()
    e.define_variable("x", 0, 1, "a := trian 0 1 1; b := trian 0 0 1")
    e.define_variable("y", 0, 100, "lo := 10; hi := 90")
    e.defrule("if x is a then y is hi", "s")
    e.defrule("if x is b then y is lo", "s")
    e.set("x", 0.25)
    e.fire("s")
    assert e.get("y") == pytest.approx(0.25 * 90 + 0.75 * 10)
    e.define_variable("z", 0, 100, "mid := trian 0 50 100", method="COGS")
    with pytest.raises(RuleError, match="COGS needs singleton terms"):
        e.defrule("if x is a then z is mid", "s")
    # A singleton beside shaped terms has no width: no method sees it (jFuzzyLogic's sampled set
    # misses it too), and the plan says so once.
    e.define_variable("w", 0, 100, "mid := trian 0 50 100; top := 100")
    e.defrule("if x is a then w is mid", "t")
    e.defrule("if x is a then w is top", "t")
    e.fire("t")
    assert e.get("w") == pytest.approx(50.0)
    assert "1 singleton term(s) beside shaped ones have no width" in caplog.text


@pytest.mark.parametrize(("method", "expected"), [("LM", 90.0), ("RM", 90.0), ("MM", 90.0)])
def test_a_set_of_tiny_height_still_has_its_own_maximum(method, expected):
    """The maximum is taken within 1e-12 of the set's height, not within 1e-12 absolute: a rule
    firing at 1e-28 alone made every singleton (at 0) a maximum."""
    e = FuzzyEngine()
    e.define_variable("x", 0, 1, "a := trian 0 1 1; b := trian 0 0 1")
    e.define_variable("y", 0, 100, "lo := 10; hi := 90", method=method)
    e.defrule("if x is a then y is hi", "s")
    e.defrule("if x is b then y is lo with 0", "s")
    e.set("x", 1e-28)
    e.fire("s")
    assert e.get("y") == expected


def test_bad_variable_declarations():
    e = FuzzyEngine()
    with pytest.raises(RuleError, match="empty or not finite"):
        e.define_variable("v", 5, 5, "")
    with pytest.raises(RuleError, match="lies outside the range"):
        e.define_variable("v", 0, 10, "far := trian 20 30 40")
    with pytest.raises(RuleError, match="defined twice"):
        e.define_variable("v", 0, 10, "a := trian 0 1 2; a := trian 2 3 4")
    with pytest.raises(RuleError, match="inverted"):
        e.define_variable("v", 0, 10, "a := trian 5 1 8")
    with pytest.raises(RuleError, match="terms do not parse"):
        e.define_variable("v", 0, 10, "a = trian 0 1 2")
    with pytest.raises(RuleError, match="not both"):
        e.define_variable("v", 0, 10, "", default=1, keep_last=True)
