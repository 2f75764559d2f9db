"""A running container's observer interface: its context and policy firings for watchers in other
processes (a console), delivered so that a slow or gone watcher never slows the container.

:class:`Observer` listens to the container's events while someone watches and keeps the last
:data:`EVENTS_KEPT` in a ring, each numbered. A watcher calls :meth:`Observer.watch` and gets a
snapshot of the container (every element's properties, each policy set's last firing, the clock)
and the number of the last event; then it asks for what followed with :meth:`Observer.poll`, which
waits at most :data:`MAX_WAIT` seconds for something new. The container's side of an event is one
append to the ring, under a lock that a watcher holds only while it copies at most
:data:`MAX_BATCH` references: the container never waits for a watcher and never keeps more than
the ring. A watcher that fell more than the ring behind is told how many events it missed
(``dropped``) and should take a new :meth:`~Observer.snapshot`. A watch not polled for
:data:`IDLE_SECONDS` expires; when none is left the observer unsubscribes, so a container that
nobody watches pays nothing.

What a watcher sees: each event's kind, element, attribute, value, old value, time and origin (the
policy set or monitor acting), and

- ``policy.fired``: the set's firing (its time, how often the set has fired, its engine, the
  inputs it read and the outputs it wrote, and each rule's degree: computed for a fuzzy set when
  the watcher polls; read back from CLIPS while a watch asked for ``rules``, which turns the
  crisp sets' ``trace_rules`` on);
- ``monitor.updated``: the values the monitor took;
- ``monitor.stale``: a monitor's values went stale (``value`` True, ``data``: ``cause``,
  ``since``) or fresh again (False, ``data``: ``stale_for``);
- ``model.updated``: the plan line and the descriptor's digests before and after;
- ``operation.called``: only for the operations a watch names (``Component.operation``): the
  arguments, the result and the error. A call's arguments and result are exposed as they are: a
  camera frame, or a password passed to an operation, so name only the operations you need;
- the faults the container records (kind, where, error, time), with each poll.

:class:`ObserverEndpoint` serves it over Pyro5 as the object ``acordcs.observe.<container>`` of the
container's daemon, beside its endpoint and its management interface: the same token admits
callers, serpent only, and only ``watch``, ``poll``, ``unwatch`` and ``snapshot`` are exposed.
"""

from __future__ import annotations

import itertools
import threading
import time
from collections import deque
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, TypeVar

from acordcs.runtime import events as ev
from acordcs.runtime.connectors.pyrogate import serpent_only
from acordcs.runtime.connectors.remote import RemoteFault
from acordcs.runtime.errors import ConfigurationError, RuntimeFailure
from acordcs.vocabularies import FUZZY_ENGINE

if TYPE_CHECKING:
    from acordcs.runtime.container import Container
    from acordcs.runtime.events import Event
    from acordcs.runtime.policy import Firing

T = TypeVar("T")

OBSERVE_OBJECT = "acordcs.observe.{}"
"""The Pyro5 object name of a container's observer interface."""

EVENTS_KEPT = 1024
"""Events the ring keeps: a watcher polling less often than that many events misses the oldest."""

MAX_BATCH = 256
"""Events one poll returns at most (the next poll takes the rest)."""

MAX_WAIT = 2.0
"""Seconds a poll waits at most for a new event."""

MAX_WATCHES = 8
"""Watches at once; one more is refused until one is unwatched or expires."""

IDLE_SECONDS = 30.0
"""Seconds (wall) a watch lives without a poll."""

MAX_CALLS = 32
"""Operations one watch may name."""

MAX_BYTES = 1 << 20
"""Bytes of one value (an operation's argument or result) shown as they are; a longer one is
shown by its size only."""

WATCHED = (
    ev.POLICY_FIRED,
    ev.MONITOR_UPDATED,
    ev.MONITOR_STALE,
    ev.PROPERTY_CHANGED,
    ev.MODEL_UPDATED,
)
"""The kinds of events every watch sees (``operation.called`` only for the operations named)."""


@dataclass(slots=True)
class _Record:
    """One event as the ring keeps it: what the container's thread captured, made plain only when
    a watcher polls (off the container's thread)."""

    seq: int
    event: Event
    extra: Any = None  # policy.fired: (firing, fires, engine); others: None


@dataclass
class _Watch:
    calls: frozenset[str]
    rules: bool
    polled: float
    faults_seen: int
    busy: int = 0  # polls of it running now (an expiry waits for none)


@dataclass
class _Subscription:
    calls: frozenset[str] = frozenset()
    traced: set[str] = field(default_factory=set)  # sets whose trace_rules it turned on


class Observer:
    """The observer of container ``container`` (see the module docstring). ``policy_sets``: the
    names of the policy sets it hosts now (a watch asking for ``rules`` traces the crisp ones)."""

    def __init__(
        self,
        container: Container,
        policy_sets: Callable[[], Iterable[str]] = tuple,
        *,
        keep: int = EVENTS_KEPT,
        max_watches: int = MAX_WATCHES,
        idle: float = IDLE_SECONDS,
    ) -> None:
        if keep < 1 or max_watches < 1 or not idle > 0:
            raise ConfigurationError("keep and max_watches must be >= 1 and idle > 0 seconds")
        self.container = container
        self.policy_sets = policy_sets
        self.max_watches = max_watches
        self.idle = idle
        self._cond = threading.Condition(threading.Lock())
        self._ring: deque[_Record] = deque(maxlen=keep)
        self._seq = 0
        self._waiting = 0
        self._watches: dict[int, _Watch] = {}
        self._ids = itertools.count(1)
        self._label = f"observer:{container.name}"
        self._subscribed: _Subscription | None = None
        self._setup = threading.Lock()  # (un)subscribing, from the watchers' threads
        self._checked = time.monotonic()
        self._check_every = min(1.0, idle / 2)  # seconds between looks for expired watches

    # --------------------------------------------------------------------- the container's side
    def _record(self, event: Event) -> None:
        extra = None
        if event.kind == ev.POLICY_FIRED:
            try:
                found = self.container.policy_set(event.element)
                extra = (found.last_firing, found.fires, found.engine_kind)
            except RuntimeFailure:  # removed meanwhile (an update): the event alone
                pass
        with self._cond:
            self._seq += 1
            self._ring.append(_Record(self._seq, event, extra))
            if self._waiting:
                self._cond.notify_all()
            due = self._seq % 64 == 0
        if due:
            # In the container's thread, which holds its dispatcher: never wait for a watcher's
            # thread that may be (un)subscribing, hence waiting for that dispatcher.
            self._expire_idle(wait=False)

    def notice(self, kind: str, element: str, value: object, data: dict[str, object]) -> None:
        """An event of the container's management side (a hold starting or ending: nothing the
        container's dispatcher carries) for every watch, at once: from the management's thread,
        never waiting for the container's chain of events."""
        event = ev.Event(
            kind, element, None, value=value, time=self.container.clock.now(), data=data
        )
        self._record(event)

    # ------------------------------------------------------------------------------- calls
    def watch(self, calls: Iterable[str] = (), rules: bool = False) -> dict[str, Any]:
        """Start a watch: ``calls``, the operations (``Component.operation``) whose calls it sees;
        ``rules``: read the crisp sets' rule degrees. Returns its id (``watch``), the number of the
        last event so far (``after``: poll from it) and the container's :meth:`snapshot`."""
        wanted = frozenset(calls)
        if len(wanted) > MAX_CALLS:
            raise ConfigurationError(f"a watch names at most {MAX_CALLS} operations")
        for name in wanted:
            component, dot, operation = name.partition(".")
            if not dot or not component or not operation or "." in operation:
                raise ConfigurationError(
                    f"{name!r:.80} does not name an operation as Component.operation"
                )
        self._expire_idle()
        with self._cond:
            if len(self._watches) >= self.max_watches:
                raise ConfigurationError(
                    f"container {self.container.name!r} has its maximum of {self.max_watches} "
                    "watches",
                    hint=f"unwatch one, or wait: a watch not polled for {self.idle:g} s expires",
                )
            key = next(self._ids)
            faults = self.container.faults.counts["total"]
            self._watches[key] = _Watch(wanted, bool(rules), time.monotonic(), faults)
        self._resubscribe()
        with self._cond:
            after = self._seq
        return {"watch": key, "after": after, "snapshot": self.snapshot()}

    def poll(self, watch: int, after: int, wait: float = 0.0) -> dict[str, Any]:
        """What happened since event ``after`` (waiting up to ``wait`` seconds, at most
        :data:`MAX_WAIT`, for something new): ``events`` (at most :data:`MAX_BATCH`), ``after``
        (the number to poll from next), ``dropped`` (events missed: take a new snapshot),
        ``more`` (whether events are left), ``faults`` (recorded since the last poll), ``time``
        (the container's clock)."""
        deadline = time.monotonic() + min(max(float(wait), 0.0), MAX_WAIT)
        with self._cond:
            after = min(int(after), self._seq)  # a cursor from the future: from now
            mine = self._watches.get(watch)
            if mine is None:
                raise ConfigurationError(
                    f"no watch {watch} on container {self.container.name!r} (it expired after "
                    f"{self.idle:g} s without a poll, or was never made)",
                    hint="watch again: a new watch comes with a snapshot",
                )
            mine.busy += 1
            try:
                while self._seq <= after and (left := deadline - time.monotonic()) > 0:
                    self._waiting += 1
                    try:
                        self._cond.wait(left)
                    finally:
                        self._waiting -= 1
                first = self._ring[0].seq if self._ring else self._seq + 1
                start = max(after + 1, first)
                taken = list(itertools.islice(self._ring, start - first, start - first + MAX_BATCH))
                last = taken[-1].seq if taken else after
                more = last < self._seq
            finally:
                mine.busy -= 1
                mine.polled = time.monotonic()
        faults = self._new_faults(mine)
        events = [
            self._plain(r)
            for r in taken
            if r.event.kind != ev.OPERATION_CALLED
            or f"{r.event.element}.{r.event.attribute}" in mine.calls
        ]
        return {
            "events": events,
            "after": last,
            "dropped": max(0, first - after - 1),
            "more": more,
            "faults": faults,
            "time": self.container.clock.now(),
        }

    def unwatch(self, watch: int) -> bool:
        """End a watch; False when there was none of that number."""
        with self._cond:
            found = self._watches.pop(watch, None)
        self._resubscribe()
        return found is not None

    def snapshot(self) -> dict[str, Any]:
        """The container now: its name, clock ``time`` and ``seed``, every element's properties
        (``elements``: components, ``Component.Port``, connections, monitors, the container),
        each policy set's last firing (``policy_sets``: None before its first) and the faults it
        recorded (``faults``: how many)."""
        container = self.container
        elements: dict[str, dict[str, Any]] = {}
        for name, props in _settled(container.elements, {}).items():
            copied = _settled(lambda p=props: dict(p), {})
            elements[name] = {str(k): plain(v) for k, v in copied.items()}
        sets: dict[str, Any] = {}
        for name in self.policy_sets():
            try:
                found = container.policy_set(name)
            except RuntimeFailure:
                continue
            firing = found.last_firing
            sets[name] = (
                None if firing is None else _firing(name, firing, found.fires, found.engine_kind)
            )
        return {
            "container": container.name,
            "time": container.clock.now(),
            "seed": container.clock.seed,
            "elements": elements,
            "policy_sets": sets,
            "faults": container.faults.counts["total"],
        }

    @property
    def watches(self) -> int:
        """The watches now."""
        with self._cond:
            return len(self._watches)

    @property
    def waiting(self) -> int:
        """The polls waiting for an event now."""
        with self._cond:
            return self._waiting

    def close(self) -> None:
        with self._cond:
            self._watches.clear()
            self._cond.notify_all()
        self._resubscribe()

    # ----------------------------------------------------------------------------- internals
    def _expire_idle(self, *, wait: bool = True) -> None:
        now = time.monotonic()
        if now - self._checked < self._check_every:
            return
        self._checked = now
        with self._cond:
            gone = [
                k for k, w in self._watches.items() if not w.busy and now - w.polled > self.idle
            ]
            for key in gone:
                del self._watches[key]
        if gone:
            self._resubscribe(wait=wait)

    def _resubscribe(self, *, wait: bool = True) -> None:
        """Subscribe to what the watches need now (nothing when there are none); ``wait=False``:
        unless another thread is at it (then the next check does it)."""
        if not self._setup.acquire(blocking=wait):
            self._checked = 0.0  # try again at the next check
            return
        try:
            with self._cond:
                watches = list(self._watches.values())
            calls = frozenset().union(*(w.calls for w in watches)) if watches else frozenset()
            rules = any(w.rules for w in watches)
            container, current = self.container, self._subscribed
            if current is not None and (not watches or current.calls != calls):
                container.unsubscribe(self._label)
            if not watches:
                if current is not None:
                    self._trace(current.traced, on=False)
                self._subscribed = None
                return
            if current is None or current.calls != calls:
                for kind in WATCHED:
                    container.subscribe(kind, self._record, name=self._label)
                for name in sorted(calls):
                    component, _, operation = name.partition(".")
                    container.subscribe(
                        ev.OPERATION_CALLED,
                        self._record,
                        name=self._label,
                        element=component,
                        attribute=operation,
                    )
            traced = current.traced if current is not None else set()
            if rules:
                traced |= self._trace(set(self.policy_sets()) - traced, on=True)
            elif traced:
                self._trace(traced, on=False)
                traced = set()
            self._subscribed = _Subscription(calls, traced)
        finally:
            self._setup.release()

    def _trace(self, names: set[str], *, on: bool) -> set[str]:
        """Turn ``trace_rules`` on (the crisp sets among ``names`` that had it off: returned) or
        off again."""
        changed = set()
        for name in names:
            try:
                found = self.container.policy_set(name)
            except RuntimeFailure:
                continue
            if on and found.engine_kind != FUZZY_ENGINE and not found.trace_rules:
                found.trace_rules = True
                changed.add(name)
            elif not on:
                found.trace_rules = False
        return changed

    def _new_faults(self, watch: _Watch) -> list[dict[str, Any]]:
        log = self.container.faults
        total = log.counts["total"]
        new = min(total - watch.faults_seen, len(log.recent), MAX_BATCH)
        watch.faults_seen = total
        recent = _settled(lambda: list(log.recent), [])[-new:] if new > 0 else []
        return [
            {"kind": f.kind, "where": f.where, "error": f.error[:500], "time": f.time}
            for f in recent
        ]

    def _plain(self, record: _Record) -> dict[str, Any]:
        event = record.event
        out: dict[str, Any] = {
            "seq": record.seq,
            "kind": event.kind,
            "element": event.element,
            "attribute": event.attribute,
            "time": event.time,
            "origin": event.origin,
        }
        if event.kind == ev.POLICY_FIRED and record.extra is not None:
            firing, fires, engine = record.extra
            if firing is not None:
                out["firing"] = _firing(event.element, firing, fires, engine)
        elif event.kind == ev.OPERATION_CALLED:
            error = event.data.get("error")
            out.update(
                value=plain(event.value),
                args=[plain(a) for a in event.data.get("args", ())],
                error=None if error is None else f"{type(error).__name__}: {error}"[:500],
            )
        elif event.kind == ev.MONITOR_UPDATED:
            out["values"] = {str(k): plain(v) for k, v in event.data.items()}
        else:
            out.update(value=plain(event.value), old=plain(event.old))
            if event.data:
                out["data"] = {str(k): plain(v) for k, v in event.data.items()}
        return out


def _firing(name: str, firing: Firing, fires: int, engine: str) -> dict[str, Any]:
    try:
        degrees = firing.rules
    except Exception:  # an engine that cannot explain these inputs: no degrees, not a failure
        degrees = {}
    return {
        "set": name,
        "engine": engine,
        "time": firing.time,
        "fires": fires,
        "inputs": {str(k): plain(v) for k, v in firing.inputs.items()},
        "outputs": {str(k): plain(v) for k, v in firing.outputs.items()},
        "rules": [[policy, label, float(degree)] for (policy, label), degree in degrees.items()],
    }


def _settled(read: Callable[[], T], empty: T) -> T:
    """``read()``, again if another thread (the container's) changed what it copies meanwhile
    (a dict or deque changing size while copied); ``empty`` if it never settles."""
    for _ in range(5):
        try:
            return read()
        except RuntimeError:
            continue
    return empty


def plain(value: object, depth: int = 0) -> Any:
    """``value`` as serpent carries it: numbers, text, booleans, None and bytes as they are (bytes
    over :data:`MAX_BYTES` by their size), lists and string-keyed dicts of those (4 levels at most,
    1000 items each), anything else shown (``repr``, 200 characters)."""
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, bytes | bytearray | memoryview):
        data = bytes(value)
        return data if len(data) <= MAX_BYTES else f"<{len(data)} bytes>"
    if depth < 4 and isinstance(value, list | tuple):
        return [plain(v, depth + 1) for v in itertools.islice(value, 1000)]
    if depth < 4 and isinstance(value, Mapping):
        return {str(k): plain(v, depth + 1) for k, v in itertools.islice(value.items(), 1000)}
    return repr(value)[:200]


class ObserverEndpoint:
    """:class:`Observer` over Pyro5 (see the module docstring); failures come back as
    :class:`~.connectors.remote.RemoteFault`."""

    def __init__(self, observer: Observer) -> None:
        self._observer = observer

    @serpent_only
    def watch(self, calls: list[str], rules: bool) -> dict[str, Any]:
        if not isinstance(calls, list | tuple) or not all(
            isinstance(c, str) and len(c) <= 200 for c in calls
        ):
            raise RemoteFault("TypeError", "calls is a list of Component.operation names", None)
        return self._guarded(lambda: self._observer.watch(list(calls), bool(rules)))

    @serpent_only
    def poll(self, watch: int, after: int, wait: float) -> dict[str, Any]:
        numbers = (watch, after, wait)
        if any(isinstance(n, bool) for n in numbers) or not (
            isinstance(watch, int) and isinstance(after, int) and isinstance(wait, int | float)
        ):
            raise RemoteFault("TypeError", "watch and after are integers, wait a number", None)
        return self._guarded(lambda: self._observer.poll(watch, after, float(wait)))

    @serpent_only
    def unwatch(self, watch: int) -> bool:
        if isinstance(watch, bool) or not isinstance(watch, int):
            raise RemoteFault("TypeError", "watch is an integer", None)
        return self._guarded(lambda: self._observer.unwatch(watch))

    @serpent_only
    def snapshot(self) -> dict[str, Any]:
        return self._guarded(self._observer.snapshot)

    @staticmethod
    def _guarded(call: Callable[[], Any]) -> Any:
        try:
            return call()
        except Exception as exc:  # including faults of our own: the worker must survive
            hint = exc.hint if isinstance(exc, RuntimeFailure) else None
            raise RemoteFault(type(exc).__name__, str(exc), hint) from None
