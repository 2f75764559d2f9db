"""``hold`` on a container's management interface (what the WebLab console does to pause the
Navigator of the other process while a viewer drives): a call from another process into the held
component waits until the hold is released, then runs; calls made in the container itself are
never held; a held call waits no longer than its patience (a share of the remote-call timeout),
so its caller gets an answer before it times out; a hold nobody renews ends by itself; what
cannot be held is refused with the reason."""

from __future__ import annotations

import threading
from typing import Any

import pytest

from acordcs.descriptor import to_xml
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.connectors.remote import RemoteConnector, container_uri
from acordcs.runtime.errors import RemoteCallError
from acordcs.runtime.live.apply_update import GivenClasses
from acordcs.runtime.live.management import HOLD_PATIENCE
from acordcs.runtime.live.management_server import MANAGE_OBJECT, manage
from acordcs.runtime.ports import sync_port
from tests.support.descriptors import application, component, container, op, port, ref
from tests.support.services import wait_for

TOKEN = "token-of-the-lab"


class Camera(CtxComponent):
    ports = (sync_port("CameraPort"),)

    def grab(self) -> str:
        return "frame"


class Lamp(CtxComponent):
    """A component that provides no operation: no call to it can be held."""


def lab():
    return application(
        "Lab",
        containers=(container("lab", ref("component", "Camera"), ref("component", "Lamp")),),
        components=(
            component(
                "Camera", operations=(op("grab", returns="string"),), ports=(port("CameraPort"),)
            ),
            component("Lamp"),
        ),
    )


@pytest.fixture
def served(monkeypatch):
    monkeypatch.delenv("ACORDCS_TOKEN", raising=False)
    app = lab()
    run = assemble(app, clock=VirtualClock(), factories={"Camera": Camera, "Lamp": Lamp},
                   token=TOKEN)  # fmt: skip
    server = run.serve("lab", host="127.0.0.1")
    management = manage(run, "lab", server, to_xml(app), GivenClasses({"Camera": Camera, "Lamp": Lamp}),
                        timeout=2.0)  # fmt: skip
    yield (
        run,
        management,
        f"PYRO:{MANAGE_OBJECT.format('lab')}@127.0.0.1:{server.port}",
        container_uri("lab", "127.0.0.1", server.port),
    )
    management.close()
    run.close()


def ask(uri: str, method: str, *args: Any, timeout: float = 10.0) -> Any:
    connector = RemoteConnector(timeout=timeout, token=TOKEN)
    try:
        return connector.request(uri, method, *args, where="test")
    finally:
        connector.close()


def grab_in_a_thread(uri: str) -> tuple[threading.Thread, list]:
    got: list = []
    caller = threading.Thread(
        target=lambda: got.append(ask(uri, "call", "Camera", "CameraPort", "grab", [], {}))
    )
    caller.start()
    return caller, got


def test_a_remote_call_waits_while_held_and_runs_once_released(served):
    run, management, manage_uri, lab_uri = served
    held = ask(manage_uri, "hold", "Camera", 30.0)
    assert held["component"] == "Camera" and 29.0 < held["left"] <= 30.0
    assert held["patience"] == pytest.approx(HOLD_PATIENCE * 2.0) and held["waiting"] == 0
    caller, got = grab_in_a_thread(lab_uri)
    assert wait_for(lambda: management.hold("Camera", 30.0)["waiting"] == 1)
    assert not got  # it waits
    # A call made in the container itself is not held.
    assert run.container("lab").find("Camera").call("grab") == "frame"
    released = ask(manage_uri, "release", "Camera")
    assert released["held"] is True
    caller.join(10)
    assert got == ["frame"]
    assert ask(manage_uri, "release", "Camera")["held"] is False
    assert ask(lab_uri, "call", "Camera", "CameraPort", "grab", [], {}) == "frame"


def test_a_held_call_goes_on_after_its_patience_and_the_hold_stays(served):
    _run, management, manage_uri, lab_uri = served
    ask(manage_uri, "hold", "Camera", 60.0)
    # Its patience (0.75 of the container's 2 s timeout) is shorter than the caller's timeout.
    connector = RemoteConnector(timeout=2.0, token=TOKEN)
    try:
        assert connector.request(lab_uri, "call", "Camera", "CameraPort", "grab", [], {},
                                 where="test") == "frame"  # fmt: skip
    finally:
        connector.close()
    assert management.hold("Camera", 60.0)["left"] > 50.0


def test_a_hold_nobody_renews_ends_by_itself(served):
    _run, management, manage_uri, lab_uri = served
    ask(manage_uri, "hold", "Camera", 0.3)
    assert ask(lab_uri, "call", "Camera", "CameraPort", "grab", [], {}) == "frame"
    assert management.hold("Camera", 0.01)["waiting"] == 0


@pytest.mark.parametrize(
    ("args", "says"),
    [
        (("Heater", 5.0), "container 'lab' hosts no component 'Heater' (it hosts: Camera, Lamp)"),
        (("Lamp", 5.0), "component 'Lamp' of container 'lab' provides no operation, so no call"),
        (("Camera", 0), "a hold lasts more than 0 and at most 60 seconds"),
        (("Camera", 61), "a hold lasts more than 0 and at most 60 seconds"),
        (("Camera", float("nan")), "seconds is a finite number"),
        (("Camera", True), "hold(component name, seconds)"),
        ((3, 5.0), "hold(component name, seconds)"),
    ],
)
def test_what_cannot_be_held_is_refused_with_the_reason(served, args, says):
    _run, _management, manage_uri, _ = served
    with pytest.raises(RemoteCallError) as refused:
        ask(manage_uri, "hold", *args)
    assert says in str(refused.value)


def test_a_hold_starting_and_ending_is_told_to_the_watchers_at_once(served):
    _run, management, _uri, _endpoint = served
    observer = management.observer
    watch = observer.watch([], False)

    def told() -> list[tuple[str, object]]:
        events = observer.poll(watch["watch"], watch["after"], 0.0)["events"]
        return [(e["kind"], e["value"]) for e in events if e["kind"].startswith("component.")]

    management.hold("Camera", 5.0)
    management.hold("Camera", 5.0)  # a renewal while it lasts: no new hold
    management.release("Camera")
    management.hold("Camera", 0.2)  # nobody renews it: it expires
    assert wait_for(lambda: ("component.released", "expired") in told(), timeout=5.0), told()
    kinds = told()
    assert [k for k, _ in kinds] == ["component.held", "component.released"] * 2, kinds
    assert kinds[1] == ("component.released", "released")
    assert 4.0 < float(kinds[0][1]) <= 5.0  # the seconds the hold had left when it started
