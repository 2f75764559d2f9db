"""Quick subscriptions are delivered in the receiving thread; a slow one goes back to the delivery
threads after one overrun, its order kept, and does not hold the receiving thread again."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
from lxml import etree

from acordcs.runtime.context import MqttContextProvider, Notification
from acordcs.runtime.context.delivery import DeliveryDispatcher, Subscription
from acordcs.runtime.context.quick import QUICK_RUNS
from tests.support.services import Broker, wait_for

DOCUMENT = etree.ElementTree(etree.fromstring(b"<r/>"))


class Recorder:
    """Records the sequence number and the thread of each notification; ``slow_at``: the
    sequence numbers whose callback sleeps ``pause`` s (longer than the quick limit)."""

    def __init__(self, slow_at: tuple[int, ...] = (), pause: float = 0.05) -> None:
        self.seen: list[tuple[int, str]] = []
        self.slow_at, self.pause = slow_at, pause
        self.lock = threading.Lock()

    def __call__(self, note: Notification) -> None:
        if note.seq in self.slow_at:
            time.sleep(self.pause)
        with self.lock:
            self.seen.append((note.seq, threading.current_thread().name))

    def count(self) -> int:
        with self.lock:
            return len(self.seen)


def receive(dispatcher: DeliveryDispatcher, sub: Subscription, first: int, last: int) -> None:
    """What the MQTT engine does per document: offer (may inline), then flush in this thread;
    one at a time, as paho's network thread receives them."""
    for seq in range(first, last + 1):
        count = sub.stats.delivered
        dispatcher.offer(sub, Notification("p", seq, DOCUMENT, []), may_inline=True)
        dispatcher.flush()
        assert wait_for(lambda c=count: sub.stats.delivered > c, timeout=10)


@pytest.fixture
def dispatcher():
    made = DeliveryDispatcher(quick_seconds=0.01)
    yield made
    made.close()


def test_a_quick_subscription_moves_into_the_receiving_thread(dispatcher) -> None:
    recorder = Recorder()
    sub = Subscription(recorder, None, None)
    receive(dispatcher, sub, 1, QUICK_RUNS + 10)
    me = threading.current_thread().name
    threads = [name for _, name in recorder.seen]
    assert me not in threads[:QUICK_RUNS]  # observed on the delivery threads first
    assert threads[QUICK_RUNS:] == [me] * 10
    assert sub.stats.inline == 10 and sub.stats.delivered == QUICK_RUNS + 10


def test_an_overrun_sends_it_back_to_the_threads_in_order(dispatcher) -> None:
    slow = QUICK_RUNS + 3
    recorder = Recorder(slow_at=(slow,))
    sub = Subscription(recorder, None, None)
    receive(dispatcher, sub, 1, slow + 5)
    me = threading.current_thread().name
    assert [seq for seq, _ in recorder.seen] == list(range(1, slow + 6))
    assert recorder.seen[slow - 1][1] == me  # the overrun itself ran inline, once
    assert all(name != me for _, name in recorder.seen[slow:])
    assert sub.stats.demoted == 1
    assert sub.mailbox.quick_needed == 2 * QUICK_RUNS


def test_a_callback_busy_on_the_cpu_is_sent_back_too(dispatcher) -> None:
    """Not only one that sleeps: one that computes for longer than quick_seconds (CPU time, so
    the test does not depend on how busy the host is)."""
    busy_at = QUICK_RUNS + 2

    def compute(note: Notification) -> None:
        if note.seq == busy_at:
            end = time.thread_time() + 0.03
            while time.thread_time() < end:
                pass

    sub = Subscription(compute, None, None)
    receive(dispatcher, sub, 1, busy_at + 2)
    assert sub.stats.demoted == 1 and not sub.mailbox.quick


def test_documents_offered_during_an_inline_callback_wait_in_the_mailbox(dispatcher) -> None:
    """Offers while an inline delivery is pending (another receiving thread) queue behind it."""
    recorder = Recorder()
    sub = Subscription(recorder, None, None)
    receive(dispatcher, sub, 1, QUICK_RUNS)
    assert sub.mailbox.quick
    dispatcher.offer(sub, Notification("p", 100, DOCUMENT, []), may_inline=True)
    other = threading.Thread(
        target=dispatcher.offer, args=(sub, Notification("p", 101, DOCUMENT, []), True)
    )
    other.start()
    other.join()
    dispatcher.flush()
    assert wait_for(lambda: recorder.count() == QUICK_RUNS + 2, timeout=10)
    assert [seq for seq, _ in recorder.seen[-2:]] == [100, 101]


def test_max_rate_subscriptions_stay_on_the_threads(dispatcher) -> None:
    recorder = Recorder()
    sub = Subscription(recorder, None, None, max_rate=10_000.0)
    receive(dispatcher, sub, 1, QUICK_RUNS + 5)
    assert sub.stats.inline == 0 and not sub.mailbox.quick


@pytest.mark.service
def test_a_blocked_subscriber_does_not_stop_another_on_the_same_mqtt_client(
    tmp_path: Path,
) -> None:
    broker = Broker(tmp_path)
    broker.start()
    release = threading.Event()
    blocked_once = threading.Event()
    try:
        with (
            MqttContextProvider("127.0.0.1", broker.port) as publisher,
            MqttContextProvider("127.0.0.1", broker.port, mirror=False) as subscriber,
        ):
            quick, stuck = Recorder(), Recorder()
            block_at = QUICK_RUNS + 5

            def blocking(note: Notification) -> None:
                stuck(note)
                if note.seq == block_at:
                    blocked_once.set()
                    time.sleep(0.05)  # over quick_seconds: back to the threads
                elif note.seq > block_at:
                    release.wait(30)  # now it blocks for good, on a delivery thread

            fast = subscriber.subscribe(quick, "/r", "a")
            slow = subscriber.subscribe(blocking, "/r", "a")
            total = block_at + 40
            for seq in range(1, total + 1):
                publisher.publish("a", "<r/>")
                # one at a time: no backlog, so the quick subscription goes inline
                wait_for(lambda n=seq: quick.count() >= n, timeout=10)
            assert wait_for(lambda: quick.count() == total, timeout=20)
            assert blocked_once.is_set() and slow.stats.demoted == 1
            assert fast.stats.inline > 0 and fast.stats.demoted == 0
            assert [seq for seq, _ in quick.seen] == list(range(1, total + 1))
            assert subscriber.stats()["lost"] == 0
            release.set()
    finally:
        release.set()
        broker.stop()
