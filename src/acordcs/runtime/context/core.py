"""What both engines share: subscriptions, the index, latest documents, policies and dispatch."""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable

from lxml import etree

from acordcs.runtime.context.delivery import (
    DeliveryDispatcher,
    InlineDelivery,
    Notification,
    Subscription,
)
from acordcs.runtime.context.errors import ContextError, SubscriptionError
from acordcs.runtime.context.index import SubscriptionIndex
from acordcs.runtime.context.xmlparse import Limits, parse_document, to_bytes
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

    ``delivery_threads`` bounds how many callbacks can run at once (slow ones each hold a thread);
    ``inline``: no threads, callbacks run in the publishing thread (:class:`InlineDelivery`)."""

    def __init__(
        self, limits: Limits | None = None, delivery_threads: int = 64, *, inline: bool = False
    ) -> None:
        self.limits = limits or Limits()
        self.inline = inline
        self._dispatcher: DeliveryDispatcher | InlineDelivery = (
            InlineDelivery() if inline else DeliveryDispatcher(max_threads=delivery_threads)
        )
        self._lock = threading.RLock()
        self._index = SubscriptionIndex(self.limits.max_eval_seconds, self.limits.max_strikes)
        self._index.on_suspend = self._suspended
        self._subs: dict[int, tuple[Subscription, object]] = {}
        self._latest: dict[str, tuple[int, etree._ElementTree]] = {}
        # publisher -> the on_change subscriptions whose last selection there was not empty, with
        # the fingerprint of that selection
        self._changing: dict[str, dict[Subscription, object]] = {}
        self._closed = False
        self.rejected = 0  # documents refused (malformed, hostile, too large)

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
    ) -> Subscription:
        """Call ``callback(notification)`` for every document (of ``publisher``, if given) that ``xpath``
        selects something in. ``max_rate``: at most that many notifications per second, the latest wins.
        ``on_change``: only when the selection differs from the previous document of that publisher
        (including when it becomes empty: then ``nodes`` is empty)."""
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
        compiled = form = None
        if xpath is not None:
            compiled = compile_expression(xpath, self.limits.max_expression_chars)
            form = recognise(xpath)
        sub = Subscription(callback, xpath, publisher, max_rate, bool(on_change), queue_size)
        with self._lock:
            self._check_open()
            self._index.add(sub, publisher, form, compiled)
            self._subs[sub.id] = (sub, form)
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
            self.rejected += 1
            raise

    def _dispatch(self, publisher: str, seq: int, tree: etree._ElementTree) -> int:
        """Match and hand notifications to the subscribers' mailboxes. Returns how many were queued."""
        with self._lock:
            self._latest[publisher] = (seq, tree)
            matches = self._index.match(tree, publisher)
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
                    self._dispatcher.offer(sub, Notification(publisher, seq, tree, nodes, value))
                    queued += 1
            if changing or matched_changing:
                # on_change subscribers whose selection just became empty are told so once
                for sub in changing.keys() - matched_changing.keys():
                    self._dispatcher.offer(sub, Notification(publisher, seq, tree, [], None))
                    queued += 1
                self._changing[publisher] = matched_changing
            return queued

    def _suspended(self, sub: Subscription, elapsed: float) -> None:
        sub.stats.suspended = True
        log.warning(
            "%r suspended: its XPath took %.1f ms on one document, over the %.1f ms budget %d times",
            sub,
            elapsed * 1e3,
            self.limits.max_eval_seconds * 1e3,
            self.limits.max_strikes,
        )

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
