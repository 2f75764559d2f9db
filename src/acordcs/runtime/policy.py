"""Policy sets (paper, CtxPolicySet): rules bound to a rule engine, variables bound to attributes.

A policy set holds policies (rule sets, one per :class:`CtxPolicy`), binds their rules to an engine by
the model's engine tag (see :mod:`acordcs.engines.engine_registry`) and drives it with the paper's four calls:
``defrule`` each rule once; on each firing ``set`` every input variable from its attribute, ``fire``
every rule set, then ``get`` every output variable and write it back through the container (so the
change is an event, seen by monitors and other policy sets). Operations called by crisp rules go
through the container too.

Firing: ``trigger="event"`` fires when an attribute it reads changes, when a monitor feeding it
updates, or when a component is created, destroyed or replaced; ``trigger="periodic"`` fires at
``frequency`` Hz of the container's clock. A change the set's own actions caused does not fire it
again: a counter it reads and writes (the paper's recovering policy counts its tries) is its state,
not news. Sets that trigger each other are cut by the container's cascade bound and reported.
A raising engine or action is a fault (kind ``action``):
recorded, and the policy set fires again at the next trigger.

Names: what the rules name is resolved once (:mod:`acordcs.rules.binding`). A set assembled from
the application descriptor takes that resolution from it (:meth:`PolicySet.from_plan`); a set
made by hand is resolved when it is attached, over its scope: the attributes of the elements it
``adapts`` (and of their ports) and of the monitors that feed it, or with neither ``adapts`` nor
``fed_by``, every element of the container.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from acordcs.engines.engine_registry import Variable, lookup_engine
from acordcs.engines.plan import PolicyPlan, Terms, plan_by_hand
from acordcs.engines.rule_engine import RuleEngine, RuleError
from acordcs.rules import split_rules
from acordcs.runtime import events as ev
from acordcs.runtime.errors import BindingError, ComponentNotFoundError, ConfigurationError
from acordcs.runtime.policy_binding import (
    Bound,
    PolicyHost,
    Target,
    bind,
    check_elements,
    scope,
    split,
)
from acordcs.vocabularies import FUZZY_ENGINE, TRIGGERS

if TYPE_CHECKING:
    from acordcs.runtime.clock import Timer
    from acordcs.runtime.events import Event

__all__ = ["Firing", "PolicyHost", "PolicySet"]


@dataclass
class Firing:
    """A policy set's firing: when, the inputs it was given and the outputs it wrote. :attr:`rules`
    gives per ``(policy, rule label)`` its degree: fuzzy, the rule's firing strength on these
    inputs (computed when first asked, off the hot path); crisp, 1.0 if the rule fired, 0.0 if not
    (read after each fire when the set's ``trace_rules`` is on, else empty); empty when the engine
    cannot explain itself."""

    time: float
    inputs: dict[str, object]
    outputs: dict[str, object]
    explain: Callable[[], dict[tuple[str, str], float]] | None = field(default=None, repr=False)
    _rules: dict[tuple[str, str], float] | None = field(default=None, repr=False)

    @property
    def rules(self) -> dict[tuple[str, str], float]:
        if self._rules is None:
            self._rules = self.explain() if self.explain is not None else {}
        return self._rules


_Key = tuple[str, str, str | None]  # an event a set subscribes to: kind, element, attribute


class PolicySet:
    """A policy set: its rules and engine, driven on its container's events or clock (see the
    module docstring). Built from a plan (:meth:`from_plan`: the application descriptor's
    resolution, as :func:`~acordcs.runtime.assembly.assemble` does) or by hand: ``policies`` maps
    each policy to its rules (a list of rule strings, or one text with a rule per line), resolved
    when the set is added to a container over the elements it ``adapts`` and the monitors it is
    ``fed_by`` (all of the container's elements when neither is given); ``variables`` gives the
    linguistic variables (by ``Element.attribute`` or as the rules write them) and ``bindings``
    binds written names by hand (written name -> ``Element.attribute``)."""

    def __init__(
        self,
        name: str,
        policies: Mapping[str, Sequence[str] | str] | None = None,
        *,
        engine: str = FUZZY_ENGINE,
        trigger: str = "event",
        frequency: float | None = None,
        semantics: str = "mamdani",
        adapts: Iterable[str] = (),
        fed_by: Iterable[str] = (),
        variables: Mapping[str, Variable] | None = None,
        bindings: Mapping[str, str] | None = None,
        plan: PolicyPlan | None = None,
    ) -> None:
        _check_trigger(name, trigger, frequency)
        self.name = name
        self.plan = plan
        if plan is not None:
            engine, semantics = plan.engine, plan.semantics
            self.policies: dict[str, list[Any]] = {p: plan.rules_of(p) for p in plan.policies}
        else:
            self.policies = {
                p: split_rules(rules)
                if isinstance(rules, str)
                else [_line(r, i) for i, r in enumerate(rules, 1)]
                for p, rules in (policies or {}).items()
            }
        self.engine_kind = engine
        self.trigger = trigger
        self.frequency = frequency
        self.semantics = semantics
        self.adapts = tuple(adapts)
        self.fed_by = tuple(fed_by)
        self.variables = dict(variables or {})
        self.bindings = dict(bindings or {})
        self.engine: RuleEngine | None = None
        self.container: PolicyHost | None = None
        # The engine's variable name -> (element, attribute), in the order it is given (inputs),
        # read back (outputs), subscribed (reads); an operation as the engine calls it -> target.
        self.inputs: dict[str, Target] = {}
        self.outputs: dict[str, Target] = {}
        self.operations: dict[str, Target] = {}
        self.reads: dict[str, Target] = {}
        self.fires = 0
        self._last: tuple[float, list, dict, dict | None] | None = None
        self._firing: Firing | None = None
        # Crisp engines: read which rules fired after each fire (one more engine call per
        # policy, so off unless someone shows it, as the WebLab console does).
        self.trace_rules = False
        self._timer: Timer | None = None
        # What a firing runs (replaced whole by replan) and what fires it: the events subscribed
        # under _label (a replan that changes them subscribes under a new one, _pending, first).
        self._bound: Bound | None = None
        self._subscribed: frozenset[_Key] = frozenset()
        self._label = self._pending = f"policy:{name}"
        self._generation = 0

    @classmethod
    def from_plan(
        cls,
        plan: PolicyPlan,
        *,
        trigger: str = "event",
        frequency: float | None = None,
        adapts: Iterable[str] = (),
        fed_by: Iterable[str] = (),
    ) -> PolicySet:
        """A policy set whose rules are resolved already (:mod:`acordcs.engines.plan`)."""
        return cls(
            plan.name, trigger=trigger, frequency=frequency, adapts=adapts, fed_by=fed_by, plan=plan
        )

    def __repr__(self) -> str:
        return f"<PolicySet {self.name} ({self.engine_kind}, {self.trigger}), fired {self.fires}x>"

    # ------------------------------------------------------------------------------ binding
    def attach(self, container: PolicyHost) -> None:
        """Bind to ``container``: resolve the rules (unless planned), build the engine, subscribe."""
        bound = self._bind(container, self.plan)
        self._install(bound)
        self.container = container
        self._subscribe(container, self._keys(container))

    def replan(
        self,
        plan: PolicyPlan,
        *,
        trigger: str,
        frequency: float | None,
        adapts: Iterable[str] = (),
        fed_by: Iterable[str] = (),
    ) -> Callable[[], None]:
        """Take ``plan`` (new rules, terms, variables, engine), ``trigger`` and ``frequency`` while
        attached: the new engine is built first, then replaces the old one between two firings (a
        firing under way ends with the old one; the next runs the new one). A crisp engine keeps
        the values of the variables both plans have. Subscriptions change only when what fires
        the set changes, and an event fires it once either way. Returns what undoes it (the old
        engine back, as it was). Raises as :meth:`attach` does (nothing changed then)."""
        container = self.container
        if container is None:
            raise BindingError(f"policy set {self.name!r} is not attached to a container")
        _check_trigger(self.name, trigger, frequency)
        saved = (self.plan, self.trigger, self.frequency, self.adapts, self.fed_by)
        saved_bound = self._bound
        assert saved_bound is not None
        bound = self._bind(container, plan)
        if plan.syntax == "crisp" and saved_bound.plan.syntax == "crisp":
            for name in set(plan.variables) & set(saved_bound.plan.variables):
                value = saved_bound.engine.get(name)
                if value is not None:
                    bound.engine.set(name, value)
        self.plan, self.trigger, self.frequency = plan, trigger, frequency
        self.adapts, self.fed_by = tuple(adapts), tuple(fed_by)
        self._swap(container, saved_bound, bound, saved[1:3])

        def undo() -> None:
            current = self._bound
            self.plan, self.trigger, self.frequency, self.adapts, self.fed_by = saved
            if self.container is not None and current is not None:
                self._swap(self.container, current, saved_bound, (trigger, frequency))

        return undo

    def _swap(
        self,
        container: PolicyHost,
        old: Bound,
        new: Bound,
        was: tuple[str, float | None],
    ) -> None:
        """Put ``new`` in place of ``old``, resubscribing only if what fires the set changed."""
        keys = self._keys(container, new)
        if keys == self._subscribed and (self.trigger, self.frequency) == was:
            self._install(new)
            return
        previous_label, previous_timer = self._label, self._timer
        self._timer = None
        self._subscribe(container, keys, fresh=True)  # guarded: they fire once the label is theirs
        self._install(new)
        self._label = self._pending
        if previous_timer is not None:
            previous_timer.cancel()
        container.unsubscribe(previous_label)

    def _install(self, bound: Bound) -> None:
        # One assignment is what a firing reads: it runs wholly on the old binding or the new.
        self._bound = bound
        self.plan = bound.plan
        self.engine_kind, self.semantics = bound.plan.engine, bound.plan.semantics
        self.policies = {p: bound.plan.rules_of(p) for p in bound.plan.policies}
        self.engine = bound.engine
        self.inputs, self.outputs = bound.inputs, bound.outputs
        self.reads, self.operations = bound.reads, bound.operations

    def _bind(self, container: PolicyHost, plan: PolicyPlan | None) -> Bound:
        """The engine and variable bindings of ``plan`` (resolved here when None) in ``container``."""
        if plan is None:
            _constructor, syntax, _loads = lookup_engine(self.engine_kind)
            plan = plan_by_hand(
                self.name,
                self.policies,
                engine=self.engine_kind,
                syntax=syntax,
                semantics=self.semantics,
                scope=scope(self.name, container, (*self.adapts, *self.fed_by)),
                where=f"container {container.name!r}",
                variables={k: Terms(v.lo, v.hi, v.terms) for k, v in self.variables.items()},
                bindings=self.bindings,
            )
        else:
            check_elements(self.name, container, plan)
        return bind(self.name, container, plan, self._call)

    def _keys(self, container: PolicyHost, bound: Bound | None = None) -> frozenset[_Key]:
        """The events that fire the set (none for a periodic one)."""
        if self.trigger == "periodic":
            return frozenset()
        reads = (bound or self._bound).reads  # type: ignore[union-attr]
        monitors = set(container.monitors())
        keys: set[_Key] = set()
        for element, attribute in reads.values():
            if element in monitors:
                keys.add((ev.MONITOR_UPDATED, element, None))
            else:
                keys.add((ev.PROPERTY_CHANGED, element, attribute))
        for monitor in self.fed_by:
            keys.add((ev.MONITOR_UPDATED, monitor, None))
        return frozenset(keys)

    def _subscribe(self, container: PolicyHost, keys: frozenset[_Key], fresh: bool = False) -> None:
        """Subscribe to ``keys`` (or start the periodic timer) under a label of its own; with
        ``fresh``, a new label that fires only once it is :attr:`_label` (see :meth:`_swap`)."""
        self._generation += 1 if fresh else 0
        label = f"policy:{self.name}" + (f"#{self._generation}" if self._generation else "")
        self._pending = label
        if not fresh:
            self._label = label
        self._subscribed = keys

        def handler(event: Event) -> None:
            if self._label == label:
                self._on_event(event)

        if self.trigger == "periodic":
            self._timer = container.clock.call_every(
                1.0 / float(self.frequency or 1.0), self._periodic
            )
            return
        for kind, element, attribute in sorted(keys, key=str):
            container.subscribe(kind, handler, name=label, element=element, attribute=attribute)
        for kind in (ev.COMPONENT_CREATED, ev.COMPONENT_DESTROYED, ev.COMPONENT_REPLACED):
            container.subscribe(kind, handler, name=label)

    def detach(self) -> None:
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        if self.container is not None:
            self.container.unsubscribe(self._label)
        self.container = None

    # ------------------------------------------------------------------------------- firing
    def _on_event(self, event: Event) -> None:
        if event.origin == self.name:
            return  # caused by this set's own actions (see the module docstring)
        self.fire(event)

    def _periodic(self) -> None:
        self.fire(None)

    def fire(self, event: Event | None = None) -> bool:
        """Run the four calls once; True if the rules ran (False: skipped or faulted)."""
        container, bound = self.container, self._bound
        if container is None or bound is None:
            return False
        engine, outputs = bound.engine, bound.outputs
        try:
            values = [(var, container.get_property(e, a)) for var, (e, a) in bound.inputs.items()]
        except (ComponentNotFoundError, BindingError):
            # An input's element is gone (destroyed): nothing sensible to evaluate.
            container.stats["policy_skipped"] += 1
            return False
        # Plain try/finally rather than context managers: this is the adaptation hot path.
        # A crisp set's records run assignments first, then the operations its rules call; an
        # operation may itself change an assigned property (Recovery.askUser resets the retries
        # the count rule raised): its write is the later one and must stand, so the write-back
        # below skips an output whose property changed during the firing.
        before = (
            [container.get_property(e, a) for e, a in outputs.values()]
            if bound.operations
            else None
        )
        previous, container.origin = container.origin, self.name
        try:
            for var, value in values:
                engine.set(var, value)
            fired: dict[tuple[str, str], float] | None = None
            for policy in bound.plan.policies:
                engine.fire(policy)
                if self.trace_rules and bound.plan.engine != FUZZY_ENGINE:
                    fired = fired if fired is not None else {}
                    fired.update(_explained(engine, policy))
            self.fires += 1
            container.stats["policy_fires"] += 1
            written: dict[str, object] = {}
            for i, (var, (element, attribute)) in enumerate(outputs.items()):
                value = engine.get(var)
                if value is not None:
                    current = container.get_property(element, attribute)
                    if before is not None and current != before[i]:
                        continue  # an operation called after the assignment wrote it last
                    written[var] = _coerce(value, current)
                    container.set_property(element, attribute, written[var])
            # Kept raw: the Firing is built when someone asks (this is the adaptation hot path).
            self._last = (container.clock.now(), values, written, fired)
            self._firing = None
            container.emit(ev.POLICY_FIRED, self.name)
            return True
        except Exception as exc:
            trigger = f"{event.kind} {event.element}" if event else "periodic"
            container.faults.record(
                "action", self.name, exc, container.clock.now(), trigger=trigger
            )
            return False
        finally:
            container.origin = previous

    @property
    def last_firing(self) -> Firing | None:
        """The set's last firing (None before the first): see :class:`Firing`."""
        if self._firing is None and self._last is not None:
            when, values, written, fired = self._last
            inputs = dict(values)
            engine = self.engine
            if self.engine_kind == FUZZY_ENGINE and engine is not None:
                explain = lambda: self._fuzzy_degrees(engine, inputs)  # noqa: E731
            else:
                explain = None if fired is None else (lambda: fired)
            self._firing = Firing(when, inputs, written, explain)
        return self._firing

    def _fuzzy_degrees(
        self, engine: RuleEngine, inputs: dict[str, object]
    ) -> dict[tuple[str, str], float]:
        out: dict[tuple[str, str], float] = {}
        for policy in self.policies:
            out.update(_explained(engine, policy, inputs))
        return out

    def _call(self, operations: dict[str, Target], target: str, args: tuple[Any, ...]) -> Any:
        container = self.container
        if container is None:
            raise BindingError(f"policy set {self.name!r} is not attached to a container")
        component, operation = operations.get(target) or split(target)
        return container.invoke(component, operation, tuple(args))


def _check_trigger(name: str, trigger: str, frequency: float | None) -> None:
    if trigger not in TRIGGERS:
        raise ConfigurationError(
            f"policy set {name!r}: trigger must be {' or '.join(map(repr, TRIGGERS))}, "
            f"not {trigger!r}"
        )
    if trigger == "periodic" and not (frequency and frequency > 0):
        raise ConfigurationError(f"policy set {name!r}: a periodic set needs a frequency > 0 Hz")


def _explained(engine: RuleEngine, policy: str, *args: object) -> dict[tuple[str, str], float]:
    """``engine.explain(policy, ...)`` keyed by (policy, label); {} for an engine without one."""
    explain = getattr(engine, "explain", None)
    if explain is None:
        return {}
    return {(policy, label): degree for label, degree in explain(policy, *args).items()}


def _coerce(value: object, current: object) -> object:
    """Engines answer floats; an int attribute (fps) stays an int."""
    if isinstance(current, bool) or not isinstance(value, float):
        return value
    if isinstance(current, int):
        return round(value)
    return value


def _line(text: str, number: int) -> Any:
    lines = split_rules(text)
    if len(lines) != 1:
        raise RuleError("a rule is one line; pass a list of rule strings", rule=f"line {number}")
    lines[0].line = number
    return lines[0]
