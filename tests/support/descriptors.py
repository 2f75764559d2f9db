"""Small application descriptors written by hand, for the runtime's assembly tests.

Ids and qualified names are made up from the names: ``assemble`` reads names, kinds and values.
"""

from __future__ import annotations

from acordcs.descriptor.model import (
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
)

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
) -> Component:
    return Component(f"id-{name}", name, f"M::{name}", "python", properties, operations, ports)


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
        for text in texts:
            label, sep, rest = text.partition(": ")
            parsed.append(Rule(label, rest, "Rule") if sep else Rule(None, text, "Rule"))
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
    return Application(name, **parts)
