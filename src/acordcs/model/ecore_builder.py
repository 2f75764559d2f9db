"""The ACORD-CS model as pyecore instances of the metamodel, built from a checked architecture.

What ``acordcs-gen export --format ecore`` writes (an XMI instance of ``acordcs.ecore`` that EMF
tools load), and, in the tests, an oracle read apart from the descriptor. Validation and generation
work on the architecture and the descriptor instead: pyecore costs about 40 us per object.
"""

from __future__ import annotations

from acordcs import metamodel
from acordcs.model.architecture import (
    COMPONENT,
    CONNECTION,
    CONTAINER,
    MONITOR,
    POLICY_SET,
    Architecture,
    Role,
)
from acordcs.model.queries import (
    parse_integer,
    parse_real,
    policy_rules,
    rule_kind,
    variable_terms,
)
from acordcs.rules import RuleSyntaxError, parse_rule
from acordcs.typed_values import parse_boolean
from acordcs.xmi.uml import Classifier

_TYPED_PARSERS = {"EDouble": parse_real, "EInt": parse_integer, "EBoolean": parse_boolean}

_ROOT_LISTS = {
    CONTAINER: "containers",
    COMPONENT: "components",
    MONITOR: "monitors",
    POLICY_SET: "policySets",
    CONNECTION: "connections",
}


def to_ecore(arch: Architecture):
    """An ``Application`` holding every role of ``arch`` with its attributes, tags and relations.

    Meant for a model that validates without errors; elements an error left without a place (a port
    of no component, a policy of no set) are left out.
    """
    app = metamodel.create("Application", name=arch.uml.name or "application")
    built: dict[str, object] = {}
    for kind, feature in _ROOT_LISTS.items():
        for role in arch.of_kind(kind):
            obj = _element(role, arch)
            built[role.id] = obj
            getattr(app, feature).append(obj)
            if kind == COMPONENT:
                for port in arch.related(role, "owns_port"):
                    port_obj = _element(port, arch)
                    built[port.id] = port_obj
                    obj.ports.append(port_obj)
    for ps in arch.of_kind(POLICY_SET):
        ps_obj = built[ps.id]
        engine = ps.tag("engine")
        for policy in arch.policies(ps):
            pol = metamodel.create(
                "CtxPolicy", name=policy.name, xmiId=policy.id, sourceLine=policy.element.line
            )
            for n, rule in enumerate(policy_rules(policy), start=1):
                label, text = _split_label(rule.text, rule_kind(ps))
                pol.rules.append(
                    metamodel.create(
                        "Rule",
                        name=label or f"{policy.name}_{n}",
                        label=label,
                        text=text,  # the rule without its label: the label is its own feature
                        engine=_enum("EngineKind", engine),
                        tag=rule.tag,
                    )
                )
            ps_obj.policies.append(pol)
        ps_obj.adapts.extend(built[t.id] for t in arch.related(ps, "adapts") if t.id in built)
    for container in arch.of_kind(CONTAINER):
        obj = built[container.id]
        for hosted in arch.related(container, "hosts"):
            target = built.get(hosted.id)
            feature = {COMPONENT: "components", MONITOR: "monitors", POLICY_SET: "policySets"}[
                hosted.kind
            ]
            if target is not None:
                getattr(obj, feature).append(target)
    for monitor in arch.of_kind(MONITOR):
        obj = built[monitor.id]
        obj.feeds.extend(built[s.id] for s in arch.related(monitor, "feeds") if s.id in built)
        obj.sources.extend(built[s.id] for s in arch.related(monitor, "sources") if s.id in built)
    for conn in arch.of_kind(CONNECTION):
        obj = built[conn.id]
        for port in arch.related(conn, "joins"):
            if port.id in built:
                setattr(
                    obj,
                    "provided" if port.tag("role") == "provided" else "required",
                    built[port.id],
                )
    return app


def _split_label(text: str, kind) -> tuple[str | None, str]:
    """A rule's label, as the rule parser reads it, and the rule without it (after the label's
    colon, the first in the text: a label is a name)."""
    try:
        label = parse_rule(text, kind).label
    except RuleSyntaxError:  # the checks report it; the text is kept whole
        return None, text
    return (label, text.split(":", 1)[1].strip()) if label else (None, text)


def _enum(name: str, literal: str | None):
    enum = metamodel.load().getEClassifier(name)
    return enum.getEEnumLiteral(literal) if literal else enum.default_value


def _element(role: Role, arch: Architecture):
    obj = metamodel.create(role.kind, name=role.name, xmiId=role.id, sourceLine=role.element.line)
    eclass = obj.eClass
    for tag in role.stereotype.tags:
        if tag.syntax:
            continue
        value = role.tag(tag.name)
        if value is None:
            continue
        feature = eclass.findEStructuralFeature(tag.feature)
        if tag.values:
            setattr(obj, tag.feature, _enum(tag.type, value))
        elif feature.eType.name in _TYPED_PARSERS:
            typed = _TYPED_PARSERS[feature.eType.name](value)
            if typed is not None:  # a value of the wrong type is the checks' T304
                setattr(obj, tag.feature, typed)
        else:
            setattr(obj, tag.feature, value)
    element = role.element
    if isinstance(element, Classifier):
        for prop in element.attributes:
            attr = metamodel.create(
                "Attribute",
                name=prop.name,
                xmiId=prop.id,
                sourceLine=prop.line,
                type=prop.type_name,
                defaultValue=prop.default,
            )
            attr_role = arch.variable(prop)
            if attr_role is not None:  # a linguistic variable carries its range and terms
                attr.variable = _variable(attr_role)
            obj.attributes.append(attr)
        for op in element.operations:
            operation = metamodel.create(
                "Operation",
                name=op.name,
                xmiId=op.id,
                sourceLine=op.line,
                returnType=op.return_type,
            )
            for param in op.inputs:
                operation.parameters.append(
                    metamodel.create(
                        "Parameter",
                        name=param.name,
                        type=param.type_name,
                        direction=_enum("ParameterDirection", param.direction),
                    )
                )
            obj.operations.append(operation)
    return obj


def _variable(role: Role):
    lo = parse_real(role.tags.get("min", "")) or 0.0
    hi = parse_real(role.tags.get("max", "")) or 0.0
    var = metamodel.create("CtxVariable", rangeMin=lo, rangeMax=hi)
    for term in variable_terms(role):
        var.terms.append(
            metamodel.create(
                "LinguisticTerm",
                name=term.name.text,
                shape=_enum("MembershipShape", term.shape),
                parameters=[float(p) for p in term.parameters],
            )
        )
    return var
