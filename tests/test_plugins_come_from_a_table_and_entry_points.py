"""Engines and model checks are found as targets are (acordcs.plugins): the built-in table plus
the entry points of a group, here given in place of importlib.metadata's; one that fails to load
is said and the others work. (Targets: tests/generator/test_targets_registry_and_entry_points.py.)"""

from __future__ import annotations

from importlib import metadata

import pytest

from acordcs.engines import engine_registry
from acordcs.engines.errors import EngineNotAvailableError
from acordcs.model import checks
from acordcs.model.reading import read_model
from tests.support import plugins
from tests.support.toolchain import WEBLAB


def _points(group: str, *pairs: tuple[str, str]):
    def listed(asked: str) -> list[metadata.EntryPoint]:
        return [metadata.EntryPoint(n, v, group) for n, v in pairs] if asked == group else []

    return listed


def test_the_built_in_tables_name_what_the_metamodel_and_the_package_have():
    assert sorted(engine_registry.BUILTIN) == ["clips", "fuzzy"]
    assert list(checks.BUILTIN) == [
        "monitors",
        "names",
        "profile_use",
        "rules",
        "structure",
        "tags",
        "term_limits",
    ]
    assert all(len(found) >= 1 for found in checks.CHECKS.load().values())


def test_an_engine_kind_from_an_entry_point_is_looked_up_like_a_built_in_one(monkeypatch):
    group = engine_registry.ENTRY_POINT_GROUP
    table = engine_registry.table(
        entry_points=_points(
            group,
            ("echo", "tests.support.plugins:ECHO"),
            ("gone", "no_such_module_xyz:ENGINE"),
            ("number", "math:pi"),
        ),
    )
    monkeypatch.setattr(engine_registry, "ENGINES", table)
    found = engine_registry.lookup_engine("echo")
    assert found.constructor is plugins.EchoEngine and found.syntax == "crisp"
    assert "echo" in engine_registry.registered_engines()
    assert engine_registry.lookup_engine("fuzzy").loads_plan
    with pytest.raises(EngineNotAvailableError) as raised:
        engine_registry.lookup_engine("gone")
    assert "no rule engine registered for engine kind 'gone'" in raised.value.message
    assert "entry point gone = no_such_module_xyz:ENGINE" in raised.value.hint
    assert "ModuleNotFoundError" in raised.value.hint
    assert any("number = math:pi" in p and "not an engine" in p for p in table.problems)
    engine_registry.unregister_engine("echo")


def test_checks_from_entry_points_run_after_the_built_in_ones(monkeypatch):
    group = checks.ENTRY_POINT_GROUP
    table = checks.table(
        entry_points=_points(
            group,
            ("acme", "tests.support.plugins:counts_components"),
            ("broken", "no_such_module_xyz:CHECKS"),
            ("structure", "tests.support.plugins:no_component_named_test"),
        ),
    )
    monkeypatch.setattr(checks, "CHECKS", table)
    plugins.CALLS.clear()
    reading = read_model(str(WEBLAB))
    assert plugins.CALLS == [6]  # the WebLab's six components, seen by the plug-in's check
    found = [(d.code, d.message) for d in reading.diagnostics]
    assert [code for code, _ in found] == ["Z902", "Z902"]
    assert "entry point broken = no_such_module_xyz:CHECKS" in found[0][1] + found[1][1]
    assert "check 'structure' already exists (?); not loaded" in found[0][1] + found[1][1]
