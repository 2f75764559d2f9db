"""How a policy set's plan is bound to its container: the engine built from the plan, and the
engine's variables and operations bound to the container's elements (:class:`Bound`, what a
firing of :class:`~acordcs.runtime.policy.PolicySet` runs: :func:`bind`), the checks that the
elements are there (:func:`check_elements`), and the scope a set made by hand resolves its
rules over (:func:`scope`)."""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol

from acordcs.engines.engine_registry import EngineSetup, Variable, lookup_engine
from acordcs.engines.plan import PolicyPlan
from acordcs.engines.rule_engine import RuleEngine
from acordcs.rules.binding import ScopeElement
from acordcs.runtime.errors import BindingError

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock
    from acordcs.runtime.dispatch import Handler
    from acordcs.runtime.events import FaultLog

Target = tuple[str, str]
Call = Callable[[dict[str, Target], str, tuple[Any, ...]], Any]


class PolicyHost(Protocol):
    """What a policy set needs from its container: its elements, events, clock and calls."""

    name: str
    clock: Clock
    faults: FaultLog
    stats: Counter[str]
    # The element events emitted now are attributed to (a policy set applying its actions).
    origin: str | None

    def elements(self) -> dict[str, dict[str, object]]: ...

    def monitors(self) -> list[str]: ...

    def operations_of(self, component: str) -> frozenset[str]: ...

    def subscribe(
        self,
        kind: str,
        handler: Handler,
        *,
        name: str,
        element: str | None = None,
        attribute: str | None = None,
    ) -> None: ...

    def unsubscribe(self, name: str) -> None: ...

    def get_property(self, element: str, attribute: str) -> object: ...

    def set_property(self, element: str, attribute: str, value: object) -> None: ...

    def invoke(self, name: str, operation: str, args: tuple[Any, ...] = ()) -> Any: ...


@dataclass(frozen=True, slots=True)
class Bound:
    """What a policy set's firing runs: its plan's engine and the engine's variables and
    operations (as the engine names them) bound to the container's elements."""

    plan: PolicyPlan
    engine: RuleEngine
    inputs: dict[str, Target]
    outputs: dict[str, Target]
    reads: dict[str, Target]
    operations: dict[str, Target]


def bind(name: str, container: PolicyHost, plan: PolicyPlan, call: Call) -> Bound:
    """The engine of policy set ``name``'s ``plan`` (its elements checked in ``container``: see
    :func:`check_elements`), and its variables and operations bound: what its firings run.
    ``call(operations, target, args)`` runs an operation its rules call."""
    constructor, _syntax, loads_plan = lookup_engine(plan.engine)
    # Built-in engines name variables and operations Element.member; another engine sees the
    # names as its rules write them (a variable written two ways is set under both).
    spelled: dict[str, tuple[str, ...]]
    if loads_plan:
        spelled = {v: (v,) for v in (*plan.inputs, *plan.outputs)}
        calls = {c: c for c in plan.operations}
    else:
        spelled = {}
        for written, canonical in plan.names.items():
            spelled.setdefault(canonical, ())
            spelled[canonical] += (written,)
        calls = dict(plan.calls)
    inputs = {n: split(v) for v in plan.inputs for n in spelled[v]}
    outputs = {spelled[v][0]: split(v) for v in plan.outputs}
    reads = {n: split(v) for v in plan.triggers for n in spelled[v]}
    operations = {n: split(c) for n, c in calls.items()}

    def run(target: str, args: tuple[Any, ...]) -> Any:
        return call(operations, target, args)

    setup = EngineSetup(
        policy_set=name,
        kind=plan.engine,
        semantics=plan.semantics,
        variables={
            n: Variable(var.terms.lo, var.terms.hi, var.terms.terms)
            for canonical, var in plan.variables.items()
            if var.terms is not None
            for n in spelled.get(canonical, (canonical,))
        },
        inputs=tuple(inputs),
        outputs=tuple(outputs),
        operations=tuple(operations),
        call=run,
        plan=plan,
    )
    engine = constructor(setup)
    if not loads_plan:
        for rule in plan.rules:
            engine.defrule(rule.text, rule.policy)
    return Bound(plan, engine, inputs, outputs, reads, operations)


def check_elements(name: str, container: PolicyHost, plan: PolicyPlan) -> None:
    """Every element a planned set reads or writes is the container's (or a replica there)."""
    elements = container.elements()
    for variable in (*plan.inputs, *plan.outputs):
        element, attribute = split(variable)
        if element not in elements or attribute not in elements[element]:
            raise BindingError(
                f"policy set {name!r} reads or writes {variable}, which is not an "
                "attribute of an element of the container",
                where=f"container {container.name!r}",
                hint="create the component / add the monitor before adding the policy set",
            )


def scope(name: str, container: PolicyHost, names: Iterable[str]) -> list[ScopeElement]:
    """The scope policy set ``name`` resolves its rules over: the elements ``names`` (those it
    adapts and the monitors feeding it) and their ports, or every element when none is named."""
    elements = container.elements()
    chosen: dict[str, dict[str, object]] = {}
    names = list(names)
    if not names:
        chosen = elements
    for element in names:
        if element not in elements:
            raise BindingError(
                f"policy set {name!r} refers to {element!r}, which is not an element of the container",
                where=f"container {container.name!r}",
                hint="create the component / add the monitor before adding the policy set",
            )
        chosen[element] = elements[element]
        prefix = element + "."
        chosen.update({k: v for k, v in elements.items() if k.startswith(prefix)})
    return [
        ScopeElement(
            element,
            props,
            dict.fromkeys(container.operations_of(element)),
            short=element.rpartition(".")[2] if "." in element else None,
        )
        for element, props in chosen.items()
    ]


def split(name: str) -> Target:
    """``Element.member`` as (element, member): the member is the part after the last dot (an
    element may be ``Component.Port``)."""
    element, _, member = name.rpartition(".")
    return element, member
