"""Notifications, subscription handles, and the :class:`DeliveryDispatcher` that delivers them.

Every subscription has its own bounded :class:`Mailbox`; a pool of delivery threads runs the
callbacks, at most one thread per subscription at a time (so each subscriber sees its notifications
in order). Publishers never wait for callbacks: when a mailbox is full its oldest notification is
dropped, counted and logged. Threads track how many callbacks run *at once*, not how many
subscriptions exist; threads beyond the first retire when idle. A subscriber (the owner of one or
more subscriptions, by default their callback) runs at most ``per_subscriber`` callbacks at once,
and subscribers take turns: a subscriber whose callbacks block holds that many threads, and a new
thread is made for any other subscriber that has waited a few milliseconds while every thread was
stuck, so blocked callbacks of one subscriber never starve another.

With ``quick_seconds`` (the MQTT provider's default), a subscription whose callbacks have returned
within that time 16 times in a row on the delivery threads is delivered in the receiving thread
(paho's network thread) instead, without a thread hand-over, while its mailbox is empty; a callback
that then holds that thread longer sends it back to the threads at once (see
:class:`~.quick.QuickJudge`).
"""

from __future__ import annotations

import heapq
import itertools
import logging
import threading
import time
from collections import deque
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field

from lxml import etree

from acordcs.runtime.context.quick import QUICK_RUNS, QuickJudge, thread_waits

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
    inline: int = 0  # of ``delivered``, run in the receiving thread (a quick subscription)
    demoted: int = 0  # times an inline callback overran ``quick_seconds`` (back to the threads)
    suspended: bool = False  # a fallback expression overran its time budget too often
    last_error: str | None = None


class Mailbox:
    """A subscription's pending notifications and delivery state, kept by the
    :class:`DeliveryDispatcher` under its lock."""

    __slots__ = (
        "closed",
        "next_allowed",
        "pending",
        "quick",
        "quick_needed",
        "quick_runs",
        "running",
        "scheduled",
    )

    def __init__(self) -> None:
        self.pending: deque[Notification] = deque()
        self.scheduled = False  # in the ready queue or the delayed heap
        self.running = False  # a delivery thread is in its callback
        self.closed = False
        self.next_allowed = 0.0  # max_rate: monotonic time of the next delivery
        self.quick = False  # delivered in the receiving thread (see DeliveryDispatcher)
        self.quick_runs = 0  # quick callbacks in a row on the delivery threads
        self.quick_needed = QUICK_RUNS  # how many make it quick


def subscriber_of(callback: Callable[..., object]) -> Hashable:
    """The default subscriber of ``callback``: the callback itself when hashable (bound methods
    of one object compare equal), else its identity."""
    try:
        hash(callback)
    except TypeError:
        return ("callback", id(callback))
    return callback


@dataclass(eq=False)
class Subscription:
    """The handle ``subscribe`` returns; pass it to ``unsubscribe``."""

    callback: Callable[[Notification], object]
    xpath: str | None
    publisher: str | None
    max_rate: float | None = None
    on_change: bool = False
    queue_size: int = 1024
    # Whose callback this is: its callbacks share a bounded number of delivery threads. Default:
    # the callback itself (subscriptions sharing one callback, or one object's method, share).
    subscriber: Hashable = None
    id: int = field(default_factory=lambda: next(_ids))
    stats: SubscriptionStats = field(default_factory=SubscriptionStats)
    mailbox: Mailbox = field(default_factory=Mailbox, init=False, repr=False)

    def __post_init__(self) -> None:
        if self.subscriber is None:
            self.subscriber = subscriber_of(self.callback)

    def __repr__(self) -> str:
        where = f" publisher={self.publisher!r}" if self.publisher is not None else ""
        return f"<Subscription {self.id} xpath={self.xpath!r}{where}>"

    def __hash__(self) -> int:
        return self.id

    @property
    def active(self) -> bool:
        return not self.mailbox.closed


class _Lane:
    """One subscriber's share of the pool: its subscriptions with notifications to deliver, in the
    order they became ready, and how many of its callbacks run now."""

    __slots__ = ("listed", "queue", "running", "subscriber")

    def __init__(self, subscriber: Hashable) -> None:
        self.subscriber = subscriber
        self.queue: deque[Subscription] = deque()
        self.running = 0
        self.listed = False  # in the dispatcher's ready queue


class DeliveryDispatcher:
    """The delivery threads of one provider, shared by every subscriber.

    One thread delivers while callbacks are quick (a document matching many subscriptions then costs
    one thread wake-up, not one per subscription). Subscribers (:attr:`Subscription.subscriber`)
    take turns, and each runs at most ``per_subscriber`` callbacks at once: its other notifications
    wait in its mailboxes and take no thread. A watchdog adds threads when a subscriber has waited
    ``stall_seconds`` while every thread has been inside one callback for at least as long: one
    for each waiting subscriber that has no callback running (whatever the count), else one more up
    to ``max_threads``. So the blocked callbacks of one subscriber hold at most ``per_subscriber``
    threads and keep another subscriber waiting about ``stall_seconds`` at most.
    """

    def __init__(
        self,
        name: str = "ctx",
        max_threads: int = 64,
        stall_seconds: float = 0.01,
        idle_seconds: float = 5.0,
        per_subscriber: int = 2,
        quick_seconds: float | None = None,
    ) -> None:
        if max_threads < 1:
            raise ValueError(f"max_threads must be at least 1, got {max_threads!r}")
        if per_subscriber < 1:
            raise ValueError(f"per_subscriber must be at least 1, got {per_subscriber!r}")
        self._name = name
        self._max = max_threads
        self._per_subscriber = per_subscriber
        self._stall = stall_seconds
        self._idle_seconds = idle_seconds
        self._lock = threading.Lock()
        self._work_cond = threading.Condition(self._lock)
        self._watch_cond = threading.Condition(self._lock)
        self._ready: deque[tuple[float, _Lane]] = deque()  # (listed at, lane): their turn
        self._delayed: list[tuple[float, int, Subscription]] = []  # heap: max_rate waits
        self._lanes: dict[Hashable, _Lane] = {}  # subscribers with something queued or running
        self._threads: set[threading.Thread] = set()
        self._in_callback: dict[threading.Thread, float] = {}  # thread -> when its callback began
        self._watchdog: threading.Thread | None = None
        self._idle = 0  # threads waiting for work
        self._wakeups = 0  # of those, how many were notified and have not woken yet
        self._closed = False
        self._count = itertools.count(1)
        self._quick = QuickJudge(quick_seconds) if quick_seconds is not None else None
        self._inline = threading.local()  # per receiving thread: [(subscription, notification)]

    @property
    def threads(self) -> int:
        with self._lock:
            return len(self._threads)

    def offer(self, sub: Subscription, note: Notification, may_inline: bool = False) -> None:
        """Queue ``note`` for ``sub``; never blocks on a callback. ``may_inline``: the caller is a
        receiving thread that calls :meth:`flush` next, which delivers ``note`` there if ``sub``
        is quick and has nothing pending (its notifications keep their order)."""
        with self._lock:
            box = sub.mailbox
            if box.closed or self._closed:
                return
            if may_inline and box.quick and not (box.pending or box.running or box.scheduled):
                box.running = True  # offers meanwhile wait in the mailbox for the threads
                queue = getattr(self._inline, "queue", None)
                if queue is None:
                    queue = self._inline.queue = []
                queue.append((sub, note))
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
        """Run, in this thread, the callbacks of the quick subscriptions that this thread's offers
        since the last flush matched; a callback overrunning ``quick_seconds`` sends its
        subscription back to the delivery threads."""
        queue = getattr(self._inline, "queue", None)
        if not queue or self._quick is None:
            return
        self._inline.queue = None
        judge = self._quick
        for sub, note in queue:
            box = sub.mailbox
            waits = thread_waits()
            started = time.monotonic()
            if not (box.closed or self._closed):
                deliver(sub, note)
                sub.stats.inline += 1
            took = time.monotonic() - started
            slow = judge.held(took, waits)
            with self._lock:
                box.running = False
                judge.inline_done(sub, took, slow)
                if box.pending and not box.closed and not box.scheduled:
                    self._schedule(sub, wake=True)

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
            if wake:
                self._wake()  # the watchdog or an idle thread keeps the time
        else:
            self._enqueue(sub, now, wake)

    def _enqueue(self, sub: Subscription, now: float, wake: bool) -> None:
        lane = self._lanes.get(sub.subscriber)
        if lane is None:
            lane = self._lanes[sub.subscriber] = _Lane(sub.subscriber)
        lane.queue.append(sub)
        if self._list(lane, now) and wake:
            self._wake()

    def _list(self, lane: _Lane, now: float) -> bool:
        """Put ``lane`` in the ready queue if it has work and may run one more callback."""
        if lane.listed or not lane.queue or lane.running >= self._per_subscriber:
            return False
        lane.listed = True
        self._ready.append((now, lane))
        return True

    def _wake(self) -> None:
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

    def _spawn(self, first: Subscription | None = None) -> None:
        """A new pool thread; ``first``: a subscription it delivers to before anything else
        (already taken by :meth:`_take`)."""
        thread = threading.Thread(
            target=self._work,
            args=(first,),
            name=f"acordcs-{self._name}-delivery-{next(self._count)}",
            daemon=True,
        )
        self._threads.add(thread)
        thread.start()

    def _promote_due(self, now: float) -> None:
        while self._delayed and self._delayed[0][0] <= now:
            self._enqueue(heapq.heappop(self._delayed)[2], now, wake=False)

    def _take(self, lane: _Lane, now: float) -> Subscription | None:
        """The next subscription of ``lane`` with something to deliver, counted as running;
        ``lane`` has left the ready queue and is listed again if it may run more."""
        lane.listed = False
        sub = None
        while lane.queue:
            candidate = lane.queue.popleft()
            candidate.mailbox.scheduled = False
            if candidate.mailbox.pending and not candidate.mailbox.closed:
                sub = candidate
                lane.running += 1
                break
        self._list(lane, now)  # at the back: subscribers take turns
        if not lane.queue and not lane.running:
            del self._lanes[lane.subscriber]
        return sub

    def _next(self) -> Subscription | None:
        while not self._closed:
            now = time.monotonic()
            self._promote_due(now)
            while self._ready:
                sub = self._take(self._ready.popleft()[1], now)
                if sub is not None:
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

    def _finished(self, sub: Subscription) -> None:
        """``sub``'s callback returned: its subscriber may run another one; ``sub`` is queued
        again if it has more (this thread or another comes back for it)."""
        lane = self._lanes[sub.subscriber]
        lane.running -= 1
        box = sub.mailbox
        if box.pending and not box.closed:
            box.scheduled = True
            lane.queue.append(sub)
        self._list(lane, time.monotonic())
        if not lane.queue and not lane.running:
            del self._lanes[sub.subscriber]

    # -- threads --------------------------------------------------------------------------------------
    def _work(self, first: Subscription | None) -> None:
        me = threading.current_thread()
        with self._lock:
            try:
                sub = first
                while True:
                    if sub is None:
                        sub = self._next()
                        if sub is None:
                            return
                    box = sub.mailbox
                    if box.pending and not box.closed:
                        note = box.pending.popleft()
                        box.running = True
                        if sub.max_rate:
                            box.next_allowed = time.monotonic() + 1.0 / sub.max_rate
                        began = self._in_callback[me] = time.monotonic()
                        self._lock.release()
                        try:
                            deliver(sub, note)
                        finally:
                            self._lock.acquire()
                            del self._in_callback[me]
                            box.running = False
                        if self._quick is not None:
                            self._quick.observe(sub, time.monotonic() - began)
                    self._finished(sub)
                    sub = None
                    if len(self._threads) > self._max:  # added for a blocked subscriber: done
                        if self._ready:
                            self._wake()
                        return
            finally:
                self._threads.discard(me)

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
                    if waited >= self._stall and stuck and self._add_threads(now):
                        continue
                    if waited >= self._stall and self._idle:
                        self._work_cond.notify_all()  # a wake-up went astray: cheap to repeat
                    self._watch_cond.wait(max(self._stall - waited, self._stall / 4))
                else:
                    self._watch_cond.wait(self._delayed[0][0] - now if self._delayed else None)

    def _add_threads(self, now: float) -> bool:
        """Every thread is stuck in a callback: each ready subscriber with no callback running gets
        a thread of its own; if none, the pool gets one more thread while under ``max_threads``.
        Returns whether a thread was added."""
        added = False
        kept: deque[tuple[float, _Lane]] = deque()
        while self._ready:
            listed, lane = self._ready.popleft()
            if lane.running:
                kept.append((listed, lane))
                continue
            sub = self._take(lane, now)  # may list the lane again, at the back of the queue
            if sub is not None:
                self._spawn(first=sub)
                added = True
        self._ready.extendleft(reversed(kept))
        if not added and self._ready and len(self._threads) < self._max:
            self._spawn()
            self._ready[0] = (now, self._ready[0][1])  # give the new thread its chance
            added = True
        return added


def deliver(sub: Subscription, note: Notification) -> None:
    """Run ``sub``'s callback on ``note``, counting it; a raising callback is counted and logged."""
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
