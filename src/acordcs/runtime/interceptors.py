"""Interceptors: hooks before and after operation calls of hosted components (paper, Figure 2).

Uses: logging, security (an interceptor may refuse a call by raising :class:`CallVetoed`), resource
accounting, and monitors that watch calls (the WebLab's control monitor: a monitor whose source is a
port is fed by an interceptor on that port's calls, :class:`~acordcs.runtime.monitor.PortTap`). Any other exception an
interceptor raises is a fault: recorded, and the call goes on as if the interceptor were absent.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any


@dataclass(slots=True)
class Invocation:
    """One intercepted call. ``before`` may replace ``args``/``kwargs``; ``after`` sees the outcome."""

    container: str
    component: str
    type_name: str
    operation: str
    args: tuple[Any, ...]
    kwargs: dict[str, Any]
    time: float
    port: str | None = None
    result: Any = None
    error: BaseException | None = None
    notes: dict[str, Any] = field(default_factory=dict)
    origin: str | None = None  # the policy set (or monitor) acting when the call was made, if any


class Interceptor:
    """Override :meth:`before` and/or :meth:`after`. ``name`` identifies it in fault reports."""

    name: str = ""

    def before(self, call: Invocation) -> None:
        """Runs before the operation; raise CallVetoed to refuse it."""

    def after(self, call: Invocation) -> None:
        """Runs after the operation (also when it raised: ``call.error``)."""


@dataclass(slots=True)
class InterceptorEntry:
    interceptor: Interceptor
    component: str | None = None
    type_name: str | None = None
    operation: str | None = None
    port: str | None = None

    def matches(self, component: str, type_name: str, operation: str, port: str | None) -> bool:
        return (
            (self.component is None or self.component == component)
            and (self.type_name is None or self.type_name == type_name)
            and (self.operation is None or self.operation == operation)
            and (self.port is None or self.port == port)
        )

    @property
    def label(self) -> str:
        return self.interceptor.name or type(self.interceptor).__name__
