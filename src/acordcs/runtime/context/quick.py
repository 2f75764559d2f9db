"""Which subscriptions are quick enough to be delivered in the receiving thread (the MQTT engine's
network thread) instead of a delivery thread: see :class:`QuickJudge`."""

from __future__ import annotations

import logging
import resource
from typing import Any, Protocol

from acordcs.runtime.context.sequences import every_power_of_two

log = logging.getLogger("acordcs.runtime.context")

QUICK_RUNS = 16
"""Quick callbacks in a row, on the delivery threads, before a subscription is delivered inline."""
MAX_QUICK_RUNS = 4096
"""The most quick callbacks asked of a subscription sent back to the threads (doubling each time):
one whose callbacks are slow now and then holds the receiving thread at most once in that many."""

_RUSAGE_THREAD = getattr(resource, "RUSAGE_THREAD", None)  # Linux: this thread's own figures


def thread_waits() -> tuple[int, float]:
    """This thread's voluntary context switches (it slept, waited for I/O, a lock or the GIL) and
    CPU seconds so far; (0, 0.0) where the system does not count them per thread."""
    if _RUSAGE_THREAD is None:
        return 0, 0.0
    usage = resource.getrusage(_RUSAGE_THREAD)
    return usage.ru_nvcsw, usage.ru_utime + usage.ru_stime


class Judged(Protocol):
    """What the judge reads and writes of a subscription (``delivery.Subscription``): its
    mailbox's ``quick``, ``quick_runs`` and ``quick_needed``, its ``stats.demoted``."""

    mailbox: Any
    stats: Any
    max_rate: float | None


class QuickJudge:
    """Keeps, in each subscription's mailbox (``quick``, ``quick_runs``, ``quick_needed``), whether
    its callbacks return within ``seconds``: :data:`QUICK_RUNS` quick ones in a row on the delivery
    threads make it quick; one that held the receiving thread longer sends it back, and it then
    needs twice as many (at most :data:`MAX_QUICK_RUNS`; back to :data:`QUICK_RUNS` after that many
    quick ones inline). The dispatcher calls it under its lock, except :meth:`held`."""

    def __init__(self, seconds: float) -> None:
        self.seconds = seconds
        self.demotions = 0  # for all subscriptions: the log is bounded by it, not per subscription

    def held(self, took: float, before: tuple[int, float]) -> bool:
        """Whether a callback inline that returned after ``took`` s held the thread itself: it
        waited (a voluntary switch: sleep, I/O, a lock, the GIL) or used the CPU for longer than
        ``seconds``; not when the system only ran other work meanwhile (preempted: the thread's
        fate whatever it ran). Where the system counts neither per thread, any late one."""
        if took <= self.seconds:
            return False
        if _RUSAGE_THREAD is None:
            return True
        switches, cpu = thread_waits()
        return switches > before[0] or cpu - before[1] > self.seconds

    def observe(self, sub: Judged, took: float) -> None:
        """A callback of ``sub`` on a delivery thread took ``took`` s: quick ones in a row make it
        quick (never with ``max_rate``, whose waits the threads keep)."""
        box = sub.mailbox
        if took > self.seconds:
            box.quick_runs = 0
        elif not box.quick and sub.max_rate is None:
            box.quick_runs += 1
            if box.quick_runs >= box.quick_needed:
                box.quick, box.quick_runs = True, 0

    def inline_done(self, sub: Judged, took: float, slow: bool) -> None:
        """A callback of ``sub`` ran inline; ``slow``: it held the thread (:meth:`held`)."""
        box = sub.mailbox
        if slow:
            self._demote(sub, took)
        elif box.quick_runs < MAX_QUICK_RUNS:
            box.quick_runs += 1
        else:  # quick for long: an overrun now is taken as rare
            box.quick_needed = QUICK_RUNS

    def _demote(self, sub: Judged, took: float) -> None:
        box = sub.mailbox
        box.quick, box.quick_runs = False, 0
        box.quick_needed = min(2 * box.quick_needed, MAX_QUICK_RUNS)
        sub.stats.demoted += 1
        self.demotions += 1
        if every_power_of_two(self.demotions):
            log.warning(
                "%r: a callback held the receiving thread for %.1f ms (it waited or computed), "
                "over quick_seconds=%g s (%d time(s) for this provider's subscriptions); its "
                "notifications go to the delivery threads until %d callbacks in a row are quick "
                "(always the threads: inline=False)",
                sub,
                took * 1e3,
                self.seconds,
                self.demotions,
                box.quick_needed,
            )
