"""State-change events and the fault log of a container.

Every state change of a container is an :class:`Event`; policy sets, monitors and listeners subscribe to
kinds of events. An event remembers the event whose handling caused it (``cause``), so a cascade can be
bounded and, when cut, reported with the chain of elements that kept it going.
"""

from __future__ import annotations

import logging
from collections import Counter, deque
from dataclasses import dataclass, field

from acordcs.errors import AcordError

# The kinds of events a container emits.
COMPONENT_CREATED = "component.created"
COMPONENT_DESTROYED = "component.destroyed"
COMPONENT_REPLACED = "component.replaced"
PROPERTY_CHANGED = "property.changed"
OPERATION_CALLED = "operation.called"
MONITOR_UPDATED = "monitor.updated"
# A monitor's values went stale (value True; data: ``cause``, ``since``): its acquisition faulted
# (a polled operation that timed out), or no call came through an intercepting monitor's sources
# for its ``quiet_after`` seconds; and fresh again (value False; data: ``stale_for``, seconds) at
# its next reading. Its last values are kept meanwhile; policy sets do not fire on it.
MONITOR_STALE = "monitor.stale"
CONNECTION_CHANGED = "connection.changed"
FACTORY_CHANGED = "factory.changed"
POLICY_FIRED = "policy.fired"  # element: the policy set; its last_firing says what it did
# A change of the model applied to the running container (acordcs-gen update): element, the
# element changed; value, the plan line; data: the descriptor's digest before and after.
MODEL_UPDATED = "model.updated"
# A hold on a component's calls from other processes (the management interface's hold) started
# (value: its seconds left; data: the calls waiting, each call's patience) and ended (value:
# "released" or "expired"): told to the container's watchers by its management side
# (Observer.notice), not dispatched to the container's subscribers.
COMPONENT_HELD = "component.held"
COMPONENT_RELEASED = "component.released"

EVENT_KINDS = frozenset(
    {
        COMPONENT_CREATED,
        COMPONENT_DESTROYED,
        COMPONENT_REPLACED,
        PROPERTY_CHANGED,
        OPERATION_CALLED,
        MONITOR_UPDATED,
        MONITOR_STALE,
        CONNECTION_CHANGED,
        FACTORY_CHANGED,
        POLICY_FIRED,
        MODEL_UPDATED,
        COMPONENT_HELD,
        COMPONENT_RELEASED,
    }
)


@dataclass(slots=True)
class Event:
    """One state change. ``element`` is the element's name (``Camera``, ``Camera.frames``, a monitor).

    For ``property.changed``: ``attribute``, ``value`` and ``old``. For ``operation.called``:
    ``attribute`` is the operation, ``value`` the result, ``data`` holds ``args``/``kwargs``/``error``.
    """

    kind: str
    element: str
    attribute: str | None = None
    value: object = None
    old: object = None
    time: float = 0.0
    depth: int = 0
    cause: Event | None = field(default=None, repr=False)
    origin: str | None = None  # the policy set or monitor whose action emitted it, if any
    data: dict[str, object] = field(default_factory=dict, repr=False)

    def chain(self) -> list[str]:
        """The origins along the causal chain, oldest first (for cascade reports)."""
        out: list[str] = []
        node: Event | None = self
        while node is not None:
            label = f"{node.kind} {node.element}" + (f".{node.attribute}" if node.attribute else "")
            out.append(label + (f" (by {node.origin})" if node.origin else ""))
            node = node.cause
        return out[::-1]


@dataclass(slots=True)
class Fault:
    """An isolated failure: what raised, where, in which context, at what time."""

    kind: str  # action, monitor, interceptor, component, listener, timer, cascade, connector
    where: str
    error: str
    time: float
    context: dict[str, object] = field(default_factory=dict)


class FaultLog:
    """Counts every fault; keeps the last ones; logs the first of each (kind, where, error type) in full.

    A monitor raising at every tick must not flood the log, but must stay visible: later repeats go
    to DEBUG and the counters keep the totals.
    """

    def __init__(self, container: str, logger: logging.Logger, keep: int = 1000) -> None:
        self.container = container
        self.log = logger
        self.recent: deque[Fault] = deque(maxlen=keep)
        self.counts: Counter[str] = Counter()
        self._seen: set[tuple[str, str, str]] = set()

    def record(
        self,
        kind: str,
        where: str,
        exc: BaseException | str,
        time: float,
        **context: object,
    ) -> Fault:
        error = exc if isinstance(exc, str) else f"{type(exc).__name__}: {exc}"
        fault = Fault(kind, where, error, time, dict(context))
        self.recent.append(fault)
        self.counts[kind] += 1
        self.counts["total"] += 1
        key = (kind, where, error.split(":", 1)[0])
        ctx = ", ".join(f"{k}={v!r}" for k, v in context.items())
        msg = "container %r: %s %s failed at t=%.6f: %s%s; isolated, the container goes on"
        args = (self.container, kind, where, time, error, f" [{ctx}]" if ctx else "")
        if key in self._seen:
            self.log.debug(msg + " (repeat %d)", *args, self.counts[kind])
        else:
            self._seen.add(key)
            # The traceback of a bug in hosted code (its first time), not of one of acordcs's own
            # errors: those say what and where, and what to do, in their message.
            bug = isinstance(exc, BaseException) and not isinstance(exc, AcordError)
            self.log.error(msg, *args, exc_info=exc if bug else None)
        return fault

    def of_kind(self, kind: str) -> list[Fault]:
        return [f for f in self.recent if f.kind == kind]
