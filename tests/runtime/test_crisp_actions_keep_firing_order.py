"""A crisp set's records run in firing order: assignments first, then the operations its rules
call. An operation that changes a property the same firing assigned (the WebLab's
``Recovery.askUser`` resetting the ``retries`` the count rule raised) wrote it last: the set's
write-back does not undo it."""

from __future__ import annotations

from typing import ClassVar

from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import ComponentFactory, CtxComponent
from acordcs.runtime.container import Container
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.policy import PolicySet

RULES = [
    # as the WebLab's Recovering set: count every stop, recover three times, then ask the user
    "count: if Control.speed == 0 then Recovery.retries = Recovery.retries + 1",
    "retry: if Control.speed == 0 and Recovery.retries <= 3 then Recovery.recover()",
    "giveUp: if Control.speed == 0 and Recovery.retries == 4 then Recovery.askUser()",
]


class Recovery(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"retries": 0}
    recovered = 0
    asked = 0

    def recover(self) -> None:
        self.recovered += 1

    def askUser(self) -> None:
        self.asked += 1
        self.set("retries", 0)  # the user put the robot back: counting starts again


def test_an_operation_called_after_an_assignment_keeps_its_write():
    with Container("lab", clock=VirtualClock()) as lab:
        lab.install_factory(ComponentFactory("Recovery", Recovery))
        lab.create("Recovery", "Recovery")
        lab.add_monitor(Monitor("Control", attributes={"speed": 1.0}))
        lab.add_policy_set(
            PolicySet(
                "Recovering",
                {"rules": RULES},
                engine="clips",
                adapts=["Recovery"],
                fed_by=["Control"],
            )
        )
        recovery = lab.find("Recovery").instance
        steps = []
        for _ in range(6):
            lab.monitor("Control").update(speed=0.0)  # the control stops the robot
            steps.append(
                (recovery.recovered, recovery.asked, lab.get_property("Recovery", "retries"))
            )
        # the fourth stop asks the user, whose reset stands: the fifth recovers again
        assert steps == [(1, 0, 1), (2, 0, 2), (3, 0, 3), (3, 1, 0), (4, 1, 1), (5, 1, 2)]
        assert lab.faults.counts["total"] == 0


def test_an_assignment_alone_is_written_back():
    with Container("lab", clock=VirtualClock()) as lab:
        lab.install_factory(ComponentFactory("Recovery", Recovery))
        lab.create("Recovery", "Recovery")
        lab.add_monitor(Monitor("Control", attributes={"speed": 1.0}))
        lab.add_policy_set(
            PolicySet(
                "Count",
                {"rules": [RULES[0]]},
                engine="clips",
                adapts=["Recovery"],
                fed_by=["Control"],
            )
        )
        for _ in range(3):
            lab.monitor("Control").update(speed=0.0)
        assert lab.get_property("Recovery", "retries") == 3
