"""A crisp policy set of the descriptor as one CLIPS file, compiled by the runtime's CLIPS compiler.

The file holds what :class:`acordcs.runtime.clips.ClipsEngine` builds in its environment for the
set: the prelude (:mod:`acordcs.runtime.clips.prelude`), one global per variable of the set's scope
(``?*Element.attribute*``, the model's default as its value), the dispatchers, one module per
policy, and each rule compiled by :func:`acordcs.runtime.clips.compiler.compile_rule`. What the
records of a fire stand for (variable numbers, call and constant sites) is stated as facts
(``acord-variable``, ``acord-site``), so a program other than ours can read them. Use::

    (load "Recovering.clp") (reset) (acord-init)
    (acord-fire-set RecoveryRules FALSE 1 0.0)   ; set variable 1 to 0.0, run RecoveryRules

The scope is the runtime's (:func:`acordcs.runtime.clips.model.scope_of`): the elements the set
adapts (a component with its ports) and the monitors feeding it; a port is named by its own name.
Every name reaching the file is an identifier (checked first), strings are escaped by the
compiler's :func:`~acordcs.runtime.clips.compiler.quote`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from acordcs.codegen.targets.names import NameRefused, require_identifiers, rule_line
from acordcs.descriptor import Application, PolicySet, Property

_IN = ("in", "inout")


@dataclass(frozen=True)
class _Element:
    name: str
    id: str
    qualified_name: str
    properties: tuple
    operations: tuple


def scope(app: Application, ps: PolicySet) -> list[_Element]:
    """The elements whose attributes and operations the set's crisp rules may use, in order."""
    components = {c.name: c for c in app.components}
    out: list[_Element] = []

    def add(element: object) -> None:
        out.append(
            _Element(
                element.name,
                element.id,
                element.qualified_name,
                tuple(getattr(element, "properties", ()) or getattr(element, "qos", ())),
                tuple(element.operations),
            )
        )

    by_kind = {
        "container": {c.name: c for c in app.containers},
        "connection": {c.name: c for c in app.connections},
    }
    for ref in ps.adapts:
        if ref.kind == "component" and ref.name in components:
            component = components[ref.name]
            add(component)
            for port in component.ports:
                add(port)
        elif ref.kind == "port":
            owner, _, port_name = ref.name.rpartition(".")
            port = components[owner].port(port_name) if owner in components else None
            if port is not None:
                add(port)
        elif ref.name in by_kind.get(ref.kind, {}):
            add(by_kind[ref.kind][ref.name])
    fed = set(app.fed_by(ps.name))
    for monitor in app.monitors:
        if monitor.name in fed:
            add(monitor)
    seen: set[str] = set()
    return [e for e in out if not (e.id in seen or seen.add(e.id))]


def _literal(prop: Property) -> str:
    from acordcs.runtime.clips.compiler import quote

    value = prop.default
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, str):
        if "\x00" in value:
            raise NameRefused("default value", value, prop.id, prop.qualified_name)
        return quote(value)
    if isinstance(value, int):
        return repr(value) if abs(value) < 2**63 else repr(float(value))
    if isinstance(value, float) and math.isfinite(value):
        return repr(value)
    raise NameRefused("default value", value, prop.id, prop.qualified_name)


def clips_for(app: Application, ps: PolicySet) -> str:
    """The CLIPS program of one crisp policy set (without the header). Raises NameRefused (a name
    that is not an identifier) or RuleError (a rule the compiler refuses: validate the model)."""
    from acordcs.rules import Name, parse_rule
    from acordcs.runtime.clips.compiler import Target, compile_rule, quote
    from acordcs.runtime.clips.prelude import (
        FIRE,
        NUMERIC_FLAG,
        RUN,
        assign_dispatcher,
        fixed_constructs,
        put_dispatcher,
    )
    from acordcs.runtime.clips.records import Sites
    from acordcs.runtime.rule_engine import RuleError

    elements = scope(app, ps)
    names: list[tuple[str, object, str, str]] = [("policy set", ps.name, ps.id, ps.qualified_name)]
    for p in ps.policies:
        names.append(("policy", p.name, p.id, p.qualified_name))
        names += [("rule label", r.label, p.id, p.qualified_name) for r in p.rules if r.label]
    for e in elements:
        names.append(("element", e.name, e.id, e.qualified_name))
        names += [("attribute", a.name, a.id, a.qualified_name) for a in e.properties]
        names += [("operation", o.name, o.id, o.qualified_name) for o in e.operations]
    require_identifiers(names)
    for p in ps.policies:
        if p.name == "MAIN":
            raise NameRefused("policy (MAIN is CLIPS's own module)", p.name, p.id, p.qualified_name)

    variables: dict[str, tuple[Target, Property]] = {}
    by_member: dict[str, list[str]] = {}
    for e in elements:
        for prop in e.properties:
            full = f"{e.name}.{prop.name}"
            if full in variables:
                continue
            index = len(variables) + 1
            variables[full] = (Target(index, f"?*{full}*"), prop)
            by_member.setdefault(prop.name, []).append(full)
    operations: dict[str, int] = {}
    arity: dict[str, int] = {}
    op_members: dict[str, list[str]] = {}
    for e in elements:
        for op in e.operations:
            full = f"{e.name}.{op.name}"
            if full not in operations:
                operations[full] = len(operations) + 1
                arity[full] = sum(1 for p in op.parameters if p.direction in _IN)
                op_members.setdefault(op.name, []).append(full)

    def lookup(text: str, table: dict, members: dict[str, list[str]], what: str) -> str:
        if text in table:
            return text
        found = members.get(text, []) if "." not in text else []
        if len(found) == 1:
            return found[0]
        raise LookupError(
            f"{what} {text!r} is not in the scope of policy set {ps.name} "
            f"({'ambiguous: ' + ', '.join(found) if found else 'unknown'}); validate the model"
        )

    def variable(name: Name) -> Target:
        return variables[lookup(name.text, variables, by_member, "variable")][0]

    def operation(name: Name, nargs: int) -> int:
        full = lookup(name.text, operations, op_members, "operation")
        if arity[full] != nargs:
            raise LookupError(f"operation {full} takes {arity[full]} argument(s), not {nargs}")
        return operations[full]

    sites = Sites()
    labels: dict[int, str] = {}
    read: set[int] = set()
    modules: list[str] = []
    rule_id = 0
    for policy in ps.policies:
        module = [f"(defmodule {policy.name} (import MAIN ?ALL))"]
        taken: set[str] = set()
        for position, rule in enumerate(policy.rules):
            rule_id += 1
            label = rule.label
            if not label:
                n = position + 1
                while f"rule_{n}" in taken:
                    n += 1
                label = f"rule_{n}"
            taken.add(label)
            labels[rule_id] = f"{policy.name}::{label}"
            try:
                parsed = parse_rule(rule_line(rule), "crisp")
            except Exception as err:  # RuleSyntaxError: the model did not validate
                raise RuleError(
                    f"{getattr(err, 'message', err)}; validate the model",
                    ruleset=policy.name,
                    rule=label,
                ) from None
            compiled = compile_rule(
                parsed,
                ruleset=policy.name,
                module=policy.name,
                label=label,
                rule_id=rule_id,
                salience=9999 - position,
                variables=variable,
                operations=operation,
                sites=sites,
            )
            read.update(compiled.reads)
            module += compiled.constructs
        modules.append("\n".join(module))

    names_by_index = {t.index: full for full, (t, _) in variables.items()}
    ops_by_number = {n: full for full, n in operations.items()}
    globals_ = [NUMERIC_FLAG] + [t.global_name for t, _ in variables.values()]
    out = list(fixed_constructs())
    out += [
        f"(defglobal MAIN {t.global_name} = {_literal(prop)} ?*acord-vf{t.index}* = FALSE)"
        for t, prop in variables.values()
    ]
    out.append(put_dispatcher(globals_))
    out.append(assign_dispatcher(list(variables), [t for t, _ in variables.values()]))
    out += [RUN, FIRE]
    out.append(
        "(deftemplate MAIN::acord-variable (slot number) (slot name) (slot type))\n"
        '(deftemplate MAIN::acord-site (slot number) (slot kind) (slot rule (default ""))'
        " (slot target) (slot arguments (default 0)) (slot value))"
    )
    facts = [
        f"  (acord-variable (number {t.index}) (name {quote(full)}) (type {quote(prop.type)}))"
        for full, (t, prop) in variables.items()
    ]
    out.append("(deffacts MAIN::acord-variables\n" + "\n".join(facts) + ")" if facts else "")
    site_facts = []
    for number, (op, index, value) in enumerate(sites.entries[1:], start=1):
        if op:  # a call: (op, rule, nargs)
            site_facts.append(
                f"  (acord-site (number {number}) (kind call) (rule {quote(labels[index])})"
                f" (target {quote(ops_by_number[op])}) (arguments {value}))"
            )
        else:  # a constant assigned: (0, variable index, value)
            site_facts.append(
                f"  (acord-site (number {number}) (kind assign)"
                f" (target {quote(names_by_index[index])}) (value {_value(value)}))"
            )
    if site_facts:
        out.append("(deffacts MAIN::acord-sites\n" + "\n".join(site_facts) + ")")
    init = " ".join(f"(bind ?*acord-vf{i}* (assert (acord-var (i {i}))))" for i in sorted(read))
    out.append(f"(deffunction MAIN::acord-init () {init} TRUE)")
    out += modules
    return "\n\n".join(c.strip() for c in out if c) + "\n"


def _value(value: object) -> str:
    from acordcs.runtime.clips.compiler import quote

    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, str):
        return quote(value)
    return repr(value)
