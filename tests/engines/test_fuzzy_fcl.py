"""FCL reader and writer: jFuzzyLogic-style files, defaults, round trips, errors with file:line:col."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings

from acordcs.engines.fuzzy import FuzzyEngine, Semantics, read_fcl, write_fcl
from acordcs.engines.rule_engine import RuleError
from tests.support.fuzzy_bases import speed_engine
from tests.support.fuzzy_oracle import oracle, rule_base

FCL = Path(__file__).parent / "fcl"
FILES = sorted(p.name for p in FCL.glob("*.fcl"))


def _same_behaviour(a: FuzzyEngine, b: FuzzyEngine, seed: int = 0) -> None:
    rng = np.random.default_rng(seed)
    for rs in a.rulesets():
        compiled = a._compile(rs)
        cols = {v: rng.uniform(a.variables[v].lo, a.variables[v].hi, 200) for v in compiled.inputs}
        got, want = b.batch(rs, cols), a.batch(rs, cols)
        assert got.keys() == want.keys()
        for k in want:
            np.testing.assert_array_equal(got[k], want[k])


@pytest.mark.parametrize("name", FILES)
def test_write_then_read_gives_an_identical_engine(name):
    first = read_fcl(FCL / name)
    text = write_fcl(first)
    second = read_fcl(text)
    assert write_fcl(second) == text
    assert list(second) == list(first)
    for key in first:
        assert second[key].variables == first[key].variables
        for rs in first[key].rulesets():
            assert second[key].semantics_of(rs) == first[key].semantics_of(rs)
            assert [
                (r.label, r.condition, r.consequents, r.weight) for r in second[key].rules(rs)
            ] == [(r.label, r.condition, r.consequents, r.weight) for r in first[key].rules(rs)]
        _same_behaviour(first[key], second[key])


TIPPER = {
    "service": (
        0,
        9,
        "poor := (0, 1) (4, 0); good := (1, 0) (4, 1) (6, 1) (9, 0); excellent := (6, 0) (9, 1)",
    ),
    "food": (0, 9, "rancid := (0, 1) (1, 1) (3, 0); delicious := (7, 0) (9, 1)"),
    "tip": (
        0,
        30,
        "cheap := (0, 0) (5, 1) (10, 0); average := (10, 0) (15, 1) (20, 0); generous := (20, 0) (25, 1) (30, 0)",
    ),
}
TIPPER_RULES = [
    "if service is poor or food is rancid then tip is cheap",
    "if service is good then tip is average",
    "if service is excellent and food is delicious then tip is generous",
]


@pytest.mark.parametrize(("service", "food"), [(3, 8), (0, 0), (5, 5), (9, 9), (7.3, 1.2)])
def test_tipper_as_jfuzzylogic_writes_it(service, food):
    tipper = read_fcl(FCL / "tipper.fcl")["tipper"]
    assert (
        tipper.variables["service"].lo == 0 and tipper.variables["service"].hi == 9
    )  # from its terms
    tipper.set("service", service)
    tipper.set("food", food)
    tipper.fire("No1")
    want = oracle(TIPPER, TIPPER_RULES, {"service": service, "food": food}, "tip", Semantics())
    assert tipper.get("tip") == pytest.approx(want, abs=1e-5)
    assert [r.label for r in tipper.rules("No1")] == ["1", "2", "3"]


def test_several_blocks_comments_defaults_and_mixed_case():
    blocks = read_fcl(FCL / "multi.fcl")
    assert list(blocks) == ["heater", "valve"]
    heater = blocks["heater"]
    # no AND/ACT/ACCU/METHOD in the block: jFuzzyLogic's defaults
    assert heater.semantics_of("heating") == Semantics(
        and_="MIN", or_="MAX", act="MIN", accu="SUM", method="COG"
    )
    assert heater.variables["power"].keep_last and heater.variables["power"].method is None
    assert [r.weight for r in heater.rules("heating")] == [1.0, 0.8, 1.0]
    valve = blocks["valve"]
    assert (
        valve.semantics_of("control").and_ == "PROD" and valve.semantics_of("control").or_ == "ASUM"
    )
    valve.set("level", 9)
    valve.set("flow", 8)
    valve.fire("control")
    assert 0 <= valve.get("opening") <= 100
    assert len(read_fcl((FCL / "multi.fcl").read_text())) == 2


@pytest.mark.parametrize("semantics", ["mamdani", "sazonov", "fcl"])
def test_engine_to_fcl_and_back(semantics):
    engine = speed_engine(semantics)
    engine.name = "speedPolicy"
    back = one_block(write_fcl(engine))
    assert back.semantics_of("speed") == engine.semantics_of("speed")
    assert back.semantics_of("speed").name == semantics
    assert write_fcl(back) == write_fcl(engine)
    _same_behaviour(engine, back)


def test_hedges_weights_and_qualified_names_survive_the_round_trip():
    e = FuzzyEngine(name="hedged")
    e.define_variable("Sensor.level", 0, 10, "low := trape 0 0 2 6; high := trape 4 8 10 10")
    e.define_variable(
        "Pump.flow", 0, 100, "low := trian 0 0 50; high := trian 50 100 100", default=7
    )
    e.defrule(
        "a: if level is not very high or not (level is somewhat low) then flow is high with 0.25",
        "p",
    )
    e.defrule("if Sensor.level is low then Pump.flow is low", "p")
    text = write_fcl(e)
    # Rules are written as resolved: the names of the variables they were bound to.
    assert "Sensor.level IS NOT very high OR NOT (Sensor.level IS somewhat low)" in text
    assert "THEN Pump.flow IS high WITH 0.25" in text
    assert "DEFAULT := 7;" in text
    back = one_block(text)
    assert write_fcl(back) == text
    _same_behaviour(e, back)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(rule_base())
def test_random_rule_bases_round_trip(base):
    variables, rules, _ = base
    e = FuzzyEngine(Semantics(act="PROD", accu="BSUM", method="COA"), name="random")
    for name, (lo, hi, terms) in variables.items():
        e.define_variable(name, lo, hi, terms, default=lo)
    for r in rules:
        e.defrule(r, "rs")
    back = one_block(write_fcl(e))
    assert write_fcl(back) == write_fcl(e)
    _same_behaviour(e, back)


BAD = {
    "unknown_method": ("METHOD : CENTROID;", "unknown METHOD CENTROID", 10),
    "cogf": ("METHOD : COGF;", "unknown METHOD COGF", 10),
}


def _block(
    defuzz_extra: str = "METHOD : COG;",
    rules: str = "RULE 1 : IF x IS a THEN y IS b;",
    end: bool = True,
) -> str:
    return (
        "FUNCTION_BLOCK t\n"  # 1
        "VAR_INPUT x : REAL; END_VAR\n"  # 2
        "VAR_OUTPUT y : REAL; END_VAR\n"  # 3
        "FUZZIFY x\n"  # 4
        "  TERM a := trian 0 1 2;\n"  # 5
        "END_FUZZIFY\n"  # 6
        "DEFUZZIFY y\n"  # 7
        "  TERM b := trian 0 5 10;\n"  # 8
        f"  {defuzz_extra}\n"  # 9
        "END_DEFUZZIFY\n"  # 10
        "RULEBLOCK r\n"  # 11
        f"  {rules}\n"  # 12
        "END_RULEBLOCK\n" + ("END_FUNCTION_BLOCK\n" if end else "")  # 13
    )


@pytest.mark.parametrize(
    ("text", "words", "line", "column"),
    [
        (_block("METHOD : CENTROID;"), "unknown METHOD CENTROID for y; use one of COG", 9, 12),
        (_block("METHOD : COGF;"), "unknown METHOD COGF", 9, 12),
        (_block(rules="ACCU : AVG;"), "unknown ACCU operator AVG in RULEBLOCK r", 12, 10),
        (_block(rules="AND : YAGER;"), "unknown AND operator YAGER", 12, 9),
        (_block("TERM c := cosine 1 2;"), "membership function cosine is not supported", 9, 13),
        (_block("TERM c := trian 5 1 8;"), "inverted", 9, 13),
        (_block("DEFAULT := MAYBE;"), "DEFAULT must be a number or NC", 9, 14),
        (_block(rules="RULE 1 : IF z IS a THEN y IS b;"), "unknown variable 'z'", 12, 15),
        (_block(rules="RULE 1 : IF x IS c THEN y IS b;"), "variable 'x' has no term 'c'", 12, 20),
        (
            _block(rules="RULE 1 : IF x IS a THEN y IS b WITH 2;"),
            "rule 1: weight 2.0 is outside 0..1",
            12,
            39,
        ),
        (_block(end=False), "missing END_FUNCTION_BLOCK", 13, 14),
        (
            _block().replace("END_FUZZIFY\n", ""),
            "missing END_FUZZIFY: the FUZZIFY block \\(opened at line 4\\)",
            6,
            1,
        ),
        (_block().replace("END_RULEBLOCK\n", ""), "missing END_RULEBLOCK", 13, 1),
        (
            _block().replace("FUZZIFY x", "FUZZIFY w"),
            "FUZZIFY w: w is not declared in VAR_INPUT",
            4,
            9,
        ),
        (_block().replace("y : REAL", "y : INT"), "type INT; fuzzy variables are REAL", 3, 16),
        (
            _block().replace("TERM a", "TERM a := trian 0 1 2; TERM a"),
            "term a of x is defined twice",
            5,
            31,
        ),
        (
            "FUNCTION_BLOCK t VAR_INPUT x : REAL; END_VAR ~ END_FUNCTION_BLOCK",
            "unexpected character '~'",
            1,
            46,
        ),
    ],
)
def test_bad_fcl_is_an_error_with_file_line_column(text, words, line, column):
    with pytest.raises(RuleError, match=words) as info:
        read_fcl(text, filename="bad.fcl")
    err = info.value
    assert (err.file, err.line, err.column) == ("bad.fcl", line, column)
    # the location once, in front (no second "bad.fcl:9:" inside the message)
    assert str(err).startswith(f"bad.fcl:{line}:{column}: error: ")
    assert str(err).count("bad.fcl") == 1, str(err)


def test_missing_file_is_an_error():
    with pytest.raises(RuleError, match="cannot read FCL file"):
        read_fcl(FCL / "no-such.fcl")


def one_block(text: str) -> FuzzyEngine:
    """The engine of an FCL text of one function block."""
    (engine,) = read_fcl(text).values()
    return engine
