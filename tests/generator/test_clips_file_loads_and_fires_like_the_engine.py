"""Target ``rules``, crisp sets: one CLIPS file per set, made with the runtime's CLIPS compiler.
clipspy loads it; fired through its own functions it assigns the same values and calls the same
operations, with the same arguments, as the runtime's ClipsEngine built for the same policy set
from the model (the pyecore oracle ``tests.support.ecore_clips_engine.engine_for_policy_set``, given the descriptor's typed
defaults where the model leaves a default unset: the descriptor has no "unset", and the file
starts from it); and it defines nothing but the prelude's ``acord-`` constructs and what the
model names."""

from __future__ import annotations

from pathlib import Path

import clips
import pytest

from acordcs.model.ecore_builder import to_ecore
from acordcs.model.reading import read_model
from tests.support.ecore_clips_engine import engine_for_policy_set
from tests.support.generator import build
from tests.support.toolchain import SMARTROOM, WEBLAB

_LISTS = ("defmodule", "defrule", "defglobal", "deffunction", "deftemplate", "deffacts")


def listed(env: clips.Environment, kind: str) -> set[str]:
    """Names of every construct of ``kind`` in every module."""
    what = f"(get-{kind}-list)" if kind == "defmodule" else f"(get-{kind}-list *)"
    return {str(n) for n in env.eval(what)}


def everything(env: clips.Environment) -> dict[str, set[str]]:
    return {kind: listed(env, kind) for kind in _LISTS}


class Recorder:
    """Stands for every element: each operation call is recorded."""

    def __init__(self, name: str, calls: list) -> None:
        self.name, self.calls = name, calls

    def __getattr__(self, operation: str):
        return lambda *args: self.calls.append((f"{self.name}.{operation}", args))


class FileEngine:
    """The generated file in clipspy, driven through its own functions and facts."""

    def __init__(self, path: Path) -> None:
        self.env = clips.Environment()
        self.env.load(str(path))
        self.env.reset()
        assert self.env.eval("(acord-init)") == clips.Symbol("TRUE")
        self.numbers, self.sites = {}, {}
        for fact in self.env.facts():
            name = fact.template.name
            if name == "acord-variable":
                self.numbers[fact["name"]] = fact["number"]
            elif name == "acord-site":
                self.sites[fact["number"]] = (str(fact["kind"]), fact["target"], fact["arguments"])

    def get(self, variable: str) -> object:
        return python(self.env.eval(f"?*{variable}*"))

    def fire(self, ruleset: str, values: dict[str, object]) -> list:
        pairs = " ".join(f"{self.numbers[n]} {literal(v)}" for n, v in values.items())
        records = list(self.env.eval(f"(acord-fire-set {ruleset} FALSE {pairs})"))
        calls, i = [], 0
        while i < len(records):
            record = records[i]
            assert isinstance(record, int), f"unexpected record {record!r} in {records}"
            if record > 0:  # variable number, value
                i += 2
                continue
            kind, target, count = self.sites[-record]
            if kind == "call":
                calls.append((target, tuple(python(a) for a in records[i + 1 : i + 1 + count])))
                i += 1 + count
            else:
                i += 1
        return calls


def literal(value: object) -> str:
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    return repr(value)


def python(value: object) -> object:
    if isinstance(value, clips.Symbol):
        return {"TRUE": True, "FALSE": False, "nil": None}.get(str(value), str(value))
    return value


def runtime_engine(sample: Path, set_name: str):
    app = to_ecore(read_model(str(sample)).architecture)
    ps = next(p for p in app.policySets if p.name == set_name)
    engine = engine_for_policy_set(ps, [m for m in app.monitors if ps in m.feeds])
    calls: list = []
    for element in [*ps.adapts, *(m for m in app.monitors if ps in m.feeds)]:
        engine.bind(element.name, Recorder(element.name, calls))
    return engine, calls


CASES = {
    "Recovering": (
        WEBLAB,
        "RecoveryRules",
        [{"Control.speed": v} for v in (0.0, 0.0, 0.0, 0.0, 0.0, 60.0, 0.0, 35.5, 0.0)],
    ),
    "Comfort": (
        SMARTROOM,
        "ComfortRules",
        [
            {"Climate.minutesEmpty": 20, "Presence.occupancy": 0.0},
            {"Climate.minutesEmpty": 0, "Presence.occupancy": 4.0},
            {"Presence.occupancy": 12.0, "Climate.temperature": 25.0},
            {"Presence.occupancy": 12.0, "Climate.temperature": 24.0},
            {"Climate.minutesEmpty": 30, "Presence.occupancy": 0.0},
        ],
    ),
}


@pytest.mark.parametrize("set_name", sorted(CASES))
def test_file_fires_like_the_runtime_engine(set_name: str, tmp_path: Path):
    sample, ruleset, steps = CASES[set_name]
    assert build(sample, tmp_path, "--target", "rules").code == 0
    loaded = FileEngine(tmp_path / "rules" / f"{set_name}.clp")
    engine, calls = runtime_engine(sample, set_name)
    # The file holds the variables the rules use (the oracle declares the whole scope), by name.
    assert loaded.numbers and set(loaded.numbers) <= set(engine._variables)
    for name in loaded.numbers:
        if engine.get(name) is None:  # unset in the model: the descriptor's typed default
            engine.set(name, loaded.get(name))
        assert loaded.get(name) == engine.get(name), name
    fired_calls = 0
    for values in steps:
        for name, value in values.items():
            engine.set(name, value)
        del calls[:]
        engine.fire(ruleset)
        assert loaded.fire(ruleset, values) == calls, values
        fired_calls += len(calls)
        for name in loaded.numbers:
            assert loaded.get(name) == engine.get(name), (name, values)
    assert engine.error_count == 0
    assert fired_calls >= 3


@pytest.mark.parametrize("set_name", sorted(CASES))
def test_file_defines_only_the_prelude_and_model_names(set_name: str, tmp_path: Path, request):
    sample = CASES[set_name][0]
    build(sample, tmp_path, "--target", "rules")
    app = request.getfixturevalue(sample.stem)
    ps = next(p for p in app.policy_sets if p.name == set_name)
    fresh = everything(clips.Environment())
    loaded = FileEngine(tmp_path / "rules" / f"{set_name}.clp")
    added = {k: v - fresh[k] for k, v in everything(loaded.env).items()}
    policies = {p.name for p in ps.policies}
    assert added["defmodule"] == policies | {"MAIN"} - fresh["defmodule"]
    assert {r.split("::")[0] for r in added["defrule"]} <= policies
    assert {r.split("::")[-1] for r in added["defrule"]} == {
        r.label for p in ps.policies for r in p.rules
    }
    for kind in ("deffunction", "deftemplate", "deffacts"):
        assert all(n.removeprefix("MAIN::").startswith("acord-") for n in added[kind]), kind
    model_globals = {
        g.removeprefix("MAIN::")
        for g in added["defglobal"]
        if not g.removeprefix("MAIN::").startswith("acord-")
    }
    assert model_globals == set(loaded.numbers)
