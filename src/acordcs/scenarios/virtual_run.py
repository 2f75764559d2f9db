"""A scenario run on the application the runtime assembles from the model's descriptor, in
virtual time, without generating or starting it.

:func:`~acordcs.runtime.assembly.assemble` builds the containers, components, monitors and policy
sets as a generated application's launcher does, on a
:class:`~acordcs.runtime.clock.VirtualClock`; the policy sets are the runtime's own
:class:`~acordcs.runtime.policy.PolicySet` (the same plans, engines, triggers and property
binding). What is the scenario's instead of the application's:

- components are the model's generic ones whose operations are recorded, not executed: a call
  returns the result the scenario gives for it, else None;
- monitors acquire nothing by themselves: a step's values are published through them
  (``Monitor.update``), as their acquisition would, and fire the sets they feed; a monitor that
  subscribes with XPath is the runtime's own, and takes the context documents a step publishes
  (the application's one context provider, embedded, inline);
- only the policy sets the scenario names are assembled.

Each policy set's firings are kept as the runtime reports them (``PolicySet.last_firing``: time,
inputs, outputs, each rule's degree), with a snapshot of the attributes the scenario watches.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from acordcs.runtime import events as ev
from acordcs.runtime.acquisition import MONITOR_KINDS
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory
from acordcs.runtime.errors import ComponentNotFoundError
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.operations import generic_component

if TYPE_CHECKING:
    from acordcs.descriptor.application import Application, Component
    from acordcs.runtime.container import Container
    from acordcs.runtime.events import Event, Fault
    from acordcs.runtime.policy import Firing


@dataclass(frozen=True, slots=True)
class Call:
    """An operation a policy called: when, ``Component.operation``, its arguments, by which set."""

    time: float
    operation: str
    args: tuple[Any, ...]
    by: str | None


@dataclass(frozen=True, slots=True)
class Sample:
    """The watched attributes' values at ``time``, after a step (``fired`` None) or after the
    firing of the policy set ``fired``."""

    time: float
    values: dict[str, object]
    fired: str | None = None


@dataclass
class Run:
    """What a scenario's run saw: firings per set, calls, samples, faults."""

    firings: list[tuple[str, Firing]] = field(default_factory=list)  # (policy set, firing)
    calls: list[Call] = field(default_factory=list)
    samples: list[Sample] = field(default_factory=list)
    faults: list[Fault] = field(default_factory=list)


def _quiet_runtime_log() -> None:
    # Faults are the run's findings, reported by the command; the runtime's log stays out of it.
    logger = logging.getLogger("acordcs.runtime")
    if not any(isinstance(h, logging.NullHandler) for h in logger.handlers):
        logger.addHandler(logging.NullHandler())
        logger.propagate = False


def _inert(name: str, *, attributes: dict[str, object] | None = None, **_how: object) -> Monitor:
    """A monitor that acquires nothing: the scenario's steps publish through it."""
    return Monitor(name, attributes=attributes)


def _subscribing(
    name: str, *, xpath: str, attributes: dict[str, object] | None = None, **_how: object
) -> Monitor:
    """A subscribing monitor as the runtime's, reading the documents the steps publish."""
    return MONITOR_KINDS["subscribe"](name, xpath=xpath, attributes=attributes)


class VirtualApplication:
    """The model's application assembled in virtual time for one scenario (see the module's
    docstring): ``policy_sets`` kept, ``results`` returned by the operations (``Component.op``),
    ``watched`` the attributes sampled."""

    def __init__(
        self,
        app: Application,
        *,
        policy_sets: Iterable[str],
        results: dict[str, object],
        watched: Iterable[str],
    ) -> None:
        _quiet_runtime_log()
        self.run = Run()
        self.clock = VirtualClock()
        # Factories, not classes: they stand in for every component, a Java one too.
        factories = {
            c.name: ComponentFactory(c.name, self._recording(c, results)) for c in app.components
        }
        keep = set(policy_sets)
        # Only the sets kept are assembled: an engine not run is not built.
        only = dataclasses.replace(
            app, policy_sets=tuple(ps for ps in app.policy_sets if ps.name in keep)
        )
        self.application = assemble(
            only,
            factories=factories,
            monitors={
                m.name: _subscribing if m.acquisition == "subscribe" else _inert
                for m in app.monitors
            },
            clock=self.clock,
        )
        self.home: dict[str, Container] = {}
        for container in self.application.containers.values():
            for ref in container.components():
                self.home.setdefault(ref.name, container)
            for monitor in container.monitors():
                self.home.setdefault(monitor, container)
            for ps in only.policy_sets:
                try:
                    hosted = container.policy_set(ps.name)
                except ComponentNotFoundError:
                    continue  # another container's
                hosted.trace_rules = True  # crisp sets: which rules fired, per firing
            container.subscribe(ev.POLICY_FIRED, self._fired(container), name="scenario:firings")
        self.monitors = {m for c in self.application.containers.values() for m in c.monitors()}
        self.watched = [(n, self._reader(n)) for n in watched]
        # Element.attribute -> its container, element, attribute and monitor (None: a property)
        self._targets: dict[str, tuple[Container, str, str, Monitor | None]] = {}

    def _recording(self, comp: Component, results: dict[str, object]) -> type:
        base = generic_component(comp)
        calls = self.run.calls
        namespace: dict[str, Callable[..., Any]] = {}
        for op in {o.name for o in comp.operations}:
            target = f"{comp.name}.{op}"

            def record(self: Any, *args: Any, _target: str = target, **kwargs: Any) -> Any:
                container = self.container
                calls.append(
                    Call(
                        container.clock.now(), _target, (*args, *kwargs.values()), container.origin
                    )
                )
                return results.get(_target)

            namespace[op] = record
        return type(comp.name, (base,), namespace)

    def _fired(self, container: Container) -> Callable[[Event], None]:
        def handler(event: Event) -> None:
            firing = container.policy_set(event.element).last_firing
            if firing is not None:
                self.run.firings.append((event.element, firing))
                self.sample(event.element)

        return handler

    def _split(self, name: str) -> tuple[Container, str, str]:
        element, _, attribute = name.rpartition(".")
        owner = element.split(".", 1)[0]
        return self.home[owner], element, attribute

    def _reader(self, name: str) -> Callable[[], object]:
        """What reads ``name``'s value now: a monitor's attribute, or a property."""
        container, element, attribute = self._split(name)
        if element in self.monitors:
            attributes = container.monitor(element).attributes
            return lambda: attributes.get(attribute)
        return lambda: container.get_property(element, attribute)

    def sample(self, fired: str | None = None) -> None:
        """Record the watched attributes' values now (after policy set ``fired``'s firing)."""
        self.run.samples.append(
            Sample(self.clock.now(), {name: read() for name, read in self.watched}, fired)
        )

    def advance(self, time: float) -> None:
        """Run the clock to ``time`` (periodic sets fire on the way)."""
        self.clock.run_until(time)

    def apply(self, values: Iterable[tuple[str, object]]) -> None:
        """Give the values of one step: a monitor's in one update, a property each on its own."""
        by_monitor: dict[Monitor, dict[str, object]] = {}
        for name, value in values:
            target = self._targets.get(name)
            if target is None:
                container, element, attribute = self._split(name)
                monitor = container.monitor(element) if element in self.monitors else None
                target = self._targets[name] = (container, element, attribute, monitor)
            container, element, attribute, monitor = target
            if monitor is not None:
                by_monitor.setdefault(monitor, {})[attribute] = value
            else:
                container.set_property(element, attribute, value)
        for monitor, given in by_monitor.items():
            monitor.update(**given)

    def publish(self, publisher: str, document: str) -> None:
        """Publish a context document (the subscribing monitors whose XPath it matches take it).
        Raises the provider's PublishError for a document it refuses."""
        next(iter(self.application.containers.values())).publish_context(publisher, document)

    def close(self) -> list[Fault]:
        """End the run; the faults its containers recorded."""
        for container in self.application.containers.values():
            self.run.faults += list(container.faults.recent)
        self.application.close()
        return self.run.faults
