"""Event dispatch with a cascade bound: a container's :class:`EventDispatcher`.

Events are queued and handled breadth-first by the thread that emitted the first one; events emitted
while handling (a policy action changing a property, which triggers a policy...) are caused by the
event being handled and one level deeper. A cascade deeper than ``max_depth`` or longer than
``max_events`` is cut: the rest is dropped, and the cut is reported once (a fault of kind
``cascade`` naming the causal chain) and counted in ``stats["cascades_cut"]``.
"""

from __future__ import annotations

import threading
from collections import Counter, deque
from collections.abc import Callable
from typing import TYPE_CHECKING

from acordcs.runtime.errors import ConfigurationError
from acordcs.runtime.events import Event

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock
    from acordcs.runtime.events import FaultLog

Handler = Callable[[Event], None]
Key = tuple[str, str | None, str | None]


class EventDispatcher:
    """The event queue of one container: counts into its ``stats``, reports faults to its ``faults``."""

    def __init__(
        self,
        stats: Counter[str],
        faults: FaultLog,
        clock: Clock,
        *,
        max_depth: int,
        max_events: int,
    ) -> None:
        if max_depth < 1 or max_events < 1:
            raise ConfigurationError("cascade bounds max_depth and max_events must be >= 1")
        self.stats = stats
        self.faults = faults
        self.clock = clock
        self.max_depth = max_depth
        self.max_events = max_events
        self._subs: dict[Key, list[tuple[str, Handler]]] = {}
        # Kinds with listeners, replaced (not mutated) on change: read without the lock.
        self._kinds: frozenset[str] = frozenset()
        self._lock = threading.RLock()
        self._queue: deque[Event] = deque()
        self._current: Event | None = None
        self._drainer: int | None = None
        self.origin: str | None = None

    # ------------------------------------------------------------------------- subscriptions
    def subscribe(
        self,
        kind: str,
        handler: Handler,
        *,
        name: str,
        element: str | None = None,
        attribute: str | None = None,
    ) -> None:
        """``handler`` gets events of ``kind`` (``*``: all), optionally of one element / attribute."""
        with self._lock:
            self._subs.setdefault((kind, element, attribute), []).append((name, handler))
            self._kinds = frozenset(k[0] for k in self._subs)

    def unsubscribe(self, name: str) -> None:
        with self._lock:
            for key in list(self._subs):
                kept = [(n, h) for n, h in self._subs[key] if n != name]
                if kept:
                    self._subs[key] = kept
                else:
                    del self._subs[key]
            self._kinds = frozenset(k[0] for k in self._subs)

    def wants(self, kind: str) -> bool:
        """Whether anyone listens to ``kind`` (saves building events nobody reads)."""
        kinds = self._kinds
        return kind in kinds or "*" in kinds

    def _handlers(self, event: Event) -> list[tuple[str, Handler]]:
        subs = self._subs
        out: list[tuple[str, Handler]] = []
        keys: tuple[Key, ...] = (
            (event.kind, event.element, None),
            (event.kind, None, None),
            ("*", None, None),
        )
        if event.attribute is not None:
            keys = ((event.kind, event.element, event.attribute), *keys)
        for key in keys:
            found = subs.get(key)
            if found:
                out.extend(found)
        return out

    # ------------------------------------------------------------------------------ emitting
    def emit(self, event: Event) -> None:
        with self._lock:
            me = threading.get_ident()
            if self._drainer == me:
                cause = self._current
                if cause is not None:
                    event.cause = cause
                    event.depth = cause.depth + 1
                if event.origin is None:
                    event.origin = self.origin
                self._queue.append(event)
                return
            event.origin = event.origin or self.origin
            self._queue.append(event)
            self._drainer = me
            try:
                self._drain()
            finally:
                self._drainer = None
                self._current = None
                self._queue.clear()

    def _drain(self) -> None:
        stats, faults, clock = self.stats, self.faults, self.clock
        handled = 0
        cut_reported = False
        while self._queue:
            event = self._queue.popleft()
            if event.depth > self.max_depth or handled >= self.max_events:
                stats["events_dropped"] += 1
                if not cut_reported:
                    cut_reported = True
                    self._report_cut(event, handled)
                continue
            handled += 1
            stats["events"] += 1
            self._current = event
            for name, handler in self._handlers(event):
                try:
                    handler(event)
                except Exception as exc:
                    faults.record(
                        "listener",
                        name,
                        exc,
                        clock.now(),
                        event=f"{event.kind} {event.element}",
                    )

    def _report_cut(self, event: Event, handled: int) -> None:
        self.stats["cascades_cut"] += 1
        reason = (
            f"cascade deeper than {self.max_depth} events"
            if event.depth > self.max_depth
            else f"cascade longer than {self.max_events} events"
        )
        chain = event.chain()
        origins = sorted({e.split(" (by ", 1)[1][:-1] for e in chain if " (by " in e})
        self.faults.record(
            "cascade",
            ", ".join(origins) or event.element,
            f"{reason} cut (after {handled} handled); the rest of it was dropped",
            self.clock.now(),
            chain=chain[-6:],
            hint="a policy whose actions re-trigger it: check its rules",
        )
