"""Subscribers whose callbacks block (issue 14; issue 22, item 12): a subscriber runs at most
``threads_per_subscriber`` callbacks at once, so its blocked callbacks never starve another
subscriber, and other subscribers with nothing running get a thread of their own."""

from __future__ import annotations

import threading

import pytest
from lxml import etree

from acordcs.runtime.context import ContextProvider, SubscriptionError
from acordcs.runtime.context.delivery import DeliveryDispatcher, Notification, Subscription
from tests.support.services import wait_for


def note(seq: int) -> Notification:
    return Notification("p", seq, etree.ElementTree(etree.fromstring("<a/>")), [])


class Blocker:
    """A callback that blocks until released, counting how many of its calls run at once."""

    def __init__(self) -> None:
        self.release = threading.Event()
        self.lock = threading.Lock()
        self.inside = 0
        self.most = 0

    def __call__(self, note: Notification) -> None:
        with self.lock:
            self.inside += 1
            self.most = max(self.most, self.inside)
        try:
            self.release.wait(30)
        finally:
            with self.lock:
                self.inside -= 1


def test_200_blocked_callbacks_of_one_subscriber_hold_two_threads_and_starve_nobody():
    blocker = Blocker()
    got: list[int] = []
    with ContextProvider() as provider:
        try:
            for _ in range(200):
                provider.subscribe(blocker, "/a")  # one subscriber: the same callback
            provider.subscribe(lambda n: got.append(n.seq), "/a")
            provider.publish("p", "<a/>")
            assert wait_for(lambda: got == [1])
            assert wait_for(lambda: blocker.inside == 2)
            provider.publish("p", "<a/>")
            assert wait_for(lambda: got == [1, 2])
            # before: every pool thread, then one more per second, went into the blocker
            assert blocker.most == 2
        finally:
            blocker.release.set()


def test_a_named_subscriber_shares_its_threads_across_callbacks():
    blockers = [Blocker() for _ in range(50)]
    got: list[int] = []
    with ContextProvider(threads_per_subscriber=3) as provider:
        try:
            for blocker in blockers:
                provider.subscribe(blocker, "/a", subscriber="remote client 7")
            provider.subscribe(lambda n: got.append(n.seq), "/a", subscriber="console")
            provider.publish("p", "<a/>")
            assert wait_for(lambda: got == [1])
            assert wait_for(lambda: sum(b.inside for b in blockers) == 3)
            assert sum(b.most for b in blockers) == 3
        finally:
            for blocker in blockers:
                blocker.release.set()


def test_200_subscribers_that_block_do_not_keep_another_waiting():
    release = threading.Event()
    got: list[int] = []
    with ContextProvider() as provider:
        try:
            for _ in range(200):  # 200 subscribers: a callback each
                provider.subscribe(lambda n: release.wait(30), "/a")
            provider.subscribe(lambda n: got.append(n.seq), "/a")
            provider.publish("p", "<a/>")
            # a liveness bound, not a speed claim: about 30 ms here; before, 3.1 s
            assert wait_for(lambda: got == [1], timeout=2)
        finally:
            release.set()


def test_a_blocked_subscriber_gets_its_later_notifications_in_order_once_released():
    blocker = Blocker()
    seen: list[int] = []

    def record(n: Notification) -> None:
        blocker(n)
        seen.append(n.seq)

    dispatcher = DeliveryDispatcher("test", max_threads=2, per_subscriber=1)
    sub = Subscription(record, None, None)
    quick_seen: list[int] = []
    quick = Subscription(lambda n: quick_seen.append(n.seq), None, None)
    try:
        for seq in range(1, 6):
            dispatcher.offer(sub, note(seq))
        assert wait_for(lambda: blocker.inside == 1)
        for seq in range(1, 4):
            dispatcher.offer(quick, note(seq))
        assert wait_for(lambda: quick_seen == [1, 2, 3])
        blocker.release.set()
        assert wait_for(lambda: seen == [1, 2, 3, 4, 5])
        assert blocker.most == 1
    finally:
        blocker.release.set()
        dispatcher.close()


def test_a_subscriber_must_be_hashable():
    with (
        ContextProvider() as provider,
        pytest.raises(SubscriptionError, match="subscriber must be hashable"),
    ):
        provider.subscribe(print, "/a", subscriber=["not", "hashable"])
