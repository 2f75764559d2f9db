"""Containers assembled in one process talk in-process whatever their connections' connector says:
a ``remote`` connection between two of them gets an in-process connector (a ``shaped`` one a shaped
link over it); only an end in another process goes over Pyro5."""

from __future__ import annotations

from typing import Any, ClassVar

import pytest

from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.connectors import (
    InProcessConnector,
    RemoteConnector,
    RemotePort,
    ShapedConnector,
)
from acordcs.runtime.errors import BindingError
from acordcs.runtime.ports import async_port, sync_port
from tests.support.descriptors import (
    application,
    component,
    connection,
    container,
    port,
    prop,
    ref,
)


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"speed": 0.0}
    ports = (sync_port("LocomotionPort"), async_port("TelemetryPort"))

    def move(self, speed: float) -> float:
        self.set("speed", speed)
        return speed


class Navigator(CtxComponent):
    ports = (
        sync_port("NavLocomotionPort", role="required"),
        async_port("NavTelemetryPort", role="required"),
    )

    def __init__(self) -> None:
        self.telemetry: list[Any] = []

    def on_NavTelemetryPort(self, message: Any) -> None:
        self.telemetry.append(message)


def weblab(locomotion: str = "remote", telemetry: str = "remote"):
    return application(
        "WebLab",
        containers=(
            container("UserSide", ref("component", "Navigator")),
            container("WebLabSide", ref("component", "Locomotion")),
        ),
        components=(
            component(
                "Locomotion",
                ports=(port("LocomotionPort"), port("TelemetryPort", "asynchronous")),
            ),
            component(
                "Navigator",
                ports=(
                    port("NavLocomotionPort", "synchronous", "required"),
                    port("NavTelemetryPort", "asynchronous", "required"),
                ),
            ),
        ),
        connections=(
            connection(
                "LocomotionLink",
                "Navigator.NavLocomotionPort",
                "Locomotion.LocomotionPort",
                locomotion,
                prop("latency", 0.25),
            ),
            connection(
                "TelemetryLink", "Navigator.NavTelemetryPort", "Locomotion.TelemetryPort", telemetry
            ),
        ),
    )


FACTORIES = {"Locomotion": Locomotion, "Navigator": Navigator}


def test_a_remote_connection_between_colocated_containers_is_in_process():
    with assemble(weblab(), factories=FACTORIES, clock=VirtualClock()) as app:
        user, lab = app.container("UserSide"), app.container("WebLabSide")
        link = user.connection("LocomotionLink")
        assert type(link.connector) is InProcessConnector
        assert link.qos == {"latency": 0.25}  # the model's QoS, still adaptable
        nav = user.find("Navigator").instance
        assert nav.port("NavLocomotionPort").call("move", 120.0) == 120.0
        assert lab.get_property("Locomotion", "speed") == 120.0
        # Both directions: the provider notifies the required end in the other container.
        lab.find("Locomotion").instance.port("TelemetryPort").notify({"x": 1})
        app.clock.run_for(0.1)
        assert nav.telemetry == [{"x": 1}]


def test_a_shaped_connection_between_colocated_containers_is_shaped_in_process():
    with assemble(weblab(locomotion="shaped"), factories=FACTORIES, clock=VirtualClock()) as app:
        link = app.container("UserSide").connection("LocomotionLink")
        assert type(link.connector) is ShapedConnector
        assert type(link.connector.inner) is InProcessConnector
        nav = app.container("UserSide").find("Navigator").instance
        assert nav.port("NavLocomotionPort").call("move", 80.0) == 80.0
        assert app.clock.now() == pytest.approx(0.5)  # the model's latency, there and back


def test_an_end_in_another_process_goes_over_pyro():
    uri = "PYRO:acordcs.container.WebLabSide@127.0.0.1:9"
    for kind, shaped in (("remote", False), ("shaped", True)):
        app = assemble(
            weblab(locomotion=kind),
            factories=FACTORIES,
            only=["UserSide"],
            remote={"WebLabSide": uri},
            remote_timeout=0.5,
            clock=VirtualClock(),
        )
        with app:
            link = app.container("UserSide").connection("LocomotionLink")
            assert link.provided == RemotePort(uri, "Locomotion", "LocomotionPort")
            transport = link.connector.inner if shaped else link.connector
            assert type(link.connector) is (ShapedConnector if shaped else RemoteConnector)
            assert type(transport) is RemoteConnector and transport.timeout == 0.5


def test_an_inprocess_connection_cannot_cross_processes():
    with pytest.raises(BindingError, match=r"'TelemetryLink' is in-process.*'WebLabSide'") as info:
        assemble(
            weblab(telemetry="inprocess"),
            factories=FACTORIES,
            only=["UserSide"],
            remote={"WebLabSide": "PYRO:acordcs.container.WebLabSide@127.0.0.1:9"},
            clock=VirtualClock(),
        )
    assert "connector" in info.value.hint
