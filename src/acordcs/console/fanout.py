"""A console's hub: what the console shows, fanned out to every viewer, never waiting for one.

The publisher (any thread: the WebLab's experiment, the watches of an attached application) calls
:meth:`ConsoleHub.publish` with a channel and a payload. Each viewer has a :class:`Mailbox` that
keeps, per *latest* channel (camera frames, the context values, each policy set's last firing),
only the newest payload, and for the *event* channel (faults, updates, recoveries...) a bounded
queue that drops its oldest entry when full. So a viewer that is slow or gone costs the publisher
one dictionary store per publish, memory per viewer is bounded whatever the rates, and a slow
viewer sees the newest frame, not a backlog. Drops are counted per viewer.
"""

from __future__ import annotations

import threading
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

EVENT = "event"
"""The one queued channel; every other channel keeps only its newest payload."""

EVENTS_KEPT = 256
"""Events a viewer may lag behind before the oldest are dropped."""


@dataclass
class Mailbox:
    """One viewer's pending output; ``wake`` is called (from the publishing thread) when something
    new is pending, to wake the viewer's sender."""

    wake: Callable[[], None]
    holder: bool = False  # the viewer presented the session's token when it connected
    latest: dict[str, Any] = field(default_factory=dict)
    events: deque[Any] = field(default_factory=lambda: deque(maxlen=EVENTS_KEPT))
    replaced: int = 0  # latest payloads overwritten before they were sent
    dropped: int = 0  # events dropped, the queue being full

    def take(self) -> tuple[dict[str, Any], list[Any]]:
        """Everything pending, emptied (called by the viewer's sender under the hub's lock)."""
        latest, self.latest = self.latest, {}
        events = list(self.events)
        self.events.clear()
        return latest, events


class ConsoleHub:
    """Fan-out of what the console shows to viewers, with two caps on their number: viewers who
    presented the session's token (``max_viewers``) and viewers without it (``max_watchers``), so
    that connections without the token, however many, never take a token holder's place."""

    def __init__(self, max_viewers: int = 32, max_watchers: int = 8) -> None:
        self.max_viewers = max_viewers
        self.max_watchers = max_watchers
        self._lock = threading.Lock()
        self._viewers: dict[int, Mailbox] = {}
        self._ids = 0
        # The newest payload of each latest channel: a viewer joining now sees the current state.
        self._current: dict[str, Any] = {}
        self._recent_events: deque[Any] = deque(maxlen=64)
        self.published = 0

    # --------------------------------------------------------------------- the publisher's side
    def publish(self, channel: str, payload: Any) -> None:
        """Offer ``payload`` on ``channel`` to every viewer; never blocks on a viewer."""
        with self._lock:
            self.published += 1
            if channel == EVENT:
                self._recent_events.append(payload)
            else:
                self._current[channel] = payload
            boxes = []
            for box in self._viewers.values():
                if not box.latest and not box.events:
                    # Only a mailbox that was empty needs waking: one that holds something has a
                    # wake pending, and its sender takes everything at once (a wake per publish
                    # was a cross-thread call per viewer per payload, which slowed the publisher).
                    boxes.append(box)
                if channel == EVENT:
                    if len(box.events) == box.events.maxlen:
                        box.dropped += 1
                    box.events.append(payload)
                else:
                    if channel in box.latest:
                        box.replaced += 1
                    box.latest[channel] = payload
        for box in boxes:
            box.wake()

    # ---------------------------------------------------------------------- the viewers' side
    def join(self, wake: Callable[[], None], *, holder: bool = False) -> tuple[int, Mailbox] | None:
        """A new viewer's id and mailbox, primed with the current state; None when the viewers
        of its kind (``holder``: with the session's token) are at their cap."""
        with self._lock:
            same = sum(1 for b in self._viewers.values() if b.holder == holder)
            if same >= (self.max_viewers if holder else self.max_watchers):
                return None
            self._ids += 1
            box = Mailbox(wake, holder)
            box.latest.update(self._current)
            box.events.extend(self._recent_events)
            self._viewers[self._ids] = box
            return self._ids, box

    def leave(self, viewer: int) -> None:
        with self._lock:
            self._viewers.pop(viewer, None)

    def take(self, box: Mailbox) -> tuple[dict[str, Any], list[Any]]:
        with self._lock:
            return box.take()

    @property
    def viewers(self) -> int:
        with self._lock:
            return len(self._viewers)

    def stats(self) -> dict[str, int]:
        """Viewers, payloads published, and what slow viewers missed (for the console's footer)."""
        with self._lock:
            return {
                "viewers": len(self._viewers),
                "watchers": sum(1 for b in self._viewers.values() if not b.holder),
                "published": self.published,
                "replaced": sum(b.replaced for b in self._viewers.values()),
                "dropped": sum(b.dropped for b in self._viewers.values()),
            }
