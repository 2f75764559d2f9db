"""One import for the runtime API: ``from acordcs.runtime.api import Container, CtxComponent, ...``.

Start with :class:`Container` (docs/runtime.md walks through an example).
"""

from typing import TYPE_CHECKING

from acordcs.engines.engine_registry import EngineSetup, Variable, register_engine
from acordcs.runtime.acquisition import (
    InterceptingMonitor,
    ObservedCall,
    PollingMonitor,
    SubscribingMonitor,
)
from acordcs.runtime.assembly import RunningApplication, assemble
from acordcs.runtime.clock import Clock, RealClock, VirtualClock
from acordcs.runtime.component import ComponentFactory, ComponentRef, CtxComponent, ModelProperty
from acordcs.runtime.connectors import (
    Connection,
    Connector,
    ContainerServer,
    InProcessConnector,
    RemoteConnector,
    RemotePort,
    ShapedConnector,
    container_uri,
)
from acordcs.runtime.container import Container
from acordcs.runtime.events import Event, Fault
from acordcs.runtime.interceptors import Interceptor, Invocation
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.operations import unimplemented
from acordcs.runtime.policy import PolicySet
from acordcs.runtime.ports import PortSpec, async_port, stream_port, sync_port

if TYPE_CHECKING:  # for annotations: importing the context provider loads lxml, which this does not
    from acordcs.runtime.context.core import ProviderCore as ProviderCore

__all__ = [
    "Clock",
    "ComponentFactory",
    "ComponentRef",
    "Connection",
    "Connector",
    "Container",
    "ContainerServer",
    "CtxComponent",
    "EngineSetup",
    "Event",
    "Fault",
    "InProcessConnector",
    "InterceptingMonitor",
    "Interceptor",
    "Invocation",
    "ModelProperty",
    "Monitor",
    "ObservedCall",
    "PolicySet",
    "PollingMonitor",
    "PortSpec",
    "RealClock",
    "RemoteConnector",
    "RemotePort",
    "RunningApplication",
    "ShapedConnector",
    "SubscribingMonitor",
    "Variable",
    "VirtualClock",
    "assemble",
    "async_port",
    "container_uri",
    "register_engine",
    "stream_port",
    "sync_port",
    "unimplemented",
]
