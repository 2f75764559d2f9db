"""Operation calls into hosted components, through the interceptors (paper, Figure 2).

Mixed into :class:`~acordcs.runtime.container.Container`. Every way into a component goes through
:meth:`OperationCalls._invoke`: a handle's call, a call arriving at a provided port (local or remote), a
notification or stream item delivered to a handler, a stream source ticking. A component that raises
is a fault (recorded, counted); the caller still gets an error, since request-reply needs an answer.
"""

from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, Any

from acordcs.runtime import events as ev
from acordcs.runtime.errors import (
    CallVetoed,
    ComponentDestroyedError,
    ComponentError,
    PortError,
    RuntimeFailure,
)
from acordcs.runtime.interceptors import Interceptor, InterceptorEntry, Invocation

if TYPE_CHECKING:
    from acordcs.runtime.clock import Clock
    from acordcs.runtime.component import Hosted
    from acordcs.runtime.dispatch import EventDispatcher
    from acordcs.runtime.events import FaultLog
    from acordcs.runtime.ports import Port, PortOwner


class OperationCalls:
    """The calls and the interceptors of a container.

    The container this is mixed into keeps the attributes declared below, and provides
    ``_hosted(name, lineage)`` (the record of a live component, or the error saying why there is
    none), ``guard`` and ``emit``.
    """

    name: str
    clock: Clock
    faults: FaultLog
    stats: Counter[str]
    _where: str
    _components: dict[str, Hosted]
    _events: EventDispatcher

    def __init__(self) -> None:
        self._interceptors: list[InterceptorEntry] = []

    def invoke(
        self,
        name: str,
        operation: str,
        args: tuple[Any, ...] = (),
        kwargs: dict[str, Any] | None = None,
        *,
        lineage: int | None = None,
    ) -> Any:
        """Call an operation of a hosted component, through the interceptors."""
        hosted = self._hosted(name, lineage)
        return self._invoke(hosted, operation, args, kwargs or {}, None)

    def invoke_port(
        self, port: Port, operation: str, args: tuple[Any, ...], kwargs: dict[str, Any]
    ) -> Any:
        """A call arriving at a synchronous provided port (from a connector)."""
        if port.kind != "synchronous" or port.role != "provided":
            raise PortError(
                f"calls arrive at synchronous provided ports; {port.qualified_name} is "
                f"{port.kind}/{port.role}",
                where=self._where,
            )
        ops = port.spec.operations
        if ops is not None and operation not in ops:
            raise PortError(
                f"port {port.qualified_name} does not expose {operation!r} (exposes: {', '.join(ops)})",
                where=self._where,
            )
        if not port.component.alive:
            raise ComponentDestroyedError(
                f"component {port.component.name!r} behind port {port.name!r} was destroyed",
                where=self._where,
                hint="reconnect the port to a live component",
            )
        return self._invoke(self._hosted(port.component.name), operation, args, kwargs, port.name)

    def invoke_internal(
        self, instance: PortOwner, method: str, args: tuple[Any, ...], port: Port
    ) -> Any:
        """A delivery into a component (notification handler, stream source/sink), intercepted."""
        hosted = self._components.get(instance.name)
        if hosted is None or hosted.instance is not instance:
            return None
        return self._invoke(hosted, method, args, {}, port.name)

    def _invoke(
        self,
        hosted: Hosted,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
        port: str | None,
    ) -> Any:
        hosted.gate.enter()  # waits while the component is being replaced, then runs on the new one
        try:
            return self._invoke_entered(hosted, operation, args, kwargs, port)
        finally:
            hosted.gate.leave()

    def _invoke_entered(
        self,
        hosted: Hosted,
        operation: str,
        args: tuple[Any, ...],
        kwargs: dict[str, Any],
        port: str | None,
    ) -> Any:
        instance = hosted.instance
        name = instance.name
        if operation not in hosted.operations:
            raise ComponentError(
                f"component {name!r} ({type(instance).__name__}) has no operation {operation!r} "
                f"(operations: {', '.join(sorted(hosted.operations)) or 'none'})",
                where=self._where,
            )
        self.stats["calls"] += 1
        type_name = instance.factory.type_name
        interceptors = self._interceptors
        # none installed (the usual case): not even the comprehension's own frame
        entries = (
            [e for e in interceptors if e.matches(name, type_name, operation, port)]
            if interceptors
            else []
        )
        if not entries and not self._events.wants(ev.OPERATION_CALLED):
            # nobody intercepts or watches this call: no Invocation to make (the remote
            # endpoint's calls mostly take this path), the same fault record and error
            try:
                return getattr(instance, operation)(*args, **kwargs)
            except Exception as exc:
                self.faults.record(
                    "component", f"{name}.{operation}", exc, self.clock.now(), args=args
                )
                if isinstance(exc, RuntimeFailure):
                    raise  # already says what and where (see _failure)
                raise self._failure(name, operation, exc) from exc
        call = Invocation(
            self.name,
            name,
            type_name,
            operation,
            args,
            kwargs,
            self.clock.now(),
            port,
            origin=self.origin,  # type: ignore[attr-defined]  (the container's, see Container)
        )
        for entry in entries:
            try:
                entry.interceptor.before(call)
            except CallVetoed:
                self.stats["vetoed"] += 1
                raise
            except Exception as exc:
                self.faults.record(
                    "interceptor",
                    entry.label,
                    exc,
                    call.time,
                    phase="before",
                    call=f"{name}.{operation}",
                )
        try:
            call.result = getattr(instance, operation)(*call.args, **call.kwargs)
        except Exception as exc:
            call.error = exc
            self.faults.record(
                "component", f"{name}.{operation}", exc, self.clock.now(), args=call.args
            )
        for entry in entries:
            with self.guard("interceptor", entry.label, phase="after", call=f"{name}.{operation}"):
                entry.interceptor.after(call)
        if self._events.wants(ev.OPERATION_CALLED):
            self.emit(
                ev.OPERATION_CALLED,
                name,
                operation,
                value=call.result,
                data={"args": call.args, "kwargs": call.kwargs, "error": call.error, "port": port},
            )
        if call.error is not None:
            err = call.error
            if isinstance(err, RuntimeFailure):
                raise err
            raise self._failure(name, operation, err) from err
        return call.result

    def _failure(self, name: str, operation: str, err: Exception) -> ComponentError:
        """What a call that raised ``err`` raises to its caller, unless ``err`` is a
        ``RuntimeFailure``: that already says what and where (a port not connected, a remote
        timeout) and is passed on as it is."""
        return ComponentError(
            f"component {name!r} raised {type(err).__name__} in {operation}(): {err}",
            where=self._where,
            hint="the fault is recorded in container.faults; the container goes on",
        )

    # ------------------------------------------------------------------------- interceptors
    def add_interceptor(
        self,
        interceptor: Interceptor,
        *,
        component: str | None = None,
        type_name: str | None = None,
        operation: str | None = None,
        port: str | None = None,
    ) -> None:
        """Intercept the calls matching every given filter (none given: all calls); ``port``: the
        calls arriving through that port of the component (a provided port's calls, the deliveries
        to a port's handler, a stream source's ticks)."""
        self._interceptors.append(
            InterceptorEntry(interceptor, component, type_name, operation, port)
        )

    def interceptors(self, component: str | None = None) -> list[Interceptor]:
        """The interceptors installed (those filtered on ``component``, when given)."""
        return [
            e.interceptor
            for e in self._interceptors
            if component is None or e.component == component
        ]

    def remove_interceptor(self, interceptor: Interceptor) -> None:
        self._interceptors = [e for e in self._interceptors if e.interceptor is not interceptor]
