"""An oracle: a ClipsEngine built straight from the pyecore model (``acordcs.ecore`` instances, as
``acordcs.model.ecore_builder.to_ecore`` makes them), resolving a policy set's scope on its own.

The runtime and the ``rules`` target build from the descriptor; tests hold them to this. Every
attribute of an element in scope becomes a typed variable ``Element.attribute`` with the model's
default as its initial value; every operation becomes a declared operation whose parameters (those
of direction ``in`` or ``inout``) fix its number of arguments.
"""

from __future__ import annotations

from collections.abc import Iterable

from acordcs.engines.clips.clips_engine import ClipsEngine
from acordcs.engines.clips.values import kind_of_type, parse_default
from acordcs.engines.rule_engine import RuleError


def _literal(value: object) -> str:
    return str(getattr(value, "name", value))


def declare_element(engine: ClipsEngine, element: object) -> None:
    """Declare the attributes and operations of one CtxElement (container, component, port, monitor...)."""
    name = element.name
    for attribute in element.attributes:
        variable = f"{name}.{attribute.name}"
        initial = None
        if attribute.defaultValue not in (None, ""):
            try:
                initial = parse_default(attribute.defaultValue, kind_of_type(attribute.type))
            except ValueError as err:
                raise RuleError(
                    f"default value of {variable} ({attribute.type}): {err}; fix it in the model",
                    line=getattr(attribute, "sourceLine", None) or None,
                ) from None
        engine.declare(variable, initial, type=attribute.type)
    for operation in element.operations:
        parameters = [
            p.name for p in operation.parameters if _literal(p.direction) in ("in", "inout", "None")
        ]
        engine.declare_operation(f"{name}.{operation.name}", parameters)


def scope_of(policy_set: object, monitors: Iterable[object] = ()) -> list[object]:
    """The elements a policy set's rules may use: what it adapts (with a component's ports) and its monitors."""
    out: list[object] = []
    for element in policy_set.adapts:
        out.append(element)
        out.extend(getattr(element, "ports", ()))
    out.extend(monitors)
    return out


def engine_for_policy_set(
    policy_set: object, monitors: Iterable[object] = (), *, max_firings: int = 10_000
) -> ClipsEngine:
    """A strict engine with the set's scope declared and each policy's rules in a rule set named after it."""
    engine = ClipsEngine(max_firings=max_firings, strict=True)
    for element in scope_of(policy_set, monitors):
        declare_element(engine, element)
    for policy in policy_set.policies:
        for rule in policy.rules:
            text = rule.text or ""
            if rule.label and not text.lstrip().startswith(f"{rule.label}:"):
                text = f"{rule.label}: {text}"
            engine.defrule(text, policy.name)
    return engine
