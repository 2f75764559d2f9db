"""A container served at a port another process uses, or at an address that is not this machine's
(what a wrong host in the model or the settings gives), is a ConfigurationError naming the
container, host and port and what to do, not a traceback. Nothing is sent anywhere: binding to an
address that is not local fails before any packet (192.0.2.1 is TEST-NET-1, never assigned)."""

from __future__ import annotations

import socket

import pytest

from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.container import Container
from acordcs.runtime.errors import ConfigurationError


def test_a_port_in_use_names_the_container_host_and_port() -> None:
    with socket.socket() as taken, Container("box") as container:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        with pytest.raises(ConfigurationError) as caught:
            ContainerServer(container, port=port, token="t" * 32)
    message = str(caught.value)
    assert f"container 'box' cannot serve at 127.0.0.1:{port}: Address already in use" in message
    assert f"another process uses port {port}" in message


def test_an_address_of_another_machine_says_to_give_this_ones() -> None:
    with Container("box") as container, pytest.raises(ConfigurationError) as caught:
        ContainerServer(container, host="192.0.2.1", port=0, token="t" * 32)
    message = str(caught.value)
    assert "container 'box' cannot serve at 192.0.2.1:0" in message
    assert "'192.0.2.1' is not a name or address of this machine" in message
