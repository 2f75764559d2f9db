"""The remote endpoint of a container is public: ``container_uri`` names it as the descriptor's
``Endpoint`` does, ``ContainerServer`` publishes it, and ``RunningApplication.serve`` serves an
assembled container there, so two processes of one application find each other."""

from __future__ import annotations

from typing import ClassVar

from acordcs.descriptor.application import Endpoint
from acordcs.runtime.api import Container, ContainerServer, container_uri
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.ports import sync_port
from tests.support.descriptors import application, component, connection, container, port, ref


def test_container_uri_is_the_descriptors_endpoint():
    uri = container_uri("WebLabSide", "weblab.example.org", 9090)
    assert uri == "PYRO:acordcs.container.WebLabSide@weblab.example.org:9090"
    endpoint = Endpoint("pyro", "acordcs.container.WebLabSide", "weblab.example.org")
    assert endpoint.uri(9090) == uri


def test_a_container_server_publishes_the_container_uri():
    with Container("box", clock=VirtualClock()) as box, ContainerServer(box) as server:
        assert server.uri == container_uri("box", server.host, server.port)


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (sync_port("LocomotionPort"),)

    def move(self, speed: float) -> float:
        self.set("speed", speed)
        return speed


def weblab():
    return application(
        "WebLab",
        containers=(
            container("UserSide", ref("component", "Navigator")),
            container("WebLabSide", ref("component", "Locomotion")),
        ),
        components=(
            component("Locomotion", ports=(port("LocomotionPort"),)),
            component("Navigator", ports=(port("NavPort", "synchronous", "required"),)),
        ),
        connections=(
            connection(
                "LocomotionLink", "Navigator.NavPort", "Locomotion.LocomotionPort", "remote"
            ),
        ),
    )


def test_an_assembled_container_served_at_its_endpoint_is_reached_by_another_assembly():
    with assemble(
        weblab(), only=["WebLabSide"], factories={"Locomotion": Locomotion}, clock=VirtualClock()
    ) as lab:
        server = lab.serve("WebLabSide", host="127.0.0.1")
        assert server.uri == container_uri("WebLabSide", "127.0.0.1", server.port)
        assert lab.servers == {"WebLabSide": server}
        with assemble(
            weblab(), only=["UserSide"], remote={"WebLabSide": server.uri}, remote_timeout=5.0
        ) as user:
            nav = user.container("UserSide").find("Navigator").instance
            assert nav.port("NavPort").call("move", 42.0) == 42.0
        assert lab.container("WebLabSide").get_property("Locomotion", "speed") == 42.0
    assert lab.servers == {}  # closed with the application


def test_assemble_token_is_required_by_serve_and_presented_to_remote(monkeypatch):
    import pytest

    from acordcs.runtime.errors import RemoteUnreachableError

    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    with assemble(
        weblab(),
        only=["WebLabSide"],
        factories={"Locomotion": Locomotion},
        clock=VirtualClock(),
        token="lab-token",
    ) as lab:
        server = lab.serve("WebLabSide", host="127.0.0.1")
        with assemble(
            weblab(), only=["UserSide"], remote={"WebLabSide": server.uri}, token="lab-token"
        ) as user:
            nav = user.container("UserSide").find("Navigator").instance
            assert nav.port("NavPort").call("move", 7.0) == 7.0
        with assemble(weblab(), only=["UserSide"], remote={"WebLabSide": server.uri}) as stranger:
            nav = stranger.container("UserSide").find("Navigator").instance
            with pytest.raises(RemoteUnreachableError, match="wrong or missing token"):
                nav.port("NavPort").call("move", 9.0)
        assert lab.container("WebLabSide").get_property("Locomotion", "speed") == 7.0
