"""Subscribers whose callbacks block (issue 14): once every delivery thread is stuck in one, the
others must still receive (the blocked ones' threads are set aside)."""

from __future__ import annotations

import threading

from lxml import etree

from acordcs.runtime.context.delivery import DeliveryDispatcher, Notification, Subscription
from tests.support.services import wait_for


def note(seq: int) -> Notification:
    return Notification("p", seq, etree.ElementTree(etree.fromstring("<a/>")), [])


def test_blocking_subscribers_do_not_stop_delivery_to_the_others():
    release = threading.Event()
    got: list[int] = []
    dispatcher = DeliveryDispatcher("test", max_threads=4)  # isolate_seconds: 1 s
    blockers = [Subscription(lambda n: release.wait(30), None, None) for _ in range(6)]
    quick = Subscription(lambda n: got.append(n.seq), None, None)
    try:
        for sub in blockers:
            dispatcher.offer(sub, note(1))
        assert wait_for(lambda: dispatcher.threads == 4)  # every thread now blocks
        for seq in range(1, 4):
            dispatcher.offer(quick, note(seq))
        assert wait_for(lambda: got == [1, 2, 3], timeout=10), got
        assert dispatcher.threads <= 4  # the pool stays within max_threads
        assert sum(s.stats.isolated for s in blockers) >= 1
        release.set()
        assert wait_for(lambda: all(s.stats.delivered == 1 for s in blockers), timeout=10)
        dispatcher.offer(quick, note(4))
        assert wait_for(lambda: got == [1, 2, 3, 4])
    finally:
        release.set()
        dispatcher.close()
