"""What both engines share: subscriptions, the index, latest documents, policies and dispatch."""

from __future__ import annotations

import logging
import math
import threading
from collections import Counter
from collections.abc import Callable, Hashable, Iterator
from contextlib import contextmanager

from lxml import etree

from acordcs.runtime.context.delivery import DeliveryDispatcher, Notification, Subscription
from acordcs.runtime.context.errors import ContextError, SubscriptionError
from acordcs.runtime.context.index import SubscriptionIndex
from acordcs.runtime.context.inlinedelivery import InlineDelivery
from acordcs.runtime.context.xmlparse import Limits, parse_document, to_bytes
from acordcs.runtime.context.xpathcost import check_cost
from acordcs.runtime.context.xpathexpr import compile_expression, recognise

log = logging.getLogger("acordcs.runtime.context")


def _fingerprint(nodes: list, value: object) -> object:
    if not nodes:
        return ("value", value if not isinstance(value, list) else ())
    return tuple(
        etree.tostring(n, with_tail=False)
        if isinstance(n, etree._Element)
        else ("s", str(n), getattr(n, "attrname", None))
        for n in nodes
    )


def check_publisher(publisher: object, what: str = "publisher") -> str:
    if not isinstance(publisher, str) or not publisher:
        raise ContextError(
            f"{what} must be a non-empty str, got {publisher!r}",
            element=what,
            hint="name the publisher, e.g. 'robot1/telemetry'",
        )
    if "\x00" in publisher or len(publisher) > 1024:
        raise ContextError(
            f"{what} {publisher[:40]!r} contains NUL or is longer than 1024 characters",
            element=what,
            hint="use a short printable name",
        )
    return publisher


class ProviderCore:
    """Subscriptions, matching and dispatch; engines add ``publish``.

    ``delivery_threads``: the pool of threads that run callbacks (slow ones each hold a thread);
    ``threads_per_subscriber``: how many callbacks of one subscriber may run at once (more are
    made beyond ``delivery_threads`` for subscribers kept waiting by others' blocked callbacks);
    ``inline``: no threads, callbacks run in the publishing thread (:class:`InlineDelivery`);
    ``quick_seconds``: subscriptions whose callbacks are that quick are delivered in the receiving
    thread (see :class:`DeliveryDispatcher`; the MQTT engine's default)."""

    def __init__(
        self,
        limits: Limits | None = None,
        delivery_threads: int = 64,
        *,
        inline: bool = False,
        threads_per_subscriber: int = 2,
        quick_seconds: float | None = None,
    ) -> None:
        self.limits = limits or Limits()
        self.inline = inline
        self._dispatcher: DeliveryDispatcher | InlineDelivery = (
            InlineDelivery()
            if inline
            else DeliveryDispatcher(
                max_threads=delivery_threads,
                per_subscriber=threads_per_subscriber,
                quick_seconds=quick_seconds,
            )
        )
        self._lock = threading.RLock()
        self._index = SubscriptionIndex(
            self.limits.max_eval_seconds, self.limits.max_strikes, self.limits.strike_window
        )
        self._index.on_suspend = self._suspended
        # One lock per publisher, held while one of its documents is matched and dispatched (its
        # notifications keep their order); the provider lock is held only for the index and the
        # bookkeeping, not while a fallback XPath runs.
        self._publisher_locks: dict[str, list] = {}  # publisher -> [lock, users]: see _publishing
        self._on_suspend: dict[Subscription, Callable[[Subscription, str], object]] = {}
        self._subs: dict[int, tuple[Subscription, object]] = {}
        self._latest: dict[str, tuple[int, etree._ElementTree]] = {}
        # publisher -> the on_change subscriptions whose last selection there was not empty, with
        # the fingerprint of that selection
        self._changing: dict[str, dict[Subscription, object]] = {}
        self._closed = False
        self.rejected = 0  # documents refused (malformed, hostile, too large, too costly)
        self.rejected_by: Counter[str] = Counter()  # the same, by publisher (the first 4,096)

    # -- subscriptions -------------------------------------------------------------------------------
    def subscribe(
        self,
        callback: Callable[[Notification], object],
        xpath: str | None = None,
        publisher: str | None = None,
        *,
        max_rate: float | None = None,
        on_change: bool = False,
        queue_size: int = 1024,
        on_suspend: Callable[[Subscription, str], object] | None = None,
        subscriber: Hashable = None,
    ) -> Subscription:
        """Call ``callback(notification)`` for every document (of ``publisher``, if given) that ``xpath``
        selects something in. ``max_rate``: at most that many notifications per second, the latest wins.
        ``on_change``: only when the selection differs from the previous document of that publisher
        (including when it becomes empty: then ``nodes`` is empty). ``on_suspend(handle, reason)``:
        called (on a thread of its own) if the subscription is suspended for overrunning its time
        budget. ``subscriber``: who the callback belongs to (any hashable, e.g. a client's id;
        default: the callback itself); one subscriber's callbacks run on at most
        ``threads_per_subscriber`` threads at once. Unless ``Limits.trusted_subscribers``, an
        expression the index does not walk along its trie of ``/a/b/c`` paths must pass the cost
        check (:mod:`.xpathcost`)."""
        self._check_open()
        if not callable(callback):
            raise SubscriptionError(
                "callback is not callable", element="subscription", hint="pass a function"
            )
        if publisher is not None:
            check_publisher(publisher)
        if max_rate is not None and (
            isinstance(max_rate, bool)
            or not isinstance(max_rate, int | float)
            or not max_rate > 0
            or math.isinf(max_rate)
        ):
            raise SubscriptionError(
                f"max_rate must be a positive number of notifications per second, got {max_rate!r}",
                element="subscription",
                hint="e.g. max_rate=10, or None for no limit",
            )
        if max_rate is not None and self.inline:
            raise SubscriptionError(
                "max_rate is a wall-clock rate, and this provider delivers inline (virtual time)",
                element="subscription",
                hint="leave max_rate unset; rate-limit in the callback with the clock's time",
            )
        if isinstance(queue_size, bool) or not isinstance(queue_size, int) or queue_size < 1:
            raise SubscriptionError(
                f"queue_size must be a positive int, got {queue_size!r}",
                element="subscription",
                hint="the number of notifications kept for a slow callback",
            )
        if on_suspend is not None and not callable(on_suspend):
            raise SubscriptionError(
                "on_suspend is not callable", element="subscription", hint="pass a function"
            )
        compiled = form = None
        if xpath is not None:
            compiled = compile_expression(xpath, self.limits.max_expression_chars)
            form = recognise(xpath)
            # a /a/b/c path is walked once along the index's trie; every other expression runs
            # as an XPath of its own (a fallback) or shared with the same path (``//a//b``)
            linear = form is not None and form.child_steps is not None
            if not linear and not self.limits.trusted_subscribers:
                check_cost(xpath, self.limits.max_xpath_cost)
        try:
            hash(subscriber)
        except TypeError:
            raise SubscriptionError(
                f"subscriber must be hashable, got {type(subscriber).__name__}",
                element="subscription",
                hint="name the subscriber with a str, int or tuple",
            ) from None
        sub = Subscription(
            callback, xpath, publisher, max_rate, bool(on_change), queue_size, subscriber
        )
        with self._lock:
            self._check_open()
            self._index.add(sub, publisher, form, compiled)
            self._subs[sub.id] = (sub, form)
            if on_suspend is not None:
                self._on_suspend[sub] = on_suspend
        self._subscribed(sub)
        return sub

    def unsubscribe(self, handle: Subscription) -> bool:
        """Stop notifications for ``handle``. False if it was not (or no longer) subscribed here."""
        with self._lock:
            entry = self._subs.pop(getattr(handle, "id", None), None)
            if entry is None or entry[0] is not handle:
                return False
            sub, form = entry
            self._index.remove(sub, sub.publisher, form)
            self._on_suspend.pop(sub, None)
            for holders in self._changing.values():
                holders.pop(sub, None)
        self._dispatcher.cancel(sub)
        self._unsubscribed(sub)
        return True

    def subscriptions(self) -> list[Subscription]:
        with self._lock:
            return [sub for sub, _ in self._subs.values()]

    # -- pull -----------------------------------------------------------------------------------------
    def query(self, xpath: str, publisher: str | None = None) -> list[Notification]:
        """Evaluate ``xpath`` over the latest document of each publisher (or of ``publisher``) and
        return one notification-shaped result per document it selects something in."""
        compiled = compile_expression(xpath, self.limits.max_expression_chars, what="query")
        with self._lock:
            latest = (
                list(self._latest.items())
                if publisher is None
                else [(publisher, self._latest[publisher])]
                if publisher in self._latest
                else []
            )
        results = []
        for name, (seq, tree) in sorted(latest):
            value = compiled(tree)
            if isinstance(value, list):
                if value:
                    results.append(Notification(name, seq, tree, value, value))
            elif value and value == value:  # XPath boolean(): NaN is false
                results.append(Notification(name, seq, tree, [], value))
        return results

    def latest(self, publisher: str) -> tuple[int, etree._ElementTree] | None:
        """``(seq, document)`` last seen from ``publisher``, or None."""
        with self._lock:
            return self._latest.get(publisher)

    def publishers(self) -> list[str]:
        with self._lock:
            return sorted(self._latest)

    def stats(self) -> dict[str, object]:
        with self._lock:
            subs = [sub for sub, _ in self._subs.values()]
        return {
            "subscriptions": len(subs),
            "rejected": self.rejected,
            "dropped": sum(s.stats.dropped for s in subs),
            "callback_errors": sum(s.stats.errors for s in subs),
            "suspended": [repr(s) for s in subs if s.stats.suspended],
        }

    # -- documents ------------------------------------------------------------------------------------
    def _parse(self, publisher: str, document: object) -> tuple[bytes, etree._ElementTree]:
        try:
            data = to_bytes(publisher, document)
            return data, parse_document(publisher, data, self.limits)
        except Exception:
            self._count_rejected(publisher)
            raise

    def _count_rejected(self, publisher: str) -> None:
        self.rejected += 1
        if publisher in self.rejected_by or len(self.rejected_by) < 4096:
            self.rejected_by[publisher] += 1

    @contextmanager
    def _publishing(self, publisher: str) -> Iterator[None]:
        """Hold ``publisher``'s lock: its documents are numbered and dispatched one at a time, in
        order. A lock lives while someone uses it, so hostile publisher names leave nothing behind."""
        with self._lock:
            entry = self._publisher_locks.get(publisher)
            if entry is None:
                entry = self._publisher_locks[publisher] = [threading.Lock(), 0]
            entry[1] += 1
        try:
            with entry[0]:
                yield
        finally:
            with self._lock:
                entry[1] -= 1
                if not entry[1]:
                    del self._publisher_locks[publisher]

    def _dispatch(
        self,
        publisher: str,
        seq: int,
        tree: etree._ElementTree,
        *,
        latest: bool = True,
        may_inline: bool = False,
    ) -> int:
        """Match and hand notifications to the subscribers' mailboxes. Returns how many were queued.
        ``latest=False``: a document that came late (older than the publisher's latest, which it
        does not replace). ``may_inline``: the caller flushes the dispatcher next, in this thread
        (quick subscriptions are delivered there).

        The caller is inside :meth:`_publishing` (documents of one publisher in order)."""
        with self._lock:
            if latest:
                self._latest[publisher] = (seq, tree)
            matches = self._index.match_indexed(tree, publisher)
            fallbacks = self._index.fallbacks(publisher)
        if fallbacks:  # without the provider lock: other publishers and subscribers go on
            matches += self._index.evaluate(fallbacks, tree)
        with self._lock:
            changing = self._changing.get(publisher) or {}
            queued = 0
            matched_changing: dict[Subscription, object] = {}
            for subs, nodes, value in matches:
                for sub in subs:
                    if sub.on_change:
                        fp = matched_changing[sub] = _fingerprint(nodes, value)
                        if changing.get(sub) == fp:
                            sub.stats.unchanged += 1
                            continue
                    self._dispatcher.offer(
                        sub, Notification(publisher, seq, tree, nodes, value), may_inline
                    )
                    queued += 1
            if changing or matched_changing:
                # on_change subscribers whose selection just became empty are told so once
                for sub in changing.keys() - matched_changing.keys():
                    self._dispatcher.offer(
                        sub, Notification(publisher, seq, tree, [], None), may_inline
                    )
                    queued += 1
                self._changing[publisher] = matched_changing
            return queued

    def _suspended(self, sub: Subscription, elapsed: float) -> None:
        with self._lock:
            self._index.suspend(sub, sub.publisher)
            tell = self._on_suspend.pop(sub, None)
        sub.stats.suspended = True
        reason = (
            f"its XPath took {elapsed * 1e3:.1f} ms of CPU on one document, over the "
            f"{self.limits.max_eval_seconds * 1e3:.1f} ms budget {self.limits.max_strikes} times "
            f"within {self.limits.strike_window:g} s"
        )
        log.warning("%r suspended: %s", sub, reason)
        if tell is not None:  # on a thread of its own: the subscriber's code must not hold us up

            def notify() -> None:
                try:
                    tell(sub, reason)
                except Exception as err:
                    log.warning("%r: on_suspend raised %s: %s", sub, type(err).__name__, err)

            threading.Thread(target=notify, name="acordcs-ctx-suspended", daemon=True).start()

    # -- lifecycle ------------------------------------------------------------------------------------
    def _check_open(self) -> None:
        if self._closed:
            raise ContextError("the context provider is closed", hint="create a new provider")

    def _subscribed(self, sub: Subscription) -> None:
        """Engine hook (the MQTT engine subscribes to topics)."""

    def _unsubscribed(self, sub: Subscription) -> None:
        """Engine hook."""

    def close(self) -> None:
        """Unsubscribe everything and stop the delivery threads. Idempotent."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
            subs = [sub for sub, _ in self._subs.values()]
        for sub in subs:
            self.unsubscribe(sub)
        self._dispatcher.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
