"""Target ``rules``, fuzzy sets: one FCL file per set, written by the runtime's FCL writer with
plain identifiers (jFuzzyLogic has no dotted names and reserves its keywords in any case), which
our FCL reader reads back into an engine giving the same outputs as the engine built from the
descriptor directly, and as the engine an independent oracle builds from the pyecore model
(tests/support/ecore_fuzzy_engine: the model's scope resolved apart from the descriptor), on a
grid of inputs."""

from __future__ import annotations

import dataclasses
import itertools
import re
from pathlib import Path

import numpy as np
import pytest

from acordcs.descriptor import Application, PolicySet
from acordcs.engines.fuzzy import FuzzyEngine, read_fcl
from acordcs.generator.targets.fcl_file import FCL_KEYWORDS, fcl_for
from acordcs.model.ecore_builder import to_ecore
from acordcs.model.reading import read_model
from tests.support.ecore_fuzzy_engine import engine_for_policy_set
from tests.support.generator import build
from tests.support.toolchain import SMARTROOM, WEBLAB

DECLARED = re.compile(r"^\s+(\w+) : REAL;", re.M)


def direct_engine(ps: PolicySet) -> FuzzyEngine:
    """The engine of the set as the runtime builds one from the descriptor: dotted names."""
    engine = FuzzyEngine(ps.semantics, name=ps.name)
    for v in ps.variables:
        engine.define_variable(v.name, v.minimum, v.maximum, v.terms_text)
    for policy in ps.policies:
        engine.define_ruleset(policy.name, ps.semantics)
        for rule in policy.rules:
            engine.defrule(f"{rule.label}: {rule.text}" if rule.label else rule.text, policy.name)
    return engine


def fcl_names(text: str) -> dict[str, str]:
    """model variable -> FCL variable, read from the file's header (its list of names)."""
    found = re.findall(r"^\s+(\w+) := ([\w.]+) \(variable\)", text, re.M)
    return {model: fcl for fcl, model in found}


def assert_same_results(
    ps: PolicySet,
    text: str,
    names: dict[str, str],
    points: int = 6,
    direct: FuzzyEngine | None = None,
) -> int:
    """Fire the FCL file's engine and ``direct`` (default: the descriptor's engine) on a grid of
    every input of each rule set; the number of outputs compared."""
    direct = direct or direct_engine(ps)
    (read,) = read_fcl(text, filename=f"{ps.name}.fcl").values()
    compared = 0
    for ruleset in direct.rulesets():
        entries = direct.rules(ruleset)
        inputs = sorted({n for e in entries for n in e.inputs()})
        outputs = sorted({v for e in entries for v, _ in e.consequents})
        variables = direct.variables
        axes = [np.linspace(variables[n].lo, variables[n].hi, points) for n in inputs]
        for values in itertools.product(*axes):
            for name, value in zip(inputs, values, strict=True):
                direct.set(name, value)
                read.set(names[name], value)
            direct.fire(ruleset)
            read.fire(ruleset)
            for out in outputs:
                assert read.get(names[out]) == pytest.approx(direct.get(out), abs=1e-9), (
                    ruleset,
                    dict(zip(inputs, values, strict=True)),
                )
                compared += 1
    return compared


def fuzzy_sets(app: Application) -> list[PolicySet]:
    return [ps for ps in app.policy_sets if ps.engine == "fuzzy"]


@pytest.mark.parametrize("sample", [WEBLAB, SMARTROOM], ids=lambda p: p.stem)
def test_built_files_give_the_descriptors_results(sample: Path, tmp_path: Path, request):
    app = request.getfixturevalue(sample.stem)
    result = build(sample, tmp_path, "--target", "rules")
    assert result.code == 0, result.both
    for ps in fuzzy_sets(app):
        text = (tmp_path / "rules" / f"{ps.name}.fcl").read_text(encoding="utf-8")
        assert assert_same_results(ps, text, fcl_names(text)) >= 36  # 6 points per input


@pytest.mark.parametrize("sample", [WEBLAB, SMARTROOM], ids=lambda p: p.stem)
def test_built_files_give_what_the_pyecore_model_gives(sample: Path, tmp_path: Path, request):
    app = request.getfixturevalue(sample.stem)
    model = to_ecore(read_model(str(sample)).architecture)
    assert build(sample, tmp_path, "--target", "rules").code == 0
    for ps in fuzzy_sets(app):
        text = (tmp_path / "rules" / f"{ps.name}.fcl").read_text(encoding="utf-8")
        (oracle_set,) = (p for p in model.policySets if p.name == ps.name)
        oracle = engine_for_policy_set(oracle_set)
        assert sorted(oracle.variables) == sorted(v.name for v in ps.variables)
        assert assert_same_results(ps, text, fcl_names(text), direct=oracle) >= 36


@pytest.mark.parametrize("semantics", ["mamdani", "sazonov"])
def test_both_semantics_read_back(weblab: Application, semantics: str):
    for ps in fuzzy_sets(weblab):
        ps = dataclasses.replace(ps, semantics=semantics)
        made = fcl_for(ps)
        names = {model: fcl for what, model, fcl in made.renamed if what == "variable"}
        assert assert_same_results(ps, made.text, names, points=5) > 0


def test_names_are_plain_identifiers_for_jfuzzylogic(weblab: Application):
    for ps in fuzzy_sets(weblab):
        made = fcl_for(ps)
        declared = DECLARED.findall(made.text)
        assert declared and all("." not in n for n in declared)
        assert not re.search(r"\w\.[A-Za-z_]", made.text.replace("..", " "))
        assert all(n.upper() not in FCL_KEYWORDS for n in declared)
        assert {m for _, m, _ in made.renamed} >= {
            b.target for b in ps.bound if b.kind == "attribute"
        }


def test_names_that_are_fcl_keywords_are_renamed_and_listed(weblab: Application):
    ps = next(p for p in weblab.policy_sets if p.name == "SpeedLimiting")
    # a term named like FCL's MAX, a policy named like its RULE keyword: legal model names
    variables = tuple(
        dataclasses.replace(
            v,
            terms=tuple(
                dataclasses.replace(t, name="max") if t.name == "fast" else t for t in v.terms
            ),
        )
        if v.attribute == "maxSpeed"
        else v
        for v in ps.variables
    )
    policies = tuple(
        dataclasses.replace(
            p,
            name="Rule" if p.name == "StraightRules" else p.name,
            rules=tuple(
                dataclasses.replace(r, text=r.text.replace(" is fast", " is max")) for r in p.rules
            ),
        )
        for p in ps.policies
    )
    ps = dataclasses.replace(ps, variables=variables, policies=policies)
    made = fcl_for(ps)
    assert "TERM max_ :=" in made.text and "IS max_;" in made.text
    assert "RULEBLOCK Rule_" in made.text
    assert ("policy", "Rule", "Rule_") in made.renamed
    assert ("term of Locomotion.maxSpeed", "max", "max_") in made.renamed
    (read,) = read_fcl(made.text).values()
    assert "Rule_" in read.rulesets()
    direct = direct_engine(ps)
    for cycle, angle in itertools.product([0.2, 1.5, 2.8], [3, 30, 80]):
        for engine, names in (
            (direct, ("cycleRate", "angle")),
            (read, ("Control_cycleRate", "Control_angle")),
        ):
            engine.set(names[0], cycle)
            engine.set(names[1], angle)
        direct.fire("Rule")
        read.fire("Rule_")
        assert read.get("Locomotion_maxSpeed") == pytest.approx(direct.get("maxSpeed"), abs=1e-9)


def test_file_header_names_the_set_and_the_mapping(tmp_path: Path):
    build(WEBLAB, tmp_path, "--target", "rules")
    text = (tmp_path / "rules" / "SpeedLimiting.fcl").read_text(encoding="utf-8")
    assert text.startswith(
        "(* Generated by acordcs-gen 0.1.0 (target rules) from policy set 'SpeedLimiting' "
        "(WebLab::ContextAwareNavigation::Adaptation::SpeedLimiting, id BOUML_0x20182_4)\n"
        "   in model file weblab.xmi."
    )
    assert "Locomotion_maxSpeed := Locomotion.maxSpeed (variable)" in text
