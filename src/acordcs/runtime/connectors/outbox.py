"""One-way deliveries to a remote port, sent by a thread of their own.

A notification or a stream item needs no reply, so its sender should not wait for the network:
the sender is often the container's clock thread (a component's timer, a shaped link's delivery),
and a peer that is slow or cut off would hold every timer of the container (monitors, policy
sets, safety watches) for the connector's timeout at each message. An :class:`Outbox` takes the
item at once and a sender thread delivers the items of one connection in order.

Nothing is lost unseen. Each item is delivered, or counted in the connection's
``stats["lost"]`` and reported through ``report`` (a fault of the sending container):

- a delivery that fails (the peer unreachable, no reply within the timeout) is not retried: a
  notification is delivered at most once;
- an item arriving while ``capacity`` items wait drops the oldest waiting one (the newest context
  wins, as a receiving port's default ``drop_oldest``);
- :meth:`close` delivers what waits until its deadline and returns how many it could not.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable
from typing import Any

CAPACITY = 64
"""Items an outbox holds for a peer that does not take them (at 12 frames/s, 5 s of a camera)."""


class Outbox:
    """The one-way items of one connection, delivered in order by ``send`` in a thread."""

    def __init__(
        self,
        name: str,
        send: Callable[[Any], None],
        report: Callable[[BaseException | str], None],
        stats: dict[str, int],
        capacity: int = CAPACITY,
    ) -> None:
        self.name = name
        self._send, self.report, self._capacity = send, report, capacity
        self.stats = stats  # the connection's: items not delivered are counted in its "lost"
        self._items: deque[Any] = deque()
        self._ready = threading.Condition()
        self._busy = False  # an item is being sent (taken from the queue, not yet done)
        self._closed = False
        self._abandoned = False  # close() gave up on the item being sent and counted it lost
        self._thread = threading.Thread(
            target=self._run, name=f"acordcs-outbox {name}", daemon=True
        )
        self._thread.start()

    def put(self, item: Any) -> None:
        """Queue ``item`` for delivery; returns at once."""
        dropped = ""
        with self._ready:
            if self._closed:
                self.stats["lost"] += 1
                dropped = "OutboxClosed: an item sent after the connector closed was dropped"
            else:
                if len(self._items) >= self._capacity:
                    self._items.popleft()
                    self.stats["lost"] += 1
                    dropped = (
                        f"OutboxFull: {self._capacity} items were waiting for the peer, which "
                        "does not take them (unreachable or slow); the oldest was dropped"
                    )
                self._items.append(item)
                self._ready.notify()
        if dropped:
            self.report(dropped)

    def pending(self) -> int:
        with self._ready:
            return len(self._items) + self._busy

    def _run(self) -> None:
        while True:
            with self._ready:
                self._ready.wait_for(lambda: self._items or self._closed)
                if not self._items:
                    return
                item = self._items.popleft()
                self._busy = True
            try:
                self._send(item)
            except Exception as exc:  # the peer's failure is this connection's fault, reported
                with self._ready:
                    counted, self._abandoned = self._abandoned, False
                    if not counted:
                        self.stats["lost"] += 1
                self.report(exc)
            finally:
                with self._ready:
                    self._busy = self._abandoned = False
                    self._ready.notify_all()

    def close(self, deadline: float) -> int:
        """Stop taking items, deliver those waiting until ``deadline`` (``time.monotonic()``),
        and return how many were not delivered (also counted in ``stats["lost"]``)."""
        with self._ready:
            self._closed = True
            self._ready.notify_all()
            while (self._items or self._busy) and (left := deadline - time.monotonic()) > 0:
                self._ready.wait(left)
            undelivered = len(self._items) + self._busy
            self._abandoned = self._busy
            self._items.clear()
            self.stats["lost"] += undelivered
        return undelivered
