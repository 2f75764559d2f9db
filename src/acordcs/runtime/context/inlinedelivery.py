"""Delivery in the publishing thread, for virtual-time runs (``inline=True``): see
:class:`InlineDelivery`."""

from __future__ import annotations

import threading

from acordcs.runtime.context.delivery import Notification, Subscription, deliver


class InlineDelivery:
    """Delivers in the publishing thread instead of a pool: every notification, in the order
    matched, once the provider has released its lock (:meth:`flush`, called by ``publish``).

    For virtual-time runs: with delivery threads, when a monitor sees a document would depend on
    the thread scheduler, and a run would not repeat for its seed. A slow callback here slows its
    publisher (that is the price); a raising one is counted and logged as with threads.
    """

    threads = 0

    def __init__(self) -> None:
        self._pending = threading.local()  # per publishing thread: [(subscription, notification)]

    def offer(self, sub: Subscription, note: Notification, may_inline: bool = False) -> None:
        if sub.mailbox.closed:
            return
        queue = getattr(self._pending, "queue", None)
        if queue is None:
            queue = self._pending.queue = []
        queue.append((sub, note))

    def flush(self) -> None:
        """Run the callbacks of what this thread's publish matched (a callback that publishes
        flushes its own matches first: they are delivered in causal order)."""
        queue = getattr(self._pending, "queue", None)
        self._pending.queue = None
        for sub, note in queue or ():
            if not sub.mailbox.closed:
                deliver(sub, note)

    def cancel(self, sub: Subscription) -> None:
        sub.mailbox.closed = True

    def close(self, timeout: float = 5.0) -> None:
        self._pending = threading.local()
