"""The endpoint remembers where a short-form target (``"component.port.operation"``) leads, for the
next calls to it (issue 33), and that memory never outlives what it found: a replaced component's
calls reach the new instance with what the new type exposes, a destroyed component's calls get the
errors they got before it was remembered, and a re-created one is found again."""

from __future__ import annotations

import pytest

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from acordcs.runtime.errors import RemoteCallError
from acordcs.runtime.ports import sync_port


class ArmV1(CtxComponent):
    ports = (sync_port("control"),)

    def reach(self, x: int) -> str:
        return f"v1 {x}"

    def park(self) -> str:
        return "parked"


class ArmV2(CtxComponent):
    ports = (sync_port("control", operations=("reach",)),)

    def reach(self, x: int) -> str:
        return f"v2 {x}"

    def park(self) -> str:
        return "parked by v2"


class Caller(CtxComponent):
    ports = (sync_port("out", role="required"),)


@pytest.fixture
def lab():
    container = Container("lab")
    container.install_factory(ComponentFactory("ArmV1", ArmV1))
    container.install_factory(ComponentFactory("ArmV2", ArmV2))
    container.create("ArmV1", "arm")
    server = ContainerServer(container)
    client = Container("user")
    client.install_factory(ComponentFactory("Caller", Caller))
    client.create("Caller", "caller")
    client.connect(
        "caller.out", RemotePort(server.uri, "arm", "control"), connector=RemoteConnector()
    )
    yield container, client.find("caller").instance.port("out")
    client.close()
    server.close()
    container.close()


def test_a_replaced_component_is_reached_with_what_its_new_type_exposes(lab):
    container, out = lab
    assert [out.call("reach", 1), out.call("reach", 2)] == ["v1 1", "v1 2"]
    assert [out.call("park"), out.call("park")] == ["parked", "parked"]
    container.replace("arm", "ArmV2")
    assert out.call("reach", 3) == "v2 3"
    with pytest.raises(RemoteCallError, match="does not expose 'park'"):
        out.call("park")


def test_a_destroyed_component_is_not_called_and_a_new_one_is_found(lab):
    container, out = lab
    assert out.call("reach", 1) == "v1 1"
    container.destroy("arm")
    with pytest.raises(RemoteCallError, match="no component named 'arm'"):
        out.call("reach", 2)
    container.create("ArmV2", "arm")
    assert out.call("reach", 4) == "v2 4"
