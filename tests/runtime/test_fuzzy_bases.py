"""The two policies of the paper's case study, as Python helpers others can reuse, and their FCL twins.

- speed (12 rules): cycleRate (control actions per second, 0..3) x angle (degrees of turn, 0..90)
  -> speed (mm/s, 0..200);
- bandwidth (9 rules): cycleRate x numUsers (0..10) -> fps (0..15).

Import from another test module: ``from test_fuzzy_bases import speed_engine``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from acordcs.runtime.fuzzy import FuzzyEngine

FCL_DIR = Path(__file__).parent / "fcl"

SPEED_VARIABLES = {
    "cycleRate": (
        0.0,
        3.0,
        "small := trape 0 0 0.5 1.2; medium := trian 0.5 1.5 2.5; large := trape 1.8 2.5 3 3",
    ),
    "angle": (
        0.0,
        90.0,
        "narrow := trape 0 0 10 25; medium := trian 10 30 50; wide := trian 30 55 75; sharp := trape 60 80 90 90",
    ),
    "speed": (
        0.0,
        200.0,
        "veryslow := trape 0 0 20 50; slow := trian 20 60 100; medium := trian 60 110 160; fast := trape 130 170 200 200",
    ),
}
# rows: cycleRate small/medium/large; columns: angle narrow/medium/wide/sharp
SPEED_TABLE = {
    "small": ("fast", "fast", "medium", "slow"),
    "medium": ("fast", "medium", "slow", "veryslow"),
    "large": ("medium", "slow", "veryslow", "veryslow"),
}
ANGLES = ("narrow", "medium", "wide", "sharp")
SPEED_RULES = [
    f"s{i * 4 + j + 1}: if cycleRate is {rate} and angle is {angle} then speed is {out}"
    for i, (rate, outs) in enumerate(SPEED_TABLE.items())
    for j, (angle, out) in enumerate(zip(ANGLES, outs, strict=False))
]

BANDWIDTH_VARIABLES = {
    "cycleRate": SPEED_VARIABLES["cycleRate"],
    "numUsers": (0.0, 10.0, "low := trape 0 0 2 4; medium := trian 2 5 8; high := trape 6 8 10 10"),
    "fps": (0.0, 15.0, "low := trape 0 0 3 6; medium := trian 4 7.5 11; high := trape 9 12 15 15"),
}
BANDWIDTH_TABLE = {
    "small": ("high", "medium", "medium"),
    "medium": ("medium", "medium", "low"),
    "large": ("medium", "low", "low"),
}
USERS = ("low", "medium", "high")
BANDWIDTH_RULES = [
    f"b{i * 3 + j + 1}: if cycleRate is {rate} and numUsers is {users} then fps is {out}"
    for i, (rate, outs) in enumerate(BANDWIDTH_TABLE.items())
    for j, (users, out) in enumerate(zip(USERS, outs, strict=False))
]


def make_engine(
    variables: dict, rules: list[str], ruleset: str, semantics: str = "mamdani"
) -> FuzzyEngine:
    engine = FuzzyEngine(semantics=semantics)
    for name, (lo, hi, terms) in variables.items():
        engine.define_variable(name, lo, hi, terms)
    for rule in rules:
        engine.defrule(rule, ruleset)
    return engine


def speed_engine(semantics: str = "mamdani") -> FuzzyEngine:
    """The 12-rule speed policy in rule set ``speed``."""
    return make_engine(SPEED_VARIABLES, SPEED_RULES, "speed", semantics)


def bandwidth_engine(semantics: str = "mamdani") -> FuzzyEngine:
    """The 9-rule bandwidth policy in rule set ``bandwidth``."""
    return make_engine(BANDWIDTH_VARIABLES, BANDWIDTH_RULES, "bandwidth", semantics)


@pytest.mark.parametrize(
    ("fcl_file", "factory", "ruleset", "inputs", "output"),
    [
        ("speed.fcl", speed_engine, "speed", ("cycleRate", "angle"), "speed"),
        ("bandwidth.fcl", bandwidth_engine, "bandwidth", ("cycleRate", "numUsers"), "fps"),
    ],
)
def test_fcl_files_define_the_same_policies(fcl_file, factory, ruleset, inputs, output):
    from acordcs.runtime.fuzzy.fcl import read_fcl

    (from_file,) = read_fcl((FCL_DIR / fcl_file).read_text(), filename=fcl_file).values()
    ours = factory()
    rng = np.random.default_rng(7)
    va, vb = (ours.variables[name] for name in inputs)
    a, b = rng.uniform(va.lo, va.hi, 300), rng.uniform(vb.lo, vb.hi, 300)
    got = from_file.batch(ruleset, {inputs[0]: a, inputs[1]: b})[output]
    want = ours.batch(ruleset, {inputs[0]: a, inputs[1]: b})[output]
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9)
