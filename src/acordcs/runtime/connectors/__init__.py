"""Connectors realise port connections: in-process, remote (Pyro5) and shaped (emulated network)."""

from acordcs.runtime.connectors.base import Connection, Connector
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.inprocess import InProcessConnector
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort, container_uri
from acordcs.runtime.connectors.shaping import ShapedConnector

__all__ = [
    "Connection",
    "Connector",
    "ContainerServer",
    "InProcessConnector",
    "RemoteConnector",
    "RemotePort",
    "ShapedConnector",
    "container_uri",
]
