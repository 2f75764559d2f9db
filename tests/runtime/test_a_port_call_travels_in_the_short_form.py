"""A call through the remote connector travels as ``invoke("component.port.operation", *args,
**kwargs)`` (issue 33: a bare Pyro5 call's shape, fewer values to serialise), and that form keeps
every guarantee of the long ``call``: the token at the handshake, serpent only, the port's
exposed operations, faults as our errors saying where; names with a dot still get through."""

from __future__ import annotations

from typing import Any

import Pyro5.api
import Pyro5.errors
import pytest

from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.connectors.endpoint import ContainerServer
from acordcs.runtime.connectors.remote import RemoteConnector, RemotePort
from acordcs.runtime.container import Container
from acordcs.runtime.errors import RemoteCallError, RemoteUnreachableError
from acordcs.runtime.ports import async_port, sync_port

TOKEN = "token-of-the-short-form"


class Arm(CtxComponent):
    ports = (
        sync_port("control"),
        sync_port("admin", operations=("status",)),
        sync_port("v1.control"),
        async_port("events"),
    )

    def reach(self, x: float, unit: str = "cm") -> str:
        return f"{x}{unit}"

    def frame(self, data: bytes) -> bytes:
        return data[::-1]

    def status(self) -> str:
        return "ok"

    def jam(self) -> None:
        raise RuntimeError("the arm is jammed")

    def on_events(self, message: Any) -> None:
        pass


class Caller(CtxComponent):
    ports = (sync_port("out", role="required"), sync_port("old", role="required"))


@pytest.fixture(scope="module")
def served():
    container = Container("lab")
    container.install_factory(ComponentFactory("Arm", Arm))
    container.create("Arm", "lab.arm")  # a component name with a dot
    server = ContainerServer(container, token=TOKEN, handshake_timeout=1.0)
    client = Container("user")
    client.install_factory(ComponentFactory("Caller", Caller))
    client.create("Caller", "caller")
    connector = RemoteConnector(timeout=3.0, token=TOKEN)
    client.connect("caller.out", RemotePort(server.uri, "lab.arm", "control"), connector=connector)
    client.connect(
        "caller.old", RemotePort(server.uri, "lab.arm", "v1.control"), connector=connector
    )
    yield container, server, client
    client.close()
    server.close()
    container.close()


def proxy_to(server: ContainerServer, *, token: str | None = TOKEN, serializer: str = "serpent"):
    proxy = Pyro5.api.Proxy(server.uri)
    proxy._pyroSerializer = serializer
    proxy._pyroTimeout = 3.0
    if token is not None:
        proxy._pyroHandshake = token
    return proxy


def test_a_port_call_carries_arguments_keywords_and_bytes(served):
    _, _, client = served
    out = client.find("caller").instance.port("out")
    assert out.call("reach", 3) == "3cm"
    assert out.call("reach", 3, unit="mm") == "3mm"
    assert out.call("reach", x=2.5, unit="m") == "2.5m"
    assert out.call("frame", b"\x00\x01\xff") == b"\xff\x01\x00"


def test_the_short_form_is_the_long_form_in_fewer_values(served):
    _, server, _ = served
    with proxy_to(server) as proxy:
        assert proxy.invoke("lab.arm.control.reach", 4, unit="mm") == "4mm"
        assert proxy.call("lab.arm", "control", "reach", [4], {"unit": "mm"}) == "4mm"


def test_a_port_name_with_a_dot_goes_in_the_long_form(served):
    _, _, client = served
    assert client.find("caller").instance.port("old").call("reach", 1, unit="in") == "1in"


def test_the_short_form_calls_only_what_the_port_exposes(served):
    container, server, _ = served
    with proxy_to(server) as proxy:
        for target, refused in (
            ("lab.arm.control.on_events", "does not expose 'on_events'"),
            ("lab.arm.admin.reach", "does not expose 'reach'"),
            ("lab.arm.nosuch.reach", "has no port 'nosuch'"),
            ("control.reach", "'component.port.operation'"),
            (7, "'component.port.operation'"),
        ):
            with pytest.raises(Exception, match=refused) as caught:
                proxy.invoke(target, "forged")
            assert type(caught.value).__name__ == "RemoteFault"
        assert proxy.invoke("lab.arm.admin.status") == "ok"
    assert container.faults.counts["total"] == 0


def test_a_remote_failure_comes_back_as_our_error_naming_the_connection(served):
    _, _, client = served
    with pytest.raises(RemoteCallError, match="the arm is jammed") as caught:
        client.find("caller").instance.port("out").call("jam")
    assert "caller.out" in str(caught.value) and "lab.arm.control@" in str(caught.value)


def test_the_short_form_needs_the_token_and_serpent(served):
    _, server, _ = served
    for wrong in (None, "guess"):
        with (
            proxy_to(server, token=wrong) as proxy,
            pytest.raises(Pyro5.errors.CommunicationError, match="wrong or missing token"),
        ):
            proxy.invoke("lab.arm.control.reach", 1)
    with (
        proxy_to(server, serializer="marshal") as proxy,
        pytest.raises(Pyro5.errors.SecurityError, match="serpent serializer only"),
    ):
        proxy.invoke("lab.arm.control.reach", 1)
    connector = RemoteConnector(timeout=3.0, token="guess")
    user = Container("stranger")
    try:
        user.install_factory(ComponentFactory("Caller", Caller))
        user.create("Caller", "caller")
        user.connect(
            "caller.out", RemotePort(server.uri, "lab.arm", "control"), connector=connector
        )
        with pytest.raises(RemoteUnreachableError, match="wrong or missing token") as caught:
            user.find("caller").instance.port("out").call("reach", 1)
        assert "caller.out" in str(caught.value)
    finally:
        user.close()
        connector.close()


def test_a_remembered_target_turns_bytes_back_and_fails_as_the_first_call_did(served):
    # The endpoint's remembered targets take a path of their own from the second call on.
    # (Last in the module: its faults would count in the test above that expects none.)
    out = served[2].find("caller").instance.port("out")
    for _ in range(3):
        assert out.call("frame", b"\x00\x01\xff") == b"\xff\x01\x00"
        assert out.call("reach", {"encoding": "utf-8"}, unit="") == "{'encoding': 'utf-8'}"
        assert out.call("reach", [b"\x07"], unit="") == "[{'data': 'Bw==', 'encoding': 'base64'}]"
        with pytest.raises(RemoteCallError, match=r"remote ComponentError: .*the arm is jammed"):
            out.call("jam")
