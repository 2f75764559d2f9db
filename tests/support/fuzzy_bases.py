"""The two policies of the paper's case study, as Python helpers the fuzzy tests share.

- speed (12 rules): cycleRate (control actions per second, 0..3) x angle (degrees of turn, 0..90)
  -> speed (mm/s, 0..200);
- bandwidth (9 rules): cycleRate x numUsers (0..10) -> fps (0..15).

Their FCL twins are ``tests/engines/fcl/speed.fcl`` and ``bandwidth.fcl``
(``tests/engines/test_fuzzy_bases.py`` checks they agree).
"""

from __future__ import annotations

from acordcs.engines.fuzzy import FuzzyEngine

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
