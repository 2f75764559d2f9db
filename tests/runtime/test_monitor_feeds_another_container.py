"""A monitor feeding a policy set of another container: its readings are delivered there. The policy
set's container holds a replica of the monitor (same name and attributes, so the rules bind), updated
with each reading: directly when both containers run in this process, over Pyro5 when the policy
set's container is given by ``remote=``; with neither, the readings are not delivered, and the
assembly says so (a warning and ``app.feeds``)."""

from __future__ import annotations

import logging
from typing import ClassVar

from acordcs.runtime.assembly import Feed, assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from tests.support.descriptors import (
    application,
    component,
    container,
    monitor,
    policy_set,
    prop,
    ref,
)
from tests.support.services import wait_for


class Lights(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"dimmer": 0}


def room():
    return application(
        "SmartRoom",
        containers=(
            container("Sensors", ref("monitor", "Presence")),
            container("Room", ref("component", "Lights"), ref("policy-set", "Lighting")),
        ),
        components=(component("Lights", properties=(prop("dimmer", 0),)),),
        monitors=(monitor("Presence", prop("occupancy", 0), feeds=("Lighting",)),),
        policy_sets=(
            policy_set(
                "Lighting",
                {"rules": ["if Presence.occupancy > 0 then Lights.dimmer = 80"]},
                adapts=(ref("component", "Lights"),),
            ),
        ),
    )


def test_in_one_process_readings_reach_the_other_container():
    with assemble(room(), clock=VirtualClock()) as app:
        sensors, lights = app.container("Sensors"), app.container("Room")
        assert app.feeds == (Feed("Presence", "Sensors", "Lighting", "Room", "in-process"),)
        assert lights.policy_set("Lighting").fed_by == ("Presence",)
        sensors.monitor("Presence").update(occupancy=3)
        assert lights.monitor("Presence").attributes == {"occupancy": 3}
        assert lights.get_property("Lights", "dimmer") == 80
        assert sensors.faults.counts["total"] == lights.faults.counts["total"] == 0


def test_across_processes_readings_go_over_pyro_to_the_served_container():
    with assemble(room(), only=["Room"], clock=VirtualClock()) as here:
        assert here.feeds == (Feed("Presence", "Sensors", "Lighting", "Room", "replica"),)
        server = here.serve("Room", host="127.0.0.1")
        with assemble(room(), only=["Sensors"], remote={"Room": server.uri}) as there:
            assert there.feeds == (Feed("Presence", "Sensors", "Lighting", "Room", "remote"),)
            there.container("Sensors").monitor("Presence").update(occupancy=2)
        assert here.container("Room").get_property("Lights", "dimmer") == 80


def test_readings_with_nowhere_to_go_are_reported(caplog):
    with caplog.at_level(logging.WARNING), assemble(room(), only=["Sensors"]) as app:
        assert app.feeds == (Feed("Presence", "Sensors", "Lighting", "Room", "undelivered"),)
        app.container("Sensors").monitor("Presence").update(occupancy=2)
    (record,) = [r for r in caplog.records if "Presence" in r.getMessage()]
    assert record.levelno == logging.WARNING
    assert (
        "monitor 'Presence' feeds policy set 'Lighting' of container 'Room'" in record.getMessage()
    )
    assert "remote={'Room': uri}" in record.getMessage()


def test_an_unreachable_container_is_a_fault_of_the_feed_not_of_the_monitor():
    uri = "PYRO:acordcs.container.Room@127.0.0.1:9"  # nothing listens there
    with assemble(room(), only=["Sensors"], remote={"Room": uri}, remote_timeout=0.5) as app:
        sensors = app.container("Sensors")
        sensors.monitor("Presence").update(occupancy=2)
        assert sensors.monitor("Presence").attributes == {"occupancy": 2}
        # sent by the connector's thread (the monitor does not wait): the fault follows
        assert wait_for(lambda: sensors.faults.of_kind("listener"), 10)
        (fault,) = sensors.faults.of_kind("listener")
        assert fault.where == "feed:Presence->Room" and "RemoteUnreachableError" in fault.error


def stale_marks(container) -> list[tuple[bool, object]]:
    """The ``monitor.stale`` events of the replica of Presence in ``container``: (value, cause)."""
    seen: list[tuple[bool, object]] = []
    container.subscribe(
        "monitor.stale",
        lambda e: seen.append((e.value, e.data.get("cause"))),
        name="test:stale",
        element="Presence",
    )
    return seen


WENT_STALE = "monitor 'Presence' of container 'Sensors' went stale: the sensor bus timed out"


def test_in_one_process_a_stale_monitor_makes_its_replica_stale_until_its_next_reading():
    with assemble(room(), clock=VirtualClock()) as app:
        sensors, lights = app.container("Sensors"), app.container("Room")
        seen = stale_marks(lights)
        sensors.monitor("Presence").mark_stale("the sensor bus timed out")
        assert seen == [(True, WENT_STALE)]
        assert lights.monitor("Presence").stale_since is not None
        sensors.monitor("Presence").update(occupancy=1)
        assert [value for value, _ in seen] == [True, False]
        assert lights.monitor("Presence").stale_since is None
        assert lights.get_property("Lights", "dimmer") == 80


def test_across_processes_the_stale_mark_travels_in_order_with_the_readings():
    with assemble(room(), only=["Room"], clock=VirtualClock()) as here:
        lights = here.container("Room")
        seen = stale_marks(lights)
        server = here.serve("Room", host="127.0.0.1")
        with assemble(room(), only=["Sensors"], remote={"Room": server.uri}) as there:
            presence = there.container("Sensors").monitor("Presence")
            presence.mark_stale("the sensor bus timed out")
            assert wait_for(lambda: seen == [(True, WENT_STALE)]), seen
            assert lights.monitor("Presence").stale_since is not None
            presence.update(occupancy=2)
            assert wait_for(lambda: [value for value, _ in seen] == [True, False]), seen
            assert there.container("Sensors").faults.counts["total"] == 0
        assert lights.monitor("Presence").stale_since is None
        assert lights.get_property("Lights", "dimmer") == 80
        assert lights.faults.counts["total"] == 0
