"""Notifications, subscription handles, and the :class:`DeliveryDispatcher` that delivers them.

Every subscription has its own bounded :class:`Mailbox`; a pool of delivery threads runs the callbacks, at most
one thread per subscription at a time (so each subscriber sees its notifications in order). When every
thread is busy, e.g. inside a slow callback, the pool grows (up to ``max_threads``), so a slow or
raising subscriber delays only itself, and publishers never wait for callbacks: when a mailbox is full
its oldest notification is dropped, counted and logged. Threads beyond the first retire when idle.
Threads track how many callbacks run *at once*, not how many subscriptions exist. A callback
running longer than ``isolate_seconds`` (a subscriber blocking) has its thread set aside: it no
longer counts against ``max_threads``, so subscribers that block cannot stop delivery to the others
(at most one thread per subscription is ever set aside; it ends when its callback returns).
"""

from __future__ import annotations

import heapq
import itertools
import logging
import threading
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass, field

from lxml import etree

log = logging.getLogger("acordcs.runtime.context")

_ids = itertools.count(1)


@dataclass(frozen=True, slots=True)
class Notification:
    """One matching document. ``nodes`` are the selected nodes (empty when the expression yields a
    number, string or boolean, or, with ``on_change``, when the selection has just become empty);
    ``value`` is the raw XPath result. Treat ``document`` as read-only: it is shared."""

    publisher: str
    seq: int
    document: etree._ElementTree
    nodes: list
    value: object = None


@dataclass
class SubscriptionStats:
    delivered: int = 0
    dropped: int = 0  # mailbox full: the oldest pending notification was discarded
    coalesced: int = 0  # max_rate: replaced by a newer one before delivery (latest wins)
    unchanged: int = 0  # on_change: suppressed because the selection was the same
    errors: int = 0  # the callback raised
    isolated: int = 0  # the callback ran so long that its thread was set aside
    suspended: bool = False  # a fallback expression overran its time budget too often
    last_error: str | None = None


class Mailbox:
    """A subscription's pending notifications and delivery state, kept by the
    :class:`DeliveryDispatcher` under its lock."""

    __slots__ = ("closed", "next_allowed", "pending", "running", "scheduled")

    def __init__(self) -> None:
        self.pending: deque[Notification] = deque()
        self.scheduled = False  # in the ready queue or the delayed heap
        self.running = False  # a delivery thread is in its callback
        self.closed = False
        self.next_allowed = 0.0  # max_rate: monotonic time of the next delivery


@dataclass(eq=False)
class Subscription:
    """The handle ``subscribe`` returns; pass it to ``unsubscribe``."""

    callback: Callable[[Notification], object]
    xpath: str | None
    publisher: str | None
    max_rate: float | None = None
    on_change: bool = False
    queue_size: int = 1024
    id: int = field(default_factory=lambda: next(_ids))
    stats: SubscriptionStats = field(default_factory=SubscriptionStats)
    mailbox: Mailbox = field(default_factory=Mailbox, init=False, repr=False)

    def __repr__(self) -> str:
        where = f" publisher={self.publisher!r}" if self.publisher is not None else ""
        return f"<Subscription {self.id} xpath={self.xpath!r}{where}>"

    def __hash__(self) -> int:
        return self.id

    @property
    def active(self) -> bool:
        return not self.mailbox.closed


class DeliveryDispatcher:
    """The delivery threads of one provider.

    One thread delivers while callbacks are quick (a document matching many subscriptions then costs one
    thread wake-up, not one per subscription). A watchdog adds a thread when a subscription has waited
    ``stall_seconds`` while every thread has been inside one callback for at least as long: that is
    what keeps a slow callback from holding up the others.
    """

    def __init__(
        self,
        name: str = "ctx",
        max_threads: int = 64,
        stall_seconds: float = 0.01,
        idle_seconds: float = 5.0,
        isolate_seconds: float = 1.0,
    ) -> None:
        if max_threads < 1:
            raise ValueError(f"max_threads must be at least 1, got {max_threads!r}")
        self._name = name
        self._max = max_threads
        self._stall = stall_seconds
        self._isolate_after = isolate_seconds
        self._isolated: dict[threading.Thread, Subscription] = {}  # set aside, in a callback
        self._current: dict[threading.Thread, Subscription] = {}  # whose callback each runs
        self._idle_seconds = idle_seconds
        self._lock = threading.Lock()
        self._work_cond = threading.Condition(self._lock)
        self._watch_cond = threading.Condition(self._lock)
        self._ready: deque[tuple[float, Subscription]] = deque()  # (queued at, subscription)
        self._delayed: list[tuple[float, int, Subscription]] = []  # heap: max_rate waits
        self._threads: set[threading.Thread] = set()
        self._in_callback: dict[threading.Thread, float] = {}  # thread -> when its callback began
        self._watchdog: threading.Thread | None = None
        self._idle = 0  # threads waiting for work
        self._wakeups = 0  # of those, how many were notified and have not woken yet
        self._closed = False
        self._count = itertools.count(1)

    @property
    def threads(self) -> int:
        with self._lock:
            return len(self._threads)

    def offer(self, sub: Subscription, note: Notification) -> None:
        """Queue ``note`` for ``sub``; never blocks on a callback."""
        with self._lock:
            box = sub.mailbox
            if box.closed or self._closed:
                return
            mailbox = box.pending
            if sub.max_rate is not None and mailbox:
                mailbox.clear()
                sub.stats.coalesced += 1
            elif len(mailbox) >= sub.queue_size:
                mailbox.popleft()
                sub.stats.dropped += 1
                dropped = sub.stats.dropped
                if dropped & (dropped - 1) == 0:  # 1, 2, 4, 8...: visible without flooding the log
                    log.warning(
                        "%r: callback too slow, %d notification(s) dropped so far (queue_size=%d)",
                        sub,
                        dropped,
                        sub.queue_size,
                    )
            mailbox.append(note)
            if not box.scheduled and not box.running:
                self._schedule(sub, wake=True)

    def flush(self) -> None:
        """Nothing to do: the threads deliver (see :class:`InlineDelivery`)."""

    def cancel(self, sub: Subscription) -> None:
        """No more deliveries to ``sub`` (a callback already running finishes)."""
        with self._lock:
            sub.mailbox.closed = True
            sub.mailbox.pending.clear()

    def close(self, timeout: float = 5.0) -> None:
        """Stop delivering and join the threads (one stuck in a callback is left behind, as a daemon)."""
        with self._lock:
            self._closed = True
            self._work_cond.notify_all()
            self._watch_cond.notify_all()
            threads = [*self._threads, *([self._watchdog] if self._watchdog else [])]
        deadline = time.monotonic() + timeout
        for thread in threads:
            if thread is not threading.current_thread():
                thread.join(max(0.0, deadline - time.monotonic()))

    # -- under the lock -------------------------------------------------------------------------------
    def _schedule(self, sub: Subscription, wake: bool) -> None:
        box = sub.mailbox
        box.scheduled = True
        now = time.monotonic()
        if box.next_allowed > now:
            heapq.heappush(self._delayed, (box.next_allowed, sub.id, sub))
        else:
            self._ready.append((now, sub))
        if not wake:
            return
        if self._idle > self._wakeups:
            self._wakeups += 1
            self._work_cond.notify()
        elif not self._threads:
            self._spawn()
        else:  # everybody is busy: the watchdog adds a thread if this waits too long
            if self._watchdog is None:
                self._watchdog = threading.Thread(
                    target=self._watch, name=f"acordcs-{self._name}-watchdog", daemon=True
                )
                self._watchdog.start()
            self._watch_cond.notify()

    def _spawn(self) -> None:
        thread = threading.Thread(
            target=self._work,
            name=f"acordcs-{self._name}-delivery-{next(self._count)}",
            daemon=True,
        )
        self._threads.add(thread)
        thread.start()

    def _promote_due(self, now: float) -> None:
        while self._delayed and self._delayed[0][0] <= now:
            self._ready.append((now, heapq.heappop(self._delayed)[2]))

    def _next(self) -> Subscription | None:
        while not self._closed:
            now = time.monotonic()
            self._promote_due(now)
            while self._ready:
                sub = self._ready.popleft()[1]
                box = sub.mailbox
                box.scheduled = False
                if not box.closed and box.pending:
                    return sub
            timeout = self._delayed[0][0] - now if self._delayed else self._idle_seconds
            self._idle += 1
            notified = self._work_cond.wait(timeout)
            self._idle -= 1
            if self._wakeups:
                self._wakeups -= 1
            if not notified and not self._delayed and not self._ready and len(self._threads) > 1:
                return None  # idle long enough: retire (one thread stays)
        return None

    # -- threads --------------------------------------------------------------------------------------
    def _work(self) -> None:
        with self._lock:
            try:
                while True:
                    sub = self._next()
                    if sub is None:
                        return
                    box = sub.mailbox
                    note = box.pending.popleft()
                    box.running = True
                    if sub.max_rate:
                        box.next_allowed = time.monotonic() + 1.0 / sub.max_rate
                    me = threading.current_thread()
                    self._in_callback[me] = time.monotonic()
                    self._current[me] = sub
                    self._lock.release()
                    try:
                        _deliver(sub, note)
                    finally:
                        self._lock.acquire()
                        del self._in_callback[me]
                        del self._current[me]
                        box.running = False
                    if self._isolated.pop(me, None) is not None:
                        # set aside while it blocked: the pool has replaced this thread
                        if box.pending and not box.closed:
                            self._schedule(sub, wake=True)
                        return
                    if box.pending and not box.closed:
                        self._schedule(sub, wake=False)  # this thread comes back for it
            finally:
                self._threads.discard(threading.current_thread())

    def _watch(self) -> None:
        with self._lock:
            while not self._closed:
                now = time.monotonic()
                self._promote_due(now)
                if self._ready:
                    waited = now - self._ready[0][0]
                    # a backlog of quick callbacks is load, which more threads would not speed up
                    # (the GIL); every thread stuck in one callback for a while is what needs help
                    began = [self._in_callback.get(t) for t in self._threads]
                    stuck = all(b is not None and now - b >= self._stall for b in began)
                    if waited >= self._stall and stuck and len(self._threads) >= self._max:
                        self._set_aside(now)
                    if waited >= self._stall and stuck and len(self._threads) < self._max:
                        self._spawn()
                        self._ready[0] = (now, self._ready[0][1])  # give the new thread its chance
                        continue
                    if waited >= self._stall and self._idle:
                        self._work_cond.notify_all()  # a wake-up went astray: cheap to repeat
                    self._watch_cond.wait(max(self._stall - waited, self._stall / 4))
                else:
                    self._watch_cond.wait(self._delayed[0][0] - now if self._delayed else None)

    def _set_aside(self, now: float) -> None:
        """Take the threads whose callback has run over ``isolate_seconds`` out of the pool (under
        the lock): each finishes its callback, then ends; the pool may replace it."""
        for thread in list(self._threads):
            began = self._in_callback.get(thread)
            if began is None or now - began < self._isolate_after:
                continue
            sub = self._current[thread]
            self._threads.discard(thread)
            self._isolated[thread] = sub
            sub.stats.isolated += 1
            log.warning(
                "%r: callback running for %.1f s; its delivery thread is set aside so that the "
                "other subscriptions keep receiving (%d thread(s) set aside)",
                sub,
                now - began,
                len(self._isolated),
            )


def _deliver(sub: Subscription, note: Notification) -> None:
    try:
        sub.callback(note)
        sub.stats.delivered += 1
    except Exception as err:  # a subscriber's bug must not stop delivery
        sub.stats.errors += 1
        sub.stats.last_error = f"{type(err).__name__}: {err}"
        if sub.stats.errors & (sub.stats.errors - 1) == 0:
            log.warning(
                "%r: callback raised %s (%d time(s))",
                sub,
                sub.stats.last_error,
                sub.stats.errors,
            )


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

    def offer(self, sub: Subscription, note: Notification) -> None:
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
                _deliver(sub, note)

    def cancel(self, sub: Subscription) -> None:
        sub.mailbox.closed = True

    def close(self, timeout: float = 5.0) -> None:
        self._pending = threading.local()
