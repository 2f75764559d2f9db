"""Errors the runtime raises to its callers: each says what went wrong, where, and what to do.

They are :class:`~acordcs.errors.AcordError` s, so the CLI shows them without a traceback; the location is
the container (``container 'robot'``) instead of an input file. Their base
:class:`~acordcs.errors.RuntimeFailure` and :class:`~acordcs.errors.ConfigurationError` are
defined beside :class:`~acordcs.errors.AcordError`, and the engines' :class:`BindingError` and
:class:`EngineNotAvailableError` in :mod:`acordcs.engines.errors`, because the engines raise them
too; all four are importable from here, the runtime's one module of errors.
"""

from __future__ import annotations

from acordcs.engines.errors import BindingError, EngineNotAvailableError
from acordcs.errors import ConfigurationError, RuntimeFailure


class RemoteNotGivenError(BindingError):
    """A connection's other end runs in a container that is not built in this process, and no
    address was given for it (``remote=`` of ``assemble``, ``--remote NAME=URI`` of a container)."""


class FactoryError(RuntimeFailure):
    """A component type that is not installed, installed twice, or a factory that cannot build."""


class ComponentNotFoundError(RuntimeFailure):
    """No component (or element) of that name in the container."""


class ComponentDestroyedError(RuntimeFailure):
    """A call through a handle whose component was destroyed."""


class ComponentError(RuntimeFailure):
    """A component's operation raised; the original exception is ``__cause__``."""


class OperationNotImplementedError(RuntimeFailure, NotImplementedError):
    """An operation the model declares but no code implements (a component assembled without a
    factory): install a factory for the component. Also a NotImplementedError."""


class CallVetoed(RuntimeFailure):
    """Raised on purpose by an interceptor (security, admission) to refuse a call; reaches the caller.

    Any other exception from an interceptor is a fault: it is isolated and the call goes on.
    """


class PortError(RuntimeFailure):
    """Unknown port, a port of the wrong kind or role, or a port that is not connected."""


class QueueFullError(PortError):
    """An asynchronous port whose bounded queue is full, with the ``reject`` overflow policy."""


class ConnectorError(RuntimeFailure):
    """A connector could not deliver: message lost on a shaped link, call timed out in simulated time."""


class RemoteCallError(ConnectorError):
    """A remote (Pyro5) call that failed in transport or whose remote component raised."""


class RemoteTimeoutError(RemoteCallError):
    """No reply within the connector's timeout, or the connection dropped mid-call.

    The outcome is unknown: the remote operation may or may not have run. It is never retried
    automatically, because operations need not be idempotent.
    """


class RemoteUnreachableError(RemoteCallError):
    """The remote container could not be reached: the call was not sent."""


__all__ = [
    "BindingError",
    "CallVetoed",
    "ComponentDestroyedError",
    "ComponentError",
    "ComponentNotFoundError",
    "ConfigurationError",
    "ConnectorError",
    "EngineNotAvailableError",
    "FactoryError",
    "OperationNotImplementedError",
    "PortError",
    "QueueFullError",
    "RemoteCallError",
    "RemoteNotGivenError",
    "RemoteTimeoutError",
    "RemoteUnreachableError",
    "RuntimeFailure",
]
