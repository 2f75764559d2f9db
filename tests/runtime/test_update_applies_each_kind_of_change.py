"""Each kind of change an update applies live, on a small application in one process: a monitor's
frequency (replaced, its attributes' values kept), a connection's QoS default, a component whose
operations change (replaced by its new class, its state and connections kept), a container
property added, a connection's connector changed (reconnected), a monitor feeding a policy set of
another container (its replica there, its readings relayed)."""

from __future__ import annotations

from acordcs.descriptor.diff import diff
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.live.apply_update import GivenClasses, apply_part, container_order
from tests.support.descriptors import (
    application,
    component,
    connection,
    container,
    monitor,
    op,
    policy_set,
    port,
    prop,
    ref,
)

ALARM = (
    'calm: if office.zone == "dry" then office.zone = "A"',
    'dry: if Soil.moisture < 0.2 then office.zone = "dry"',
)


def plant(
    *,
    frequency: float = 1.0,
    latency: float = 0.0,
    ops: tuple = (op("water"),),
    extra: bool = False,
    connector: str = "inprocess",
    feeds: tuple[str, ...] = (),
):
    return application(
        "Plant",
        containers=(
            container(
                "greenhouse",
                ref("component", "Pump"),
                ref("component", "Valve"),
                ref("monitor", "Soil"),
                properties=(prop("zone", "A"), *((prop("season", "spring"),) if extra else ())),
            ),
            container("office", ref("policy-set", "Alarm"), properties=(prop("zone", "A"),)),
        ),
        components=(
            component(
                "Pump",
                properties=(prop("litres", 0),),
                operations=ops,
                ports=(port("out", "synchronous", "required"),),
            ),
            component("Valve", operations=(op("open"),), ports=(port("in"),)),
        ),
        connections=(
            connection("Pipe", "Pump.out", "Valve.in", connector, prop("latency", latency)),
        ),
        monitors=(monitor("Soil", prop("moisture", 0.5), frequency=frequency, feeds=feeds),),
        policy_sets=(
            policy_set(
                "Alarm",
                {"rules": [ALARM[1] if feeds else ALARM[0]]},
                adapts=(ref("container", "office"),),
            ),
        ),
    )


def update(run, old, new, **more):
    plan = diff(old, new)
    outcomes = {}
    for name in container_order(new, list(run.containers), plan.changes):
        outcomes[name] = apply_part(run, name, old, new, plan.part(name),
                                    classes=GivenClasses(), touched=lambda e, a: False, **more)  # fmt: skip
    return plan, outcomes


def test_monitor_connection_component_and_container_changes():
    old = plant()
    new = plant(frequency=4.0, latency=0.2, ops=(op("water"), op("drain")), extra=True)
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("greenhouse")
        soil = house.monitor("Soil")
        soil.update(moisture=0.7)
        house.set_property("Pump", "litres", 12)
        pump = house.find("Pump")
        plan, _ = update(run, old, new)
        assert set(plan.lines) == {
            "~ container greenhouse: property season added",
            "~ component Pump: operation drain() added",
            "~ connection Pipe: qos latency: default 0 -> 0.2",
            "~ monitor Soil: frequency 1 Hz -> 4 Hz",
        }
        assert house.properties == {"zone": "A", "season": "spring"}
        assert house.connection("Pipe").qos["latency"] == 0.2
        # the monitor: a new one at 4 Hz, with the value its predecessor had
        now = house.monitor("Soil")
        assert now is not soil and now.frequency == 4.0 and now.attributes["moisture"] == 0.7
        assert soil.container is None
        run.clock.run_for(1.0)
        assert now.ticks == 4
        # the component: its new class (drain), its state and connection kept, its handle follows
        assert "drain" in house.operations_of("Pump") and pump.alive
        assert house.get_property("Pump", "litres") == 12
        assert house.port_of("Pump", "out").connections[0].name == "Pipe"


def test_a_connector_changed_is_a_reconnection():
    old, new = plant(), plant(connector="shaped")
    with assemble(old, clock=VirtualClock()) as run:
        house = run.container("greenhouse")
        before = house.connection("Pipe")
        plan, _ = update(run, old, new)
        assert plan.lines == ("~ connection Pipe: connector inprocess -> shaped",)
        after = house.connection("Pipe")
        assert after is not before and type(after.connector).__name__ == "ShapedConnector"


def test_a_monitor_feeding_another_container_gets_a_replica_there():
    old, new = plant(), plant(feeds=("Alarm",))
    with assemble(old, clock=VirtualClock()) as run:
        house, office = run.container("greenhouse"), run.container("office")
        assert "Soil" not in office.monitors()
        plan, outcomes = update(run, old, new)
        assert "~ monitor Soil: feeds (none) -> Alarm" in plan.lines
        assert list(outcomes) == ["office", "greenhouse"]  # the receiver first
        assert "Soil" in office.monitors()
        house.monitor("Soil").update(moisture=0.1)  # relayed to the replica: the alarm fires
        assert office.get_property("office", "zone") == "dry"
        update(run, new, old)  # and back: the replica goes, readings stay home
        assert "Soil" not in office.monitors() and house.monitors() == ["Soil"]
        house.monitor("Soil").update(moisture=0.1)
        assert not house.faults.counts["total"] and not office.faults.counts["total"]
