"""Supporting services as components: access service (with its security interceptor) and QoS broker."""

from __future__ import annotations

import pytest

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory
from acordcs.runtime.connectors.shaping import ShapedConnector
from acordcs.runtime.container import Container
from acordcs.runtime.errors import CallVetoed
from tests.support.components import Camera, Counter, Screen
from tests.support.runtime_services import AccessService, QoSBroker, SessionGuard


@pytest.fixture
def lab():
    clock = VirtualClock(seed=4)
    container = Container("weblab", clock=clock)
    for name, cls in (
        ("Access", AccessService),
        ("Broker", QoSBroker),
        ("Counter", Counter),
        ("Camera", Camera),
        ("Screen", Screen),
    ):
        container.install_factory(ComponentFactory(name, cls))
    container.create("Access", "Access")
    yield container
    container.close()


def test_reservations_authentication_and_user_count(lab):
    access = lab.find("Access")
    ann = access.reserve("ann", "stripe", 10.0, 20.0)
    bob = access.reserve("bob", "stripe", 15.0, 30.0)
    assert ann["ok"] and bob["ok"]
    assert access.reserve("ann", "stripe", 12.0, 13.0) == {
        "ok": False,
        "reason": "ann already holds an overlapping reservation",
    }
    assert access.authenticate("ann", ann["token"]) is None  # not her slot yet
    lab.clock.run_until(16.0)
    assert access.authenticate("ann", "forged") is None
    s1 = access.authenticate("ann", ann["token"])
    s2 = access.authenticate("bob", bob["token"])
    assert s1 and s2
    assert access.get("users") == 2
    assert access.users_of("stripe") == 2
    lab.clock.run_until(21.0)  # ann's slot ended: her session expires by itself
    assert access.get("users") == 1
    access.logout(s2)
    assert access.get("users") == 0


def test_experiment_capacity_is_enforced(lab):
    access = lab.find("Access")
    lab.set_property("Access", "max_users", 1)
    assert access.reserve("ann", "stripe", 0.0, 10.0)["ok"]
    assert access.reserve("bob", "stripe", 5.0, 8.0) == {
        "ok": False,
        "reason": "experiment stripe is fully booked then",
    }
    assert access.reserve("bob", "arm", 5.0, 8.0)["ok"]


def test_session_guard_vetoes_calls_without_a_valid_session(lab):
    robot = lab.create("Counter", "robot")
    lab.add_interceptor(SessionGuard(lab, access="Access"), component="robot")
    with pytest.raises(CallVetoed, match=r"robot.bump\(\) refused: no session given"):
        robot.bump()
    access = lab.find("Access")
    token = access.reserve("ann", "stripe", 0.0, 5.0)["token"]
    session = access.authenticate("ann", token)
    assert robot.bump(session=session) == 1
    lab.clock.run_until(6.0)
    with pytest.raises(CallVetoed, match="session not valid now"):
        robot.bump(session=session)


def test_access_state_survives_replacement(lab):
    access = lab.find("Access")
    token = access.reserve("ann", "stripe", 0.0, 5.0)["token"]
    session = access.authenticate("ann", token)
    lab.replace("Access", "Access")
    assert access.valid(session)
    assert access.get("users") == 1


def test_qos_broker_grants_bandwidth_per_connection(lab):
    lab.create("Broker", "broker", properties={"capacity": 1_000_000.0})
    for name in ("cam1", "cam2"):
        lab.create("Camera", name)
        lab.create("Screen", f"{name}-view")
        lab.connect(
            f"{name}-view.video",
            f"{name}.video",
            name=f"{name}-link",
            connector=ShapedConnector(lab.clock),
        )
    broker = lab.find("broker")
    assert broker.request("cam1-link", 600_000.0) == 600_000.0
    assert broker.request("cam2-link", 600_000.0) == 400_000.0  # what is left
    assert lab.get_property("cam1-link", "bandwidth") == 600_000.0
    assert lab.get_property("cam2-link", "bandwidth") == 400_000.0
    assert broker.get("allocated") == 1_000_000.0
    # A policy halving the capacity scales every grant down.
    lab.set_property("broker", "capacity", 500_000.0)
    assert lab.get_property("cam1-link", "bandwidth") == pytest.approx(300_000.0)
    assert lab.get_property("cam2-link", "bandwidth") == pytest.approx(200_000.0)
    broker.release("cam1-link")
    assert broker.allocations() == {"cam2-link": pytest.approx(200_000.0)}
