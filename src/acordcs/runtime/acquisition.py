"""The monitor of each acquisition kind of the model (tag ``acquisition`` of ``CtxMonitor``).

- :class:`InterceptingMonitor` (``intercept``): the calls through its source port, or to its source
  component, reach :meth:`~InterceptingMonitor.on_call` once done; the component's property changes
  reach :meth:`~InterceptingMonitor.on_change` (by default a change of a property named like one of
  the monitor's attributes is taken as it is). With ``quiet_after`` (seconds) set, a monitor
  whose sources have seen no call for that long goes stale (``monitor.stale``, its last values
  kept) and :meth:`~InterceptingMonitor.on_quiet` is asked, every quarter of it while the silence
  lasts, what the silence itself says (a rate that falls, say); the next call makes it fresh.
- :class:`SubscribingMonitor` (``subscribe``): the context provider's documents its ``xpath``
  selects something in reach :meth:`~SubscribingMonitor.on_document`; by default the first selected
  element's child elements (or attributes) named like the monitor's attributes are read, each
  converted to its attribute's type.
- :class:`PollingMonitor` (``poll``): its source component's ``operation`` is called at its
  ``frequency`` through the container (interceptors and events see the call), and the result
  reaches :meth:`~PollingMonitor.on_reading` (by default: the value of its only attribute, or, for a
  mapping, the entries named like its attributes).
- ``custom``: a plain :class:`~acordcs.runtime.monitor.Monitor`, your ``acquire`` or ``on_event``.

Each hook returns the attribute values to publish (or None: nothing new); raising is a fault of the
monitor, recorded by its container, and the monitor goes on. Generated applications subclass these.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

from acordcs.runtime import events as ev
from acordcs.runtime.errors import ConfigurationError
from acordcs.runtime.events import Event
from acordcs.runtime.monitor import Monitor, MonitorHost

if TYPE_CHECKING:
    from acordcs.runtime.clock import Timer
    from acordcs.runtime.context.delivery import Notification, Subscription


@dataclass(frozen=True, slots=True)
class ObservedCall:
    """One call an intercepting monitor saw, once done: ``element`` is the component or
    ``Component.Port`` it went through, ``result`` its result (None when it raised: ``error``),
    ``origin`` the policy set whose action made it (None for a component's own call): a monitor of
    the control loop may ignore the adaptation's own calls."""

    element: str
    operation: str
    args: tuple[Any, ...]
    kwargs: Mapping[str, Any]
    result: Any
    error: BaseException | None
    time: float
    origin: str | None = None


class InterceptingMonitor(Monitor):
    """``intercept``: sees the calls through its sources and their components' property changes.

    ``quiet_after``: seconds without a call through its sources after which the monitor is stale
    (None, the default: silence says nothing); counted from the monitor's first call, so a
    source not used yet is not a silence."""

    quiet_after: ClassVar[float | None] = None

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        self.last_call: float | None = None  # the time of the last call seen (None: none yet)
        self._quiet_timer: Timer | None = None

    def on_quiet(self, quiet_for: float) -> Mapping[str, object] | None:
        """No call through the sources for ``quiet_for`` seconds (at least ``quiet_after``): the
        values the silence gives (published, the monitor still stale), or None (the default)."""
        return None

    def attach(self, container: MonitorHost) -> None:
        super().attach(container)
        if self.quiet_after is not None:
            if not self.quiet_after > 0:
                raise ConfigurationError(
                    f"monitor {self.name!r}: quiet_after must be > 0 s, not {self.quiet_after}"
                )
            self._quiet_timer = container.clock.call_every(self.quiet_after / 4, self._listen)

    def detach(self) -> None:
        if self._quiet_timer is not None:
            self._quiet_timer.cancel()
            self._quiet_timer = None
        super().detach()

    def _listen(self) -> None:
        container, last, quiet_after = self.container, self.last_call, self.quiet_after
        if container is None or last is None or quiet_after is None:
            return
        quiet_for = container.clock.now() - last
        if quiet_for < quiet_after:
            return
        self.mark_stale(
            f"no call through {', '.join(self.sources)} for {quiet_for:.1f} s",
            unless=lambda: self.last_call != last,
        )
        if self.last_call != last:  # a call came meanwhile: no silence to read
            return
        with container.guard("monitor", self.name, silence=f"{quiet_for:.1f} s"):
            values = self.on_quiet(quiet_for)
            if values:
                container.monitor_update(self, dict(values))

    def on_call(self, call: ObservedCall) -> Mapping[str, object] | None:
        """A call went through a source: return the attribute values it gives (or None)."""
        return None

    def on_change(self, attribute: str, value: object) -> Mapping[str, object] | None:
        """A source's property changed: by default taken when the monitor has that attribute."""
        return {attribute: value} if attribute in self.attributes else None

    def on_event(self, event: Event) -> None:
        if event.kind == ev.OPERATION_CALLED:
            self.last_call = event.time
            data = event.data
            values = self.on_call(
                ObservedCall(
                    event.element,
                    event.attribute or "",
                    tuple(data.get("args") or ()),
                    dict(data.get("kwargs") or {}),
                    event.value,
                    data.get("error"),  # type: ignore[arg-type]
                    event.time,
                    event.origin,
                )
            )
        elif event.kind == ev.PROPERTY_CHANGED and event.attribute is not None:
            values = self.on_change(event.attribute, event.value)
        else:
            return
        if values:
            self.update(**values)


class SubscribingMonitor(Monitor):
    """``subscribe``: reads the context provider's documents that ``xpath`` selects something in."""

    def __init__(self, name: str, *, xpath: str, **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        if not isinstance(xpath, str) or not xpath.strip():
            raise ConfigurationError(
                f"monitor {name!r}: a subscribing monitor needs an xpath (tag xpath of the model)"
            )
        self.xpath = xpath
        self.documents = 0  # documents seen
        self._subscription: Subscription | None = None

    @property
    def event_sources(self) -> tuple[str, ...]:
        return ()  # its documents come from the context provider, not from calls

    def on_document(self, note: Notification) -> Mapping[str, object] | None:
        """A document matched: by default the first selected element's children (or attributes)
        named like the monitor's attributes, converted to their types. A value that does not
        convert is a fault; the others are still taken."""
        element = next((n for n in note.nodes if isinstance(getattr(n, "tag", None), str)), None)
        if element is None:
            return None
        values: dict[str, object] = {}
        bad: list[str] = []
        for name, current in self.attributes.items():
            child = element.find(name)
            text = child.text if child is not None else element.get(name)
            if text is None and element.tag == name:
                text = element.text
            if text is None:
                continue
            try:
                values[name] = convert(text, current)
            except ValueError:
                bad.append(f"{name}={text[:40]!r}")
        if bad:
            if values:
                self.update(**values)
            raise ValueError(
                f"document {note.seq} of {note.publisher!r}: {', '.join(bad)} not of the "
                "attribute's type (the other values were taken)"
            )
        return values or None

    def attach(self, container: MonitorHost) -> None:
        super().attach(container)
        provider = container.context

        def take(note: Notification) -> None:
            host = self.container
            if host is None:
                return
            self.documents += 1
            with host.guard("monitor", self.name, document=f"{note.publisher} #{note.seq}"):
                values = self.on_document(note)
                if values:
                    self.update(**values)

        if provider.inline:
            callback = take
        else:  # a delivery thread: hand the document to the clock's thread

            def callback(note: Notification) -> None:
                container.clock.call_later(0.0, lambda: take(note))

        self._subscription = provider.subscribe(callback, self.xpath)

    def detach(self) -> None:
        container, sub = self.container, self._subscription
        self._subscription = None
        if container is not None and sub is not None:
            container.context.unsubscribe(sub)
        super().detach()


class PollingMonitor(Monitor):
    """``poll``: calls ``operation`` of its source component at ``frequency`` Hz."""

    def __init__(self, name: str, *, operation: str, **kwargs: Any) -> None:
        super().__init__(name, **kwargs)
        if not kwargs.get("frequency"):
            raise ConfigurationError(f"monitor {name!r}: a polling monitor needs a frequency > 0")
        components = [s for s in self.sources if "." not in s]
        if len(components) != 1 or not operation:
            raise ConfigurationError(
                f"monitor {name!r}: a polling monitor needs one source component and an operation "
                f"(has sources {list(self.sources)}, operation {operation!r})"
            )
        self.component = components[0]
        self.operation = operation

    @property
    def event_sources(self) -> tuple[str, ...]:
        return ()  # it asks; it does not listen

    def on_reading(self, value: object) -> Mapping[str, object] | None:
        """The polled operation returned ``value``: the attribute values it gives."""
        if isinstance(value, Mapping):
            return {
                k: convert(v, self.attributes[k]) for k, v in value.items() if k in self.attributes
            }
        if len(self.attributes) == 1:
            ((name, current),) = self.attributes.items()
            return {name: convert(value, current)}
        raise ConfigurationError(
            f"monitor {self.name!r} has {len(self.attributes)} attributes and polled "
            f"{self.component}.{self.operation}() returned one value: override on_reading"
        )

    def acquire(self) -> Mapping[str, object] | None:
        container = self.container
        if container is None:
            return None
        return self.on_reading(container.find(self.component).call(self.operation))


def convert(value: object, like: object) -> object:
    """``value`` as the type of the attribute's current value ``like`` (bool, int, float, str)."""
    if isinstance(like, bool):
        if isinstance(value, bool):
            return value
        text = str(value).strip().lower()
        if text in ("true", "1"):
            return True
        if text in ("false", "0"):
            return False
        raise ValueError(f"not a boolean: {value!r}")
    if isinstance(like, int):
        if isinstance(value, bool):
            raise ValueError(f"not an integer: {value!r}")
        if isinstance(value, int):
            return value
        return int(str(value).strip())
    if isinstance(like, float):
        if isinstance(value, bool):
            raise ValueError(f"not a number: {value!r}")
        number = float(value) if isinstance(value, int | float) else float(str(value).strip())
        if number != number or number in (float("inf"), float("-inf")):
            raise ValueError(f"not a finite number: {value!r}")
        return number
    return value if isinstance(value, str) or like is None else str(value)


MONITOR_KINDS: dict[str, type[Monitor]] = {
    "intercept": InterceptingMonitor,
    "subscribe": SubscribingMonitor,
    "poll": PollingMonitor,
    "custom": Monitor,
}
"""The monitor class of each acquisition kind (the descriptor's ``acquisition``)."""
