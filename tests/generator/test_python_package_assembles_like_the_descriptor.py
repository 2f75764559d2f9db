"""Differential test of the ``python`` target: for both samples, what the generated package
assembles (its ``assemble_application``, and each container module's ``assemble_container`` with
the other containers given as remote) is what ``assemble(describe(read_model(path).architecture))``
assembles: the same containers, components (type, properties, ports and their properties,
operations and their parameters), connections (ends, connector, QoS), monitors (frequency, sources,
attributes, acquisition kind with its xpath or polled operation), policy sets (engine, trigger, frequency, semantics, rule sets and rules, adapted
elements, the monitors feeding them, variables) and feeds; only the component and monitor classes
differ (the user's subclasses of the generated bases, not the generic and kind classes)."""

from __future__ import annotations

import importlib
import inspect
from pathlib import Path
from typing import Any

import pytest

from acordcs.generator.describe import describe
from acordcs.generator.targets.python import package_name
from acordcs.model.reading import read_model
from acordcs.runtime.api import RunningApplication, VirtualClock, assemble
from acordcs.runtime.monitor import Monitor
from tests.support.generator import build, imported
from tests.support.toolchain import SMARTROOM, WEBLAB


def _runtime_class(monitor: Monitor) -> str:
    """The runtime class a monitor is (or derives from): its acquisition kind's."""
    runtime = ("acordcs.runtime.acquisition", "acordcs.runtime.monitor")
    return next(k.__name__ for k in type(monitor).__mro__ if k.__module__ in runtime)


def connector(c: Any) -> list[str]:
    kinds = [type(c).__name__]
    while hasattr(c, "inner"):
        c = c.inner
        kinds.append(type(c).__name__)
    return kinds


def end(e: Any) -> str:
    return getattr(e, "qualified_name", None) or repr(e)


def shape(app: RunningApplication) -> dict[str, Any]:
    """What ``app`` runs, as plain data (everything but the component classes themselves)."""
    out: dict[str, Any] = {"feeds": sorted(map(repr, app.feeds))}
    for name, c in app.containers.items():
        components = {}
        for ref in c.components():
            instance = ref.instance
            cls = type(instance)
            components[ref.name] = {
                "type": instance.type_name,
                "properties": dict(instance.props),
                "ports": {
                    p.name: (p.kind, p.role, dict(p.properties)) for p in instance.port_map.values()
                },
                "operations": {
                    op: list(inspect.signature(getattr(cls, op)).parameters)
                    for op in sorted(instance.operation_names())
                },
            }
        monitors = {
            m: (
                c.monitor(m).frequency,
                c.monitor(m).sources,
                dict(c.monitor(m).attributes),
                _runtime_class(c.monitor(m)),
                getattr(c.monitor(m), "xpath", None),
                getattr(c.monitor(m), "operation", None),
            )
            for m in c.monitors()
        }
        policy_sets = {}
        for ps in app.descriptor.policy_sets:
            try:
                running = c.policy_set(ps.name)
            except Exception:
                continue
            policy_sets[ps.name] = (
                running.engine_kind,
                running.trigger,
                running.frequency,
                running.semantics,
                {p: [repr(r) for r in rules] for p, rules in running.policies.items()},
                running.adapts,
                running.fed_by,
                {k: repr(v) for k, v in running.variables.items()},
            )
        out[name] = {
            "properties": dict(c.properties),
            "components": components,
            "connections": {
                conn.name: ([end(e) for e in conn.ends()], connector(conn.connector), conn.qos)
                for conn in c.connections()
            },
            "monitors": monitors,
            "policy_sets": policy_sets,
        }
    return out


@pytest.fixture(params=[WEBLAB, SMARTROOM], ids=["weblab", "smartroom"])
def sample(request, tmp_path: Path):
    path = request.param
    descriptor = describe(read_model(str(path)).architecture)
    result = build(path, tmp_path, "-t", "python")
    assert result.code == 0, result.both
    with imported(tmp_path, package_name(descriptor.name)) as package:
        yield descriptor, package


def test_the_whole_application_in_one_process(sample):
    descriptor, package = sample
    with (
        assemble(descriptor, clock=VirtualClock()) as expected,
        package.assemble_application(clock=VirtualClock()) as generated,
    ):
        assert shape(generated) == shape(expected)
        assert generated.descriptor == descriptor
        for comp in descriptor.components:
            where = descriptor.container_of(comp.name)
            instance = generated.container(where).find(comp.name).instance
            assert type(instance) is package.FACTORIES[comp.name]


def test_each_container_module_with_the_others_remote(sample):
    descriptor, package = sample
    names = [c.name for c in descriptor.containers]
    uris = {n: f"PYRO:acordcs.container.{n}@127.0.0.1:9" for n in names}
    for name in names:
        module = importlib.import_module(f"{package.__name__}.{name}")
        assert name == module.CONTAINER
        others = {n: u for n, u in uris.items() if n != name}
        with (
            assemble(descriptor, only=[name], remote=others, clock=VirtualClock()) as expected,
            module.assemble_container(VirtualClock(), others) as generated,
        ):
            assert list(generated.containers) == [name]
            assert shape(generated) == shape(expected)


def test_the_shapes_compared_are_not_empty(sample):
    descriptor, package = sample
    with package.assemble_application() as generated:
        seen = shape(generated)
    containers = [seen[c.name] for c in descriptor.containers]
    assert sum(len(c["components"]) for c in containers) == len(descriptor.components)
    assert sum(len(c["connections"]) for c in containers) >= len(descriptor.connections)
    assert sum(len(c["policy_sets"]) for c in containers) == len(descriptor.policy_sets)
    assert any(c["monitors"] for c in containers)
