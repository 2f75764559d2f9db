"""A variable read only in an action (an operation's argument, an assigned expression) is an input of
the policy set: the engine gets its value before firing (the SmartRoom's ``Hvac.setSetpoint(Hvac.setpoint
- 1)``)."""

from __future__ import annotations

from typing import ClassVar

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.policy import PolicySet


class Hvac(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"setpoint": 21.0, "target": 0.0}

    def setSetpoint(self, celsius: float) -> None:
        self.set("setpoint", celsius)


def test_variables_read_only_in_actions_are_set_before_firing():
    with Container("room", clock=VirtualClock()) as room:
        room.install_factory(ComponentFactory("Hvac", Hvac))
        room.create("Hvac", "Hvac")
        room.add_monitor(Monitor("Presence", attributes={"occupancy": 0}))
        ps = PolicySet(
            "Comfort",
            {
                "rules": [
                    "crowded: if Presence.occupancy > 10 then Hvac.setSetpoint(Hvac.setpoint - 1)",
                    "aim: if Presence.occupancy > 0 then Hvac.target = Hvac.setpoint + 2",
                ]
            },
            engine="clips",
            adapts=["Hvac"],
            fed_by=["Presence"],
        )
        room.add_policy_set(ps)
        assert ps.inputs["Hvac.setpoint"] == ("Hvac", "setpoint")
        # What only actions read does not trigger the set: the conditions say when it fires.
        assert "Hvac.setpoint" not in ps.reads
        room.monitor("Presence").update(occupancy=12)
        assert room.get_property("Hvac", "setpoint") == 20.0
        assert room.get_property("Hvac", "target") == 23.0
        assert room.faults.counts["total"] == 0
