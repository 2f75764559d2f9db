"""Fuzzy rule base building: 1,000 rules over an output of 250 terms (issue 14, item 8).

Each rule is ``if x is iK then y is oK`` for K in 0..249, four times over (the last three with a
second input ``z``). Times, in milliseconds, for: our 1,000 ``defrule`` calls plus the first
``fire`` (which compiles the rule set); reading the same rule base as FCL text; simpful building
the same system (its sets, variables and rules) plus its first Mamdani inference; the ratio simpful /
ours in this same run. Before the output plan was kept, 250 ``defrule`` calls took 63 s and the
250-rule FCL file 75 s.

Run: .venv/bin/python benchmarks/bench_fuzzy_build.py   (about 20 s on 2 cores, simpful most of it)
"""

from __future__ import annotations

import time
import warnings

from acordcs.engines.fuzzy import FuzzyEngine
from acordcs.engines.fuzzy.fcl import read_fcl

TERMS = 250
RULES = 1_000


def _tri(k: int) -> tuple[float, float, float]:
    return (k, k + 0.5, k + 1.0)


def _rules() -> list[tuple[str, str | None, str]]:
    out = []
    for n in range(RULES):
        k = n % TERMS
        out.append((f"i{k}", None if n < TERMS else f"i{(k * 7 + n) % TERMS}", f"o{k}"))
    return out


def _condition(x: str, z: str | None, *, fcl: bool = False) -> str:
    kw = str.upper if fcl else str.lower
    first = f"x {kw('is')} {x}"
    return first if z is None else f"{first} {kw('and')} z {kw('is')} {z}"


def ours() -> float:
    t0 = time.perf_counter()
    engine = FuzzyEngine()

    def terms(prefix: str) -> str:
        return "; ".join(
            f"{prefix}{k} := trian {' '.join(map(str, _tri(k)))}" for k in range(TERMS)
        )

    engine.define_variable("x", 0, TERMS, terms("i"))
    engine.define_variable("z", 0, TERMS, terms("i"))
    engine.define_variable("y", 0, TERMS, terms("o"))
    for x, z, out in _rules():
        engine.defrule(f"if {_condition(x, z)} then y is {out}", "s")
    engine.set("x", 3.2)
    engine.set("z", 3.2)
    engine.fire("s")
    assert 3.0 < engine.get("y") < 4.0
    return (time.perf_counter() - t0) * 1e3


def fcl_text() -> str:
    def terms(prefix: str) -> str:
        return "\n".join(
            f"  TERM {prefix}{k} := ({k}, 0) ({k + 0.5}, 1) ({k + 1}, 0);" for k in range(TERMS)
        )

    rules = "\n".join(
        f"  RULE {n + 1} : IF {_condition(x, z, fcl=True)} THEN y IS {out};"
        for n, (x, z, out) in enumerate(_rules())
    )
    return (
        "FUNCTION_BLOCK b\nVAR_INPUT x : REAL; z : REAL; END_VAR\nVAR_OUTPUT y : REAL; END_VAR\n"
        f"FUZZIFY x\n{terms('i')}\n  RANGE := (0 .. {TERMS});\nEND_FUZZIFY\n"
        f"FUZZIFY z\n{terms('i')}\n  RANGE := (0 .. {TERMS});\nEND_FUZZIFY\n"
        f"DEFUZZIFY y\n{terms('o')}\n  RANGE := (0 .. {TERMS});\n  METHOD : COG;\nEND_DEFUZZIFY\n"
        f"RULEBLOCK r\n  AND : MIN;\n  ACT : MIN;\n  ACCU : MAX;\n{rules}\nEND_RULEBLOCK\n"
        "END_FUNCTION_BLOCK\n"
    )


def ours_fcl(text: str) -> float:
    t0 = time.perf_counter()
    engine = read_fcl(text)["b"]
    engine.set("x", 3.2)
    engine.set("z", 3.2)
    engine.fire("r")
    assert 3.0 < engine.get("y") < 4.0
    return (time.perf_counter() - t0) * 1e3


def simpful() -> float:
    import simpful as sf

    t0 = time.perf_counter()
    fs = sf.FuzzySystem(show_banner=False, verbose=False)
    for name, prefix in (("x", "i"), ("z", "i"), ("y", "o")):
        sets = [
            sf.FuzzySet(function=sf.Triangular_MF(*_tri(k)), term=f"{prefix}{k}")
            for k in range(TERMS)
        ]
        fs.add_linguistic_variable(
            name, sf.LinguisticVariable(sets, universe_of_discourse=[0, TERMS])
        )
    fs.add_rules(
        [
            f"IF (x IS {x}) THEN (y IS {out})"
            if z is None
            else f"IF (x IS {x}) AND (z IS {z}) THEN (y IS {out})"
            for x, z, out in _rules()
        ]
    )
    fs.set_variable("x", 3.2)
    fs.set_variable("z", 3.2)
    fs.Mamdani_inference(["y"])
    return (time.perf_counter() - t0) * 1e3


def main() -> int:
    warnings.simplefilter("ignore")
    text = fcl_text()
    ours()  # warm up: imports, the parse tables
    ms_ours = min(ours() for _ in range(3))
    ms_fcl = min(ours_fcl(text) for _ in range(3))
    ms_simpful = simpful()
    print(f"{RULES:,} rules over an output of {TERMS} terms (build + first inference):")
    print(f"  acordcs defrule x {RULES:,} + fire      {ms_ours:9.1f} ms")
    print(f"  acordcs read_fcl ({len(text) / 1024:.1f} KB) + fire  {ms_fcl:9.1f} ms")
    print(f"  simpful build + first inference  {ms_simpful:9.1f} ms")
    print(f"  simpful / acordcs (defrule): {ms_simpful / ms_ours:.1f}x")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
