"""What the console's page is told of the application, from its descriptor, once (the
``application`` channel): the architecture's SVG (:mod:`.diagram`), every element's kind,
qualified name, model id, container, properties and operations (shown when it is clicked), the
series to plot (each monitor's numeric properties, with the range a policy set's variable gives
it), each policy set's inputs, outputs and rules, the operations of provided synchronous ports
(a port declaring none offers its component's, as the remote connector does) and the components'
properties (the forms of the page, typed by the model). The page derives nothing from the
model itself: what it shows is computed here, once.
"""

from __future__ import annotations

from typing import Any

from acordcs.console.diagram import architecture_svg
from acordcs.descriptor.application import Application, Operation, Property

NUMERIC = frozenset({"int", "double"})
"""Value kinds plotted (the descriptor's kinds of numbers)."""


def _property(p: Property) -> dict[str, Any]:
    return {"name": p.name, "type": p.type, "kind": p.kind, "default": p.default}


def _operation(o: Operation) -> dict[str, Any]:
    return {
        "name": o.name,
        "qname": o.qualified_name,
        "id": o.id,
        "returns": o.return_type,
        "parameters": [
            {"name": p.name, "type": p.type, "direction": p.direction} for p in o.parameters
        ],
    }


def page_model(app: Application) -> dict[str, Any]:
    """The ``application`` payload of ``app`` (see the module docstring)."""
    where = {r.name: c.name for c in app.containers for r in c.hosts}
    ranges: dict[str, tuple[float, float]] = {}
    for s in app.policy_sets:
        for v in s.variables:
            ranges.setdefault(f"{v.element}.{v.attribute}", (v.minimum, v.maximum))
    elements: dict[str, dict[str, Any]] = {}
    for c in app.containers:
        elements[c.name] = {"kind": "container", "qname": c.qualified_name, "id": c.id,
                            "container": c.name, "host": c.host,
                            "properties": [_property(p) for p in c.properties]}  # fmt: skip
    for comp in app.components:
        elements[comp.name] = {
            "kind": "component",
            "qname": comp.qualified_name,
            "id": comp.id,
            "container": where.get(comp.name),
            "language": comp.language,
            "persistent": comp.persistent,
            "properties": [_property(p) for p in comp.properties],
            "operations": [_operation(o) for o in comp.operations],
            "ports": [
                {
                    "name": p.name,
                    "qname": p.qualified_name,
                    "id": p.id,
                    "kind": p.kind,
                    "role": p.role,
                    "operations": [o.name for o in p.operations],
                }
                for p in comp.ports
            ],
        }
    for conn in app.connections:
        elements[conn.name] = {
            "kind": "connection",
            "qname": conn.qualified_name,
            "id": conn.id,
            "connector": conn.connector,
            "required": f"{conn.required.component}.{conn.required.port}",
            "provided": f"{conn.provided.component}.{conn.provided.port}",
        }
    series = []
    for m in app.monitors:
        elements[m.name] = {
            "kind": "monitor",
            "qname": m.qualified_name,
            "id": m.id,
            "container": where.get(m.name),
            "acquisition": m.acquisition,
            "frequency": m.frequency,
            "sources": [r.name for r in m.sources],
            "feeds": [r.name for r in m.feeds],
            "properties": [_property(p) for p in m.properties],
        }
        for p in m.properties:
            if p.kind in NUMERIC:
                low, high = ranges.get(f"{m.name}.{p.name}", (None, None))
                series.append({"key": f"{m.name}.{p.name}", "monitor": m.name,
                               "attribute": p.name, "type": p.type, "min": low, "max": high,
                               "container": where.get(m.name)})  # fmt: skip
    sets = []
    for s in app.policy_sets:
        elements[s.name] = {
            "kind": "policy-set",
            "qname": s.qualified_name,
            "id": s.id,
            "container": where.get(s.name),
            "engine": s.engine,
            "semantics": s.semantics,
            "trigger": s.trigger,
            "frequency": s.frequency,
            "adapts": [r.name for r in s.adapts],
            "fed_by": list(app.fed_by(s.name)),
        }
        sets.append({
            "name": s.name,
            "engine": s.engine,
            "container": where.get(s.name),
            "inputs": list(s.inputs),
            "outputs": list(s.outputs),
            "rules": [{"policy": p.name, "label": r.label, "text": r.text}
                      for p in s.policies for r in p.rules],
            "ranges": {k: list(v) for k, v in ranges.items() if k in (*s.inputs, *s.outputs)},
        })  # fmt: skip
    # A provided synchronous port that declares no operations offers its component's (what the
    # remote connector exposes to other processes).
    operations = [
        {"component": comp.name, "port": port.name, "container": where.get(comp.name),
         **_operation(o)}
        for comp in app.components
        for port in comp.ports
        if port.role == "provided" and port.kind == "synchronous"
        for o in (port.operations or comp.operations)
    ]  # fmt: skip
    properties = [
        {"element": comp.name, "attribute": p.name, "type": p.type, "kind": p.kind,
         "default": p.default, "container": where.get(comp.name)}
        for comp in app.components
        for p in comp.properties
    ]  # fmt: skip
    return {
        "name": app.name,
        "svg": architecture_svg(app),
        "containers": [c.name for c in app.containers],
        "elements": elements,
        "series": series,
        "policy_sets": sets,
        "operations": operations,
        "properties": properties,
    }
