"""Time for the runtime: one :class:`Clock` interface, a real-time and a virtual-time implementation.

Monitor frequencies, periodic policy sets, stream rates, sleeps and connector delays all go through a
clock, so the same application runs live (:class:`RealClock`) or simulated (:class:`VirtualClock`, a
discrete-event scheduler that jumps from event to event). Randomness comes from :meth:`Clock.rng`: one
generator per purpose, derived from the clock's seed, so that a component drawing more numbers does not
shift the draws of another and a run is reproducible for a seed.
"""

from __future__ import annotations

import heapq
import itertools
import logging
import threading
import time
import zlib
from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from acordcs.runtime.errors import ConfigurationError

log = logging.getLogger(__name__)


@dataclass(order=True)
class Timer:
    """A scheduled callback; ``cancel()`` it to stop it (a periodic one stops for good)."""

    when: float
    seq: int
    fn: Callable[[], object] = field(compare=False)
    period: float | None = field(default=None, compare=False)
    cancelled: bool = field(default=False, compare=False)

    def cancel(self) -> None:
        self.cancelled = True


def _stream_key(purpose: str | int) -> int:
    # crc32 rather than hash(): str hashes are salted per process, which would break determinism.
    return purpose if isinstance(purpose, int) else zlib.crc32(purpose.encode("utf-8"))


class Clock(ABC):
    """What the runtime needs from time. Times are seconds (floats) since the clock started."""

    def __init__(self, seed: int = 0) -> None:
        self.seed = seed
        self._seq = itertools.count()
        self._rngs: dict[tuple[str | int, ...], np.random.Generator] = {}
        # Called with (timer, exception) when a callback raises; containers install their fault log here.
        self.on_error: Callable[[Timer, BaseException], None] = _log_timer_error

    @abstractmethod
    def now(self) -> float:
        """Implemented by each clock."""

    @abstractmethod
    def sleep(self, seconds: float) -> None:
        """Implemented by each clock."""

    @abstractmethod
    def call_at(self, when: float, fn: Callable[[], object]) -> Timer:
        """Implemented by each clock."""

    real_time: bool = False
    """Whether time passes by itself (a thread runs the timers): code that may block, such as a
    monitor's ``acquire``, then runs off the clock's thread, so it cannot hold the other timers up.
    A virtual clock runs everything in its caller's thread, in order (determinism)."""

    def call_later(self, delay: float, fn: Callable[[], object]) -> Timer:
        """Run ``fn`` once after ``delay`` seconds of this clock's time."""
        if delay < 0:
            raise ConfigurationError(f"delay must be >= 0 seconds, not {delay}")
        return self.call_at(self.now() + delay, fn)

    def call_every(
        self, period: float, fn: Callable[[], object], *, start: float | None = None
    ) -> Timer:
        """Run ``fn`` every ``period`` seconds (first at ``start``, default one period from now).

        Ticks keep a fixed rate: a late tick does not shift the later ones.
        """
        if not period > 0:
            raise ConfigurationError(f"period must be > 0 seconds, not {period}")
        first = self.now() + period if start is None else start
        timer = Timer(first, next(self._seq), fn, period)
        self._schedule(timer)
        return timer

    def rng(self, *purpose: str | int) -> np.random.Generator:
        """The random generator of one purpose (e.g. ``rng("link", "cam->console")``) for this seed."""
        key = tuple(purpose)
        gen = self._rngs.get(key)
        if gen is None:
            gen = np.random.default_rng([self.seed, *(_stream_key(p) for p in key)])
            self._rngs[key] = gen
        return gen

    def close(self) -> None:  # noqa: B027 (a no-op unless the clock holds a thread)
        """Stop scheduling; pending timers are dropped."""

    @abstractmethod
    def _schedule(self, timer: Timer) -> None:
        """Implemented by each clock."""

    def _run_timer(self, timer: Timer) -> None:
        try:
            timer.fn()
        except Exception as exc:
            self.on_error(timer, exc)
        if timer.period is not None and not timer.cancelled:
            timer.when += timer.period
            timer.seq = next(self._seq)
            self._schedule(timer)


def _log_timer_error(timer: Timer, exc: BaseException) -> None:
    log.error("timer callback %r at t=%.6f raised %r; the clock goes on", timer.fn, timer.when, exc)


class VirtualClock(Clock):
    """Discrete-event time: nothing happens until :meth:`run_until` / :meth:`run_for` / :meth:`sleep`.

    Events at the same instant run in the order they were scheduled. The wall clock is never read.
    """

    def __init__(self, seed: int = 0, start: float = 0.0) -> None:
        super().__init__(seed)
        self._now = float(start)
        self._heap: list[Timer] = []
        self._lock = threading.RLock()
        self.events_run = 0

    def now(self) -> float:
        return self._now

    def call_at(self, when: float, fn: Callable[[], object]) -> Timer:
        timer = Timer(max(when, self._now), next(self._seq), fn)
        self._schedule(timer)
        return timer

    def _schedule(self, timer: Timer) -> None:
        with self._lock:
            heapq.heappush(self._heap, timer)

    def pending(self) -> int:
        """Timers still scheduled (cancelled ones excluded)."""
        return sum(1 for t in self._heap if not t.cancelled)

    def step(self) -> bool:
        """Run the next event; False when none is left."""
        with self._lock:
            while self._heap and self._heap[0].cancelled:
                heapq.heappop(self._heap)
            if not self._heap:
                return False
            timer = heapq.heappop(self._heap)
            self._now = max(self._now, timer.when)
            self.events_run += 1
            self._run_timer(timer)
            return True

    def run_until(self, t: float) -> None:
        """Run every event due at or before ``t``, then set the time to ``t``."""
        with self._lock:
            while True:
                while self._heap and self._heap[0].cancelled:
                    heapq.heappop(self._heap)
                if not self._heap or self._heap[0].when > t:
                    break
                self.step()
            self._now = max(self._now, t)

    def run_for(self, seconds: float) -> None:
        self.run_until(self._now + seconds)

    def run(self, max_events: int = 1_000_000) -> int:
        """Run until no event is left (or ``max_events`` ran, against endless periodic timers)."""
        done = 0
        while done < max_events and self.step():
            done += 1
        return done

    def sleep(self, seconds: float) -> None:
        # A sleeping caller lets simulated time pass: every event in the window runs meanwhile, in order.
        if seconds < 0:
            raise ConfigurationError(f"sleep needs seconds >= 0, not {seconds}")
        self.run_until(self._now + seconds)

    def close(self) -> None:
        with self._lock:
            for timer in self._heap:
                timer.cancel()
            self._heap.clear()


class RealClock(Clock):
    """Wall-clock time (monotonic); callbacks run on one scheduler thread, in time order."""

    real_time = True

    def __init__(self, seed: int = 0) -> None:
        super().__init__(seed)
        self._t0 = time.monotonic()
        self._heap: list[Timer] = []
        self._cond = threading.Condition()
        self._closed = False
        self._thread = threading.Thread(target=self._loop, name="acordcs-clock", daemon=True)
        self._thread.start()

    def now(self) -> float:
        return time.monotonic() - self._t0

    def sleep(self, seconds: float) -> None:
        if seconds < 0:
            raise ConfigurationError(f"sleep needs seconds >= 0, not {seconds}")
        time.sleep(seconds)

    def call_at(self, when: float, fn: Callable[[], object]) -> Timer:
        timer = Timer(when, next(self._seq), fn)
        self._schedule(timer)
        return timer

    def _schedule(self, timer: Timer) -> None:
        with self._cond:
            if timer.period is not None and timer.when < self.now() - timer.period:
                # Far behind (the process was stalled): skip the missed ticks instead of bursting them.
                timer.when = self.now()
            heapq.heappush(self._heap, timer)
            self._cond.notify()

    def _loop(self) -> None:
        while True:
            with self._cond:
                while not self._closed:
                    while self._heap and self._heap[0].cancelled:
                        heapq.heappop(self._heap)
                    if self._heap and self._heap[0].when <= self.now():
                        break
                    wait = self._heap[0].when - self.now() if self._heap else None
                    self._cond.wait(wait)
                if self._closed:
                    return
                timer = heapq.heappop(self._heap)
            self._run_timer(timer)

    def close(self) -> None:
        with self._cond:
            self._closed = True
            self._heap.clear()
            self._cond.notify()
        if threading.current_thread() is not self._thread:
            self._thread.join(timeout=5)
