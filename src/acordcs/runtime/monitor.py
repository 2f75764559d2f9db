"""Monitors: acquire contextual information and feed policy sets with it (paper, CtxMonitor).

A monitor's attributes (``cycleRate``, ``numUsers``) are rule variables. A periodic monitor
(``frequency`` in Hz) has :meth:`Monitor.acquire` called at that rate through the container's clock;
an event-driven one (no frequency) has :meth:`Monitor.on_event` called for the events of its sources:
the operation calls and property changes of a component; for a port (``Component.Port``), the calls
through that port, which an interceptor on the port (:class:`PortTap`) hands over as
``operation.called`` events of the port, and its property changes. Either publishes by :meth:`Monitor.update`, which emits one
``monitor.updated`` event: the policy sets it feeds fire on it, even if the values did not change (a
new reading is news).

A raising ``acquire`` or ``on_event`` is a fault: recorded and counted; the monitor keeps its rate.
A periodic monitor whose ``acquire`` raises (a polled operation that timed out: the link to it is
down) keeps its last values and goes *stale*: its container emits one ``monitor.stale`` event (value
True, ``data``: ``cause``, the error, and ``since``, the time of the first failed acquisition),
``stale_since`` says since when, and its next reading emits ``monitor.stale`` again (value False,
``data``: ``stale_for``, seconds) before its ``monitor.updated``. No value is made up for the
policy sets meanwhile: they do not fire on ``monitor.stale`` (a periodic one reads the last values);
a watcher sees both events. A replica of the monitor in another container goes stale with it
(:mod:`acordcs.runtime.assembly`'s feeds).
On a real-time clock, ``acquire`` runs in the monitor's own thread, not the clock's: a monitor
blocking in it skips its own ticks meanwhile (counted in ``overruns``) and holds up no other monitor
or timer; its values are published from the clock's thread, like every other update.
The container attaches a monitor when it is added and detaches it when it is removed.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Iterable, Mapping
from typing import TYPE_CHECKING, Any, ClassVar, Protocol

from acordcs.runtime import events as ev
from acordcs.runtime.errors import ConfigurationError
from acordcs.runtime.events import Event
from acordcs.runtime.interceptors import Interceptor, Invocation

log = logging.getLogger(__name__)

if TYPE_CHECKING:
    from contextlib import AbstractContextManager

    from acordcs.runtime.clock import Clock, Timer
    from acordcs.runtime.component import ComponentRef
    from acordcs.runtime.context.core import ProviderCore
    from acordcs.runtime.events import FaultLog


class MonitorHost(Protocol):
    """What a monitor needs from its container."""

    clock: Clock
    faults: FaultLog

    @property
    def context(self) -> ProviderCore:
        """The context provider (subscribing monitors)."""
        ...

    def find(self, name: str) -> ComponentRef:
        """A hosted component (polling monitors call it)."""
        ...

    def guard(self, kind: str, where: str, **context: object) -> AbstractContextManager[None]:
        """Run monitor code; an exception becomes a recorded fault."""
        ...

    def monitor_update(self, monitor: Monitor, values: dict[str, object]) -> None:
        """Take the new attribute values and emit ``monitor.updated``."""
        ...

    def monitor_stale(self, monitor: Monitor, stale: bool, data: dict[str, object]) -> None:
        """Emit ``monitor.stale`` (``stale``: the monitor's values went stale, or fresh again)."""
        ...


class Monitor:
    """Base class; subclasses override :meth:`acquire` (periodic) or :meth:`on_event` (event-driven).

    ``attribute_defaults`` (a generated monitor base declares the model's attributes there, as a
    component base declares ``properties``) are the attributes of a monitor made without any."""

    attribute_defaults: ClassVar[Mapping[str, object]] = {}

    def __init__(
        self,
        name: str,
        *,
        frequency: float | None = None,
        sources: Iterable[str] = (),
        attributes: Mapping[str, object] | None = None,
    ) -> None:
        if frequency is not None and not frequency > 0:
            raise ConfigurationError(
                f"monitor {name!r}: frequency must be > 0 Hz (or None), not {frequency}"
            )
        self.name = name
        self.frequency = frequency
        self.sources = tuple(sources)
        self.attributes: dict[str, object] = dict(
            self.attribute_defaults if attributes is None else attributes
        )
        self.container: MonitorHost | None = None
        self.ticks = 0
        self.overruns = 0  # ticks skipped while the previous acquire was still running
        self.stale_since: float | None = None  # the time its values went stale (None: fresh)
        self._stale_lock = threading.Lock()
        self._timer: Timer | None = None
        self._busy = threading.Lock()  # held while an acquire runs off the clock's thread

    @property
    def clock(self) -> Clock:
        """The clock of the container the monitor is in (as a component's ``clock``)."""
        if self.container is None:
            raise ConfigurationError(
                f"monitor {self.name!r} has no clock until it is added to a container",
                hint="container.add_monitor(monitor) first",
            )
        return self.container.clock

    @property
    def event_sources(self) -> tuple[str, ...]:
        """The sources whose calls and property changes reach :meth:`on_event` (all of them,
        unless the monitor acquires otherwise: subscribing and polling monitors)."""
        return self.sources

    def acquire(self) -> Mapping[str, object] | None:
        """Read the context; return attribute updates (or call :meth:`update` yourself)."""
        return None

    def on_event(self, event: Event) -> None:
        """React to an event of a source (an operation called on it, a property change)."""

    def update(self, **values: Any) -> None:
        """Publish new attribute values to the policy sets this monitor feeds (a reading: a stale
        monitor is fresh again)."""
        if self.container is None:
            self.attributes.update(values)
            return
        with self._stale_lock:
            since, self.stale_since = self.stale_since, None
        if since is not None:
            self._fresh(self.container, since)
        self.container.monitor_update(self, values)

    def mark_stale(self, cause: str, *, unless: Callable[[], bool] | None = None) -> None:
        """Say that the monitor's values are stale (``cause``: why), once until its next
        reading; its last values are kept. ``unless``: a reading came meanwhile (checked with the
        change, so that a reading from another thread is never taken for stale)."""
        container = self.container
        if container is None:
            return
        with self._stale_lock:
            if self.stale_since is not None or (unless is not None and unless()):
                return
            since = self.stale_since = container.clock.now()
        container.monitor_stale(self, True, {"cause": cause[:500], "since": since})
        # Emitted outside the lock (the container's dispatch takes its own): a reading from
        # another thread may have said fresh before this said stale; if so, fresh again.
        with self._stale_lock:
            overtaken = self.stale_since != since
        if overtaken:
            self._fresh(container, since)

    def _fresh(self, container: MonitorHost, since: float) -> None:
        stale_for = round(container.clock.now() - since, 6)
        container.monitor_stale(self, False, {"stale_for": stale_for})

    # ------------------------------------------------------------------ driven by the container
    def attach(self, container: MonitorHost) -> None:
        """Start publishing to ``container`` (and ticking, for a periodic monitor)."""
        self.container = container
        if self.frequency is not None:
            self._timer = container.clock.call_every(1.0 / self.frequency, self._tick)

    def _tick(self) -> None:
        self.ticks += 1
        container = self.container
        if container is None:
            return
        if not container.clock.real_time:
            self._acquire(container, publish=self._publish)
            return
        if not self._busy.acquire(blocking=False):
            self.overruns += 1
            if self.overruns & (self.overruns - 1) == 0:  # 1st, 2nd, 4th... only
                log.warning(
                    "monitor %r: acquire() still running at tick %d; tick skipped (%d so far)",
                    self.name,
                    self.ticks,
                    self.overruns,
                )
            return
        # A daemon thread per acquisition (at most one at a time per monitor): a blocked acquire
        # never holds up the process's exit, and a quick one costs a thread start (~0.1 ms).
        threading.Thread(
            target=self._acquire_off_clock,
            args=(container,),
            name=f"acordcs-monitor-{self.name}",
            daemon=True,
        ).start()

    def _acquire_off_clock(self, container: MonitorHost) -> None:
        try:
            self._acquire(
                container,
                publish=lambda values: container.clock.call_later(
                    0.0, lambda: self._publish(values)
                ),
            )
        finally:
            self._busy.release()

    def _acquire(
        self, container: MonitorHost, publish: Callable[[Mapping[str, object]], object]
    ) -> None:
        try:
            values = self.acquire()
        except Exception as exc:
            container.faults.record(
                "monitor", self.name, exc, container.clock.now(), tick=self.ticks
            )
            cause = f"{type(exc).__name__}: {exc}"
            if container.clock.real_time:  # marked from the clock's thread, like its readings
                container.clock.call_later(0.0, lambda: self.mark_stale(cause))
            else:
                self.mark_stale(cause)
            return
        if values:
            publish(values)

    def _publish(self, values: Mapping[str, object]) -> None:
        container = self.container
        if container is None:
            return
        try:
            self.update(**values)
        except Exception as exc:
            container.faults.record(
                "monitor", self.name, exc, container.clock.now(), tick=self.ticks
            )

    def detach(self) -> None:
        """Stop ticking and publishing (values published afterwards stay in ``attributes``)."""
        if self._timer is not None:
            self._timer.cancel()
            self._timer = None
        self.container = None


class PortTap(Interceptor):
    """Feeds a monitor the calls through one port: installed by the container on the port's calls
    (``add_interceptor(tap, component=..., port=...)``) for a monitor whose source is that port.

    Each call, once done, becomes an ``operation.called`` event of the port (element
    ``Component.Port``, attribute the operation, value its result; ``data``: ``args``, ``kwargs``,
    ``error``, ``port``, ``component``) handed to ``feed`` (the container's guarded call of the
    monitor's ``on_event``). A call refused by another interceptor never ran and is not fed.
    """

    def __init__(
        self, monitor: str, component: str, port: str, feed: Callable[[Event], None]
    ) -> None:
        self.name = f"monitor:{monitor}@{component}.{port}"
        self.component = component
        self.port = port
        self._feed = feed

    def after(self, call: Invocation) -> None:
        self._feed(
            Event(
                ev.OPERATION_CALLED,
                f"{self.component}.{self.port}",
                call.operation,
                value=call.result,
                time=call.time,
                origin=call.origin,
                data={
                    "args": call.args,
                    "kwargs": call.kwargs,
                    "error": call.error,
                    "port": self.port,
                    "component": self.component,
                },
            )
        )
