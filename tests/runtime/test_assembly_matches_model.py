"""Differential test: what ``assemble(describe(arch))`` runs is what the model says, read through an
independent oracle, the pyecore model ``to_ecore(arch)`` (the path the runtime used to build from).

For both samples: containers (and their properties), components (property values, ports and their
properties, operations and their parameters), connections (ends, connector, QoS), monitors
(frequency, sources, attributes, the policy sets they feed), policy sets (engine, trigger, period,
semantics, rule sets, adapted elements, the monitors feeding them, linguistic variables). Once with
every container in this process, once per container with the others given as remote.
"""

from __future__ import annotations

import inspect
from typing import Any

import pytest

from acordcs.engines.engine_registry import Variable
from acordcs.generator.describe import describe
from acordcs.model.ecore_builder import to_ecore
from acordcs.model.reading import read_model
from acordcs.rules import parse_terms
from acordcs.runtime.assembly import RunningApplication, assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.connectors import (
    InProcessConnector,
    RemoteConnector,
    RemotePort,
    ShapedConnector,
)
from acordcs.runtime.ports import Port
from tests.support.toolchain import SMARTROOM, WEBLAB

_FCL = {
    "trapezoid": "trape",
    "triangle": "trian",
    "gaussian": "gauss",
    "bell": "gbell",
    "sigmoid": "sigm",
}


# ------------------------------------------------------------------- the oracle, read from pyecore
def default(attr: Any) -> object:
    """An Attribute's initial value as the runtime types it (its UML type, or its variable)."""
    kind = (attr.type or "").lower()
    text = attr.defaultValue
    var = attr.variable
    if kind in ("int", "integer", "long", "short"):
        return int(float(text)) if text not in (None, "") else int(var.rangeMin or 0) if var else 0
    if kind in ("double", "float", "real", "number") or var is not None:
        return float(text) if text not in (None, "") else float(var.rangeMin or 0.0) if var else 0.0
    if kind in ("bool", "boolean"):
        return str(text).strip().lower() in ("true", "1", "yes")
    return text if text is not None else ""


def defaults(element: Any) -> dict[str, object]:
    return {a.name: default(a) for a in element.attributes}


def terms_text(variable: Any) -> str:
    parts = []
    for term in variable.terms:
        shape = term.shape.name
        params = [f"{p:g}" for p in term.parameters]
        if shape == "points":
            body = " ".join(f"({params[i]}, {params[i + 1]})" for i in range(0, len(params) - 1, 2))
        elif shape == "singleton":
            body = params[0]
        else:
            body = f"{_FCL[shape]} {' '.join(params)}"
        parts.append(f"{term.name} := {body}")
    return "; ".join(parts)


def name_of(element: Any) -> str:
    owner = element.eContainer()
    if element.eClass.name == "CtxPort" and owner is not None:
        return f"{owner.name}.{element.name}"
    return element.name


def variables_in_scope(model: Any, ps: Any) -> dict[str, Variable]:
    """The linguistic variables of a policy set's scope: the monitors feeding it, the elements it
    adapts and their ports."""
    scope = [m for m in model.monitors if ps in m.feeds]
    for target in ps.adapts:
        scope.append(target)
        scope.extend(getattr(target, "ports", ()))
    return {
        f"{name_of(e)}.{a.name}": Variable(
            a.variable.rangeMin or 0.0, a.variable.rangeMax or 0.0, terms_text(a.variable)
        )
        for e in scope
        for a in e.attributes
        if a.variable is not None
    }


def optional(element: Any, feature: str) -> object:
    return getattr(element, feature) if element.eIsSet(feature) else None


# ------------------------------------------------------------------------------------ the test
@pytest.fixture(params=[WEBLAB, SMARTROOM], ids=["weblab", "smartroom"])
def sample(request):
    reading = read_model(str(request.param))
    assert not [d for d in reading.diagnostics if d.severity >= 2]
    return to_ecore(reading.architecture), describe(reading.architecture)


def placement(model: Any) -> dict[str, str]:
    return {
        e.name: c.name
        for c in model.containers
        for e in [*c.components, *c.monitors, *c.policySets]
    }


def test_everything_in_one_process(sample):
    model, descriptor = sample
    with assemble(descriptor, clock=VirtualClock()) as app:
        where = placement(model)
        assert set(app.containers) == {c.name for c in model.containers}
        for mc in model.containers:
            assert app.container(mc.name).properties == defaults(mc)
        check_components(app, model, where)
        check_connections(app, model, where, remote={})
        check_monitors_and_policy_sets(app, model, where)


def test_each_container_with_the_others_remote(sample):
    model, descriptor = sample
    names = [c.name for c in model.containers]
    uris = {n: f"PYRO:acordcs.container.{n}@127.0.0.1:9" for n in names}
    for name in names:
        others = {n: u for n, u in uris.items() if n != name}
        with assemble(descriptor, only=[name], remote=others, clock=VirtualClock()) as app:
            assert list(app.containers) == [name]
            where = placement(model)
            check_components(app, model, where)
            check_connections(app, model, where, remote=others)


def check_components(app: RunningApplication, model: Any, where: dict[str, str]) -> None:
    for comp in model.components:
        if where[comp.name] not in app.containers:
            continue
        instance = app.container(where[comp.name]).find(comp.name).instance
        assert instance.props == defaults(comp), comp.name
        assert {p.name: (p.kind.name, p.role.name) for p in comp.ports} == {
            p.name: (p.kind, p.role) for p in instance.port_map.values()
        }, comp.name
        for port in comp.ports:
            props = instance.port(port.name).properties
            assert {k: props[k] for k in defaults(port)} == defaults(port), port.name
        assert instance.operation_names() == {op.name for op in comp.operations}, comp.name
        for op in comp.operations:
            params = inspect.signature(getattr(type(instance), op.name)).parameters
            expected = [p.name for p in op.parameters if p.direction.name in ("in", "inout")]
            assert list(params)[1:] == expected, f"{comp.name}.{op.name}"


def check_connections(
    app: RunningApplication, model: Any, where: dict[str, str], remote: dict[str, str]
) -> None:
    for conn in model.connections:
        ends = [
            (where[p.eContainer().name], p.eContainer().name, p.name)
            for p in (conn.required, conn.provided)
        ]
        here = [e for e in ends if e[0] in app.containers]
        if not here:
            continue
        link = app.container(here[0][0]).connection(conn.name)
        for end, (container, comp, port) in zip(link.ends(), ends, strict=True):
            if container in app.containers:
                assert isinstance(end, Port) and end.qualified_name == f"{comp}.{port}"
            else:
                assert end == RemotePort(remote[container], comp, port)
        crosses = len(here) < 2
        transport = RemoteConnector if crosses else InProcessConnector
        if conn.connector.name == "shaped":
            assert type(link.connector) is ShapedConnector, conn.name
            assert type(link.connector.inner) is transport, conn.name
        else:
            assert type(link.connector) is transport, conn.name
        qos = defaults(conn)
        assert {k: link.qos[k] for k in qos} == qos, conn.name


def check_monitors_and_policy_sets(app: RunningApplication, model: Any, where: dict[str, str]):
    for mon in model.monitors:
        running = app.container(where[mon.name]).monitor(mon.name)
        assert running.frequency == optional(mon, "frequency"), mon.name
        assert running.sources == tuple(name_of(s) for s in mon.sources), mon.name
        assert running.attributes == defaults(mon), mon.name
        for ps in mon.feeds:
            target = app.container(where[ps.name])
            assert mon.name in target.policy_set(ps.name).fed_by
            assert target.monitor(mon.name).attributes == defaults(mon)  # itself or its replica
    for ps in model.policySets:
        running = app.container(where[ps.name]).policy_set(ps.name)
        assert running.engine_kind == ps.engine.name
        assert running.trigger == ps.trigger.name
        assert running.frequency == optional(ps, "frequency")
        assert running.semantics == ps.semantics.name
        assert {p: [line.text for line in lines] for p, lines in running.policies.items()} == {
            p.name: [f"{r.label}: {r.text}" if r.label else r.text for r in p.rules]
            for p in ps.policies
        }
        assert set(running.adapts) == {name_of(a) for a in ps.adapts}
        assert set(running.fed_by) == {m.name for m in model.monitors if ps in m.feeds}
        in_scope = variables_in_scope(model, ps)
        for name, planned in running.plan.variables.items():
            if planned.terms is None:
                continue
            expected = in_scope[name]  # every linguistic variable it uses is one of its scope's
            assert (planned.terms.lo, planned.terms.hi) == (expected.lo, expected.hi), name
            assert [(t.name.text, t.shape, t.parameters) for t in planned.terms.terms] == [
                (t.name.text, t.shape, t.parameters) for t in parse_terms(expected.terms)
            ], name
    replicas = {(f.monitor, f.target) for f in app.feeds if f.delivery == "in-process"}
    assert sum(len(c.monitors()) for c in app.containers.values()) == len(model.monitors) + len(
        replicas
    )
