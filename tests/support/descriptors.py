"""Small application descriptors written by hand, for the runtime's assembly tests.

Ids and qualified names are made up from the names: ``assemble`` reads names, kinds and values.
What the policy sets' rules name is resolved as the toolchain's ``describe`` does it, with the one
resolution (:func:`acordcs.rules.binding.bind`), over the scope these descriptors give each set
(:func:`application` does it for the sets given without it).
"""

from __future__ import annotations

from dataclasses import replace

from acordcs.descriptor.application import (
    Application,
    Component,
    Connection,
    Container,
    End,
    Monitor,
    Operation,
    Parameter,
    Policy,
    PolicySet,
    Port,
    Property,
    Ref,
    Rule,
    Term,
    Variable,
    bound_names,
)
from acordcs.rules import parse_rule
from acordcs.rules.binding import Scope, ScopeElement, bind, default_label, rule_syntax

_KIND = {int: "int", float: "double", bool: "bool", str: "string"}


def prop(name: str, default: bool | int | float | str) -> Property:
    kind = _KIND[type(default)]
    return Property(f"id-{name}", name, f"M::{name}", kind, kind, default)


def op(name: str, *params: tuple[str, str, str], returns: str | None = None) -> Operation:
    """``op("find", ("x", "double", "in"), ("n", "int", "out"), returns="bool")``."""
    parameters = tuple(Parameter(f"id-{name}-{p}", p, t, d) for p, t, d in params)
    return Operation(f"id-{name}", name, f"M::{name}", parameters, returns)


def port(name: str, kind: str = "synchronous", role: str = "provided", *props: Property) -> Port:
    return Port(f"id-{name}", name, f"M::{name}", kind, role, tuple(props))


def component(
    name: str,
    *,
    properties: tuple[Property, ...] = (),
    operations: tuple[Operation, ...] = (),
    ports: tuple[Port, ...] = (),
    persistent: bool = False,
) -> Component:
    return Component(
        f"id-{name}", name, f"M::{name}", "python", properties, operations, ports,
        persistent=persistent,
    )  # fmt: skip


def ref(kind: str, name: str) -> Ref:
    return Ref(kind, name, f"id-{name}")


def container(name: str, *hosted: Ref, properties: tuple[Property, ...] = ()) -> Container:
    return Container(f"id-{name}", name, f"M::{name}", "localhost", None, hosted, properties)


def connection(
    name: str, required: str, provided: str, connector: str = "inprocess", *qos: Property
) -> Connection:
    """Ends as ``Component.Port``."""
    (rc, rp), (pc, pp) = required.split("."), provided.split(".")
    return Connection(
        f"id-{name}",
        name,
        f"M::{name}",
        connector,
        End(rc, rp, f"id-{rp}"),
        End(pc, pp, f"id-{pp}"),
        tuple(qos),
    )


def monitor(
    name: str,
    *properties: Property,
    frequency: float | None = None,
    sources: tuple[Ref, ...] = (),
    feeds: tuple[str, ...] = (),
    acquisition: str | None = None,
    xpath: str | None = None,
    operation: str | None = None,
) -> Monitor:
    return Monitor(
        f"id-{name}",
        name,
        f"M::{name}",
        frequency,
        acquisition or ("intercept" if frequency is None else "custom"),
        xpath,
        operation,
        sources,
        tuple(ref("policy-set", f) for f in feeds),
        properties,
    )


def variable(element: str, attribute: str, lo: float, hi: float, **terms: str) -> Variable:
    """Terms as ``slow="trapezoid 0 0 40 80"``."""
    parsed = []
    for term, text in terms.items():
        shape, *numbers = text.split()
        parsed.append(Term(term, shape, tuple(float(n) for n in numbers)))
    return Variable(
        f"id-{element}-{attribute}",
        element,
        attribute,
        f"M::{element}::{attribute}",
        lo,
        hi,
        tuple(parsed),
    )


def policy_set(
    name: str,
    rules: dict[str, list[str]],
    *,
    engine: str = "clips",
    trigger: str = "event",
    frequency: float | None = None,
    semantics: str = "mamdani",
    adapts: tuple[Ref, ...] = (),
    variables: tuple[Variable, ...] = (),
) -> PolicySet:
    """Rules as ``"label: if ..."`` or ``"if ..."``, per policy name."""
    policies = []
    for policy, texts in rules.items():
        parsed = []
        taken = {t.partition(": ")[0] for t in texts if ": " in t}
        for position, text in enumerate(texts, start=1):
            label, sep, rest = text.partition(": ")
            if sep:
                parsed.append(Rule(label, rest, "Rule", position))
            else:
                label = default_label(position, taken)
                taken.add(label)
                parsed.append(Rule(label, text, "Rule", position, assigned_label=True))
        policies.append(Policy(f"id-{policy}", policy, f"M::{policy}", tuple(parsed)))
    return PolicySet(
        f"id-{name}",
        name,
        f"M::{name}",
        engine,
        semantics,
        trigger,
        frequency,
        adapts,
        tuple(policies),
        variables,
    )


def application(name: str = "App", **parts: tuple) -> Application:
    """The application; its policy sets' rule names bound (see the module docstring)."""
    app = Application(name, **parts)
    return replace(app, policy_sets=tuple(bound(app, ps) for ps in app.policy_sets))


def _scope(app: Application, ps: PolicySet) -> list[ScopeElement]:
    """The elements a set's rules may name: the monitors feeding it, what it adapts (a
    component with its ports)."""

    def element(name, item, properties, short=None):
        return ScopeElement(
            name,
            {p.name: p for p in properties},
            {o.name: o for o in item.operations},
            short=short,
        )

    out = [element(m.name, m, m.properties) for m in app.monitors if m.name in _fed(app, ps)]
    components = {c.name: c for c in app.components}
    for target in ps.adapts:
        if target.kind == "component" and target.name in components:
            c = components[target.name]
            out.append(element(c.name, c, c.properties))
            out += [element(f"{c.name}.{p.name}", p, p.properties, p.name) for p in c.ports]
        elif target.kind == "container":
            c = next(c for c in app.containers if c.name == target.name)
            out.append(element(c.name, c, c.properties))
        elif target.kind == "connection":
            c = next(c for c in app.connections if c.name == target.name)
            out.append(element(c.name, c, c.qos))
    return out


def _fed(app: Application, ps: PolicySet) -> set[str]:
    return {m.name for m in app.monitors if any(f.name == ps.name for f in m.feeds)}


def bound(app: Application, ps: PolicySet) -> PolicySet:
    """``ps`` with what its rules name resolved (left as it is when already resolved, or when a
    name does not resolve: assembling it then fails, as with any descriptor left unresolved)."""
    if ps.bound:
        return ps
    syntax = rule_syntax(ps.engine)
    found = bind(Scope(_scope(app, ps)), (parse_rule(r.line, syntax) for r in ps.rules()), syntax)
    if found.problems:
        return ps
    return replace(
        ps,
        bound=bound_names(found.targets().values()),
        inputs=found.inputs,
        outputs=found.outputs,
        triggers=found.triggers,
    )
