"""The WebLab descriptor holds exactly what the model says: the counts of the paper's Figure 4
application, what ``acordcs-gen inspect`` reports, and, element by element, what the pyecore model
built by ``to_ecore`` holds (an independent oracle: another builder over the same reading)."""

from __future__ import annotations

import json

import pytest

from acordcs.model.ecore_builder import to_ecore
from tests.support.toolchain import WEBLAB, run_main


@pytest.fixture(scope="module")
def ecore(weblab_reading):
    return to_ecore(weblab_reading.architecture)


@pytest.fixture(scope="module")
def inspected():
    result = run_main(["inspect", str(WEBLAB), "--format", "json"])
    assert result.code == 0, result.both
    return json.loads(result.out)["acordcs"]


# ------------------------------------------------------------------------------------ counts
def test_counts(weblab):
    assert weblab.name == "WebLab"
    assert [c.name for c in weblab.containers] == ["UserSide", "WebLabSide"]
    assert len(weblab.components) == 6
    assert sum(len(c.ports) for c in weblab.components) == 11
    assert len(weblab.connections) == 6
    assert len(weblab.monitors) == 3
    rules = {ps.name: len(ps.rules()) for ps in weblab.policy_sets}
    assert rules == {"SpeedLimiting": 12, "Recovering": 5, "BandwidthLimiting": 9}


def test_hosts_and_endpoints(weblab):
    user, lab = weblab.containers
    assert (user.host, lab.host) == ("user.example.org", "weblab.example.org")
    assert user.hosted("component") == ("Navigator",)
    assert lab.hosted("monitor") == ("Control", "Telemetry", "Usage")
    # both sides hold ends of remote connections, so both are served
    assert lab.endpoint.uri(9090) == "PYRO:acordcs.container.WebLabSide@weblab.example.org:9090"
    assert user.endpoint.object_name == "acordcs.container.UserSide"


def test_monitors_acquire_context_as_modelled(weblab):
    how = {
        m.name: (m.acquisition, m.frequency, m.xpath, m.operation, [s.name for s in m.sources])
        for m in weblab.monitors
    }
    assert how == {
        "Control": ("intercept", None, None, None, ["Locomotion.LocomotionPort"]),
        "Telemetry": ("subscribe", None, "/telemetry", None, ["Locomotion.TelemetryPort"]),
        "Usage": ("poll", 1.0, None, "countUsers", ["Access"]),
    }


def test_container_port_tag_reaches_the_endpoint(weblab):
    ports = {c.name: c.endpoint and c.endpoint.port for c in weblab.containers}
    assert ports == {"UserSide": None, "WebLabSide": 47020}


def test_documentation_from_uml_comments(weblab):
    nav = next(c for c in weblab.components if c.name == "Navigator")
    assert nav.documentation.startswith("The user's control program")
    assert "\nThe only element deployed on the user's side." in nav.documentation


# ------------------------------------------------------------------ against acordcs-gen inspect
def test_same_elements_as_inspect(weblab, inspected):
    elements = inspected["elements"]
    assert [c.name for c in weblab.containers] == elements["CtxContainer"]
    assert [c.name for c in weblab.components] == elements["CtxComponent"]
    assert sorted(p.name for c in weblab.components for p in c.ports) == elements["CtxPort"]
    assert [c.name for c in weblab.connections] == elements["CtxPortConnection"]
    assert [m.name for m in weblab.monitors] == elements["CtxMonitor"]
    assert [p.name for p in weblab.policy_sets] == elements["CtxPolicySet"]
    policies = sorted(p.name for ps in weblab.policy_sets for p in ps.policies)
    assert policies == elements["CtxPolicy"]


def test_same_deployment_and_policy_sets_as_inspect(weblab, inspected):
    deployment = {c.name: sorted(r.name for r in c.hosts) for c in weblab.containers}
    assert deployment == inspected["deployment"]
    for ps in weblab.policy_sets:
        summary = inspected["policy_sets"][ps.name]
        assert ps.engine == summary["engine"]
        assert ps.trigger == summary["trigger"]
        assert len(ps.rules()) == summary["rules"]
        assert [p.name for p in ps.policies] == sorted(summary["policies"])
        assert [r.name for r in ps.adapts] == sorted(summary["adapts"])
        assert list(weblab.fed_by(ps.name)) == sorted(summary["fed_by"])


# ----------------------------------------------------------------------- against the pyecore model
def _name(obj) -> str:
    owner = obj.eContainer()
    return f"{owner.name}.{obj.name}" if obj.eClass.name == "CtxPort" else obj.name


def _default(attr):
    """What a default should be, read off the pyecore attribute (the runtime's rule)."""
    kind = (attr.type or "").lower()
    text, var = attr.defaultValue, attr.variable
    if kind in ("int", "integer", "long", "short"):
        return int(float(text)) if text else int(var.rangeMin or 0) if var else 0
    if kind in ("double", "float", "real", "number") or var is not None:
        return float(text) if text else float(var.rangeMin or 0.0) if var else 0.0
    if kind in ("bool", "boolean"):
        return str(text).strip().lower() in ("true", "1", "yes")
    return text if text is not None else ""


def _attributes(obj):
    return [(a.xmiId, a.name, a.type or "", _default(a)) for a in obj.attributes]


def _properties(props):
    return [(p.id, p.name, p.type, p.default) for p in props]


def _operations(obj):
    return [
        (
            o.xmiId,
            o.name,
            o.returnType,
            [(p.name, p.type or "", p.direction.name) for p in o.parameters],
        )
        for o in obj.operations
    ]


def _ops(ops):
    return [
        (o.id, o.name, o.return_type, [(p.name, p.type, p.direction) for p in o.parameters])
        for o in ops
    ]


def test_containers_as_pyecore(weblab, ecore):
    expected = {
        c.name: (
            c.xmiId,
            c.host,
            sorted(e.name for e in [*c.components, *c.monitors, *c.policySets]),
            _attributes(c),
        )
        for c in ecore.containers
    }
    got = {
        c.name: (c.id, c.host, sorted(r.name for r in c.hosts), _properties(c.properties))
        for c in weblab.containers
    }
    assert got == expected


def test_components_ports_and_operations_as_pyecore(weblab, ecore):
    expected = {
        c.name: (
            c.xmiId,
            c.language.name,
            c.persistent,
            _attributes(c),
            _operations(c),
            sorted(
                (p.name, p.xmiId, p.kind.name, p.role.name, tuple(map(tuple, _attributes(p))))
                for p in c.ports
            ),
        )
        for c in ecore.components
    }
    got = {
        c.name: (
            c.id,
            c.language,
            c.persistent,
            _properties(c.properties),
            _ops(c.operations),
            sorted(
                (p.name, p.id, p.kind, p.role, tuple(map(tuple, _properties(p.properties))))
                for p in c.ports
            ),
        )
        for c in weblab.components
    }
    assert got == expected


def test_connection_ends_and_qos_as_pyecore(weblab, ecore):
    expected = {
        c.name: (
            c.xmiId,
            c.connector.name,
            (c.required.eContainer().name, c.required.name, c.required.xmiId),
            (c.provided.eContainer().name, c.provided.name, c.provided.xmiId),
            _attributes(c),
        )
        for c in ecore.connections
    }
    got = {
        c.name: (
            c.id,
            c.connector,
            (c.required.component, c.required.port, c.required.id),
            (c.provided.component, c.provided.port, c.provided.id),
            _properties(c.qos),
        )
        for c in weblab.connections
    }
    assert got == expected


def test_monitors_as_pyecore(weblab, ecore):
    expected = {
        m.name: (
            m.xmiId,
            m.frequency if m.eIsSet("frequency") else None,
            sorted(_name(s) for s in m.sources),
            sorted(p.name for p in m.feeds),
            _attributes(m),
        )
        for m in ecore.monitors
    }
    got = {
        m.name: (
            m.id,
            m.frequency,
            [s.name for s in m.sources],
            [f.name for f in m.feeds],
            _properties(m.properties),
        )
        for m in weblab.monitors
    }
    assert got == expected


def _scope_variables(ps, ecore):
    """The linguistic variables of a policy set's scope, from the pyecore model."""
    scope = [m for m in ecore.monitors if ps in m.feeds]
    for target in ps.adapts:
        scope.append(target)
        if target.eClass.name == "CtxComponent":
            scope.extend(target.ports)
    out = set()
    for element in scope:
        for a in element.attributes:
            if a.variable is not None:
                terms = tuple((t.name, t.shape.name, tuple(t.parameters)) for t in a.variable.terms)
                out.add(
                    (f"{_name(element)}.{a.name}", a.variable.rangeMin, a.variable.rangeMax, terms)
                )
    return sorted(out)


def test_policy_sets_rules_and_variables_as_pyecore(weblab, ecore):
    expected = {
        ps.name: (
            ps.xmiId,
            ps.engine.name,
            ps.semantics.name,
            ps.trigger.name,
            ps.frequency if ps.eIsSet("frequency") else None,
            sorted(_name(a) for a in ps.adapts),
            sorted(
                (p.name, p.xmiId, tuple((r.label, r.text, r.tag) for r in p.rules))
                for p in ps.policies
            ),
            _scope_variables(ps, ecore),
        )
        for ps in ecore.policySets
    }
    got = {
        ps.name: (
            ps.id,
            ps.engine,
            ps.semantics,
            ps.trigger,
            ps.frequency,
            [a.name for a in ps.adapts],
            [(p.name, p.id, tuple((r.label, r.text, r.tag) for r in p.rules)) for p in ps.policies],
            sorted(
                (
                    v.name,
                    v.minimum,
                    v.maximum,
                    tuple((t.name, t.shape, t.parameters) for t in v.terms),
                )
                for v in ps.variables
            ),
        )
        for ps in weblab.policy_sets
    }
    assert got == expected
