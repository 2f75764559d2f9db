"""The WebLab sample runs: XMI -> checked model -> descriptor -> containers -> fuzzy and CLIPS policies.

The policies come from the model file alone; the test supplies only what a model cannot (the Recovery
component's operations) and drives the Control monitor as the locomotion interceptor would.
"""

from __future__ import annotations

from typing import ClassVar

import pytest

from acordcs.descriptor import describe
from acordcs.model.reading import read_model
from acordcs.runtime.assembly import assemble
from acordcs.runtime.clock import VirtualClock
from acordcs.runtime.component import CtxComponent
from acordcs.runtime.events import OPERATION_CALLED, Event
from acordcs.runtime.monitor import Monitor
from acordcs.runtime.ports import PortSpec
from tests.support.toolchain import WEBLAB

# Table 1 of the paper: cycles/s -> mean speed in mm/s (residential, campus, LAN).
TABLE_1 = {0.90: 69, 1.46: 127, 1.72: 143}


class Recovery(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"retries": 0, "recoveries": 0}
    ports = (PortSpec("RecoveryLocomotionPort", "synchronous", "required"),)

    def __init__(self) -> None:
        self.calls: list[str] = []

    def recover(self) -> None:
        self.calls.append("recover")

    def askUser(self) -> None:  # the model's operation name
        self.calls.append("askUser")


@pytest.fixture
def weblab():
    reading = read_model(str(WEBLAB))
    assert not reading.diagnostics, [d.format_text() for d in reading.diagnostics]
    monitors: dict[str, Monitor] = {}

    def monitor(name: str, **kw) -> Monitor:
        monitors[name] = Monitor(name, **kw)
        return monitors[name]

    run = assemble(
        describe(reading.architecture),
        clock=VirtualClock(seed=1),
        factories={"Recovery": Recovery},
        monitors={"Control": monitor},
    )
    yield run.container("WebLabSide"), monitors["Control"]
    run.close()


def test_speed_limiting_reproduces_table_1_on_a_straight_path(weblab):
    container, control = weblab
    speeds = {}
    for rate in TABLE_1:
        control.update(cycleRate=rate, angle=5.0, speed=100.0)
        speeds[rate] = container.get_property("Locomotion", "maxSpeed")
    assert speeds[0.90] < speeds[1.46] < speeds[1.72]
    for rate, paper in TABLE_1.items():
        assert abs(speeds[rate] - paper) <= 10, (rate, speeds[rate], paper)


def test_sharper_turns_slow_the_robot_down(weblab):
    container, control = weblab
    limits = []
    for angle in (5.0, 20.0, 45.0, 80.0):
        control.update(cycleRate=1.46, angle=angle, speed=100.0)
        limits.append(container.get_property("Locomotion", "maxSpeed"))
    assert limits == sorted(limits, reverse=True) and limits[0] > limits[-1]


def test_recovering_policy_retries_three_times_then_asks_the_user(weblab):
    container, control = weblab
    recovery = container.find("Recovery").instance
    steps = []
    for speed in (0.0, 0.0, 0.0, 0.0, 0.0, 50.0, 0.0):
        control.update(speed=speed)
        steps.append((list(recovery.calls), container.get_property("Recovery", "retries")))
    assert [calls.count("recover") for calls, _ in steps] == [1, 2, 3, 3, 3, 3, 4]
    assert [calls.count("askUser") for calls, _ in steps] == [0, 0, 0, 1, 1, 1, 1]
    assert [retries for _, retries in steps] == [1, 2, 3, 4, 5, 0, 1]
    assert container.get_property("Recovery", "recoveries") == 1
    assert container.faults.counts["total"] == 0


class Locomotion(CtxComponent):
    properties: ClassVar[dict[str, object]] = {"maxSpeed": 200.0, "wheelBase": 330.0}
    ports = (
        PortSpec("LocomotionPort", "synchronous", "provided"),
        PortSpec("TelemetryPort", "asynchronous", "provided"),
    )

    def move(self, speed: float, turn: float) -> None:
        pass


class ControlMonitor(Monitor):
    """The paper's control monitor: extracts speed and angle from each call to the locomotion
    service (its source is the locomotion port); the cycle rate is given here."""

    def on_event(self, event: Event) -> None:
        if event.kind == OPERATION_CALLED and event.attribute == "move":
            speed, turn = event.data["args"]
            self.update(cycleRate=1.46, angle=abs(turn), speed=speed)


def test_navigator_calls_feed_the_control_monitor_across_colocated_containers():
    # UserSide and WebLabSide in one process: the remote LocomotionLink is in-process, and the
    # Control monitor, sourced by Locomotion.LocomotionPort, sees the navigator's calls.
    reading = read_model(str(WEBLAB))
    with assemble(
        describe(reading.architecture),
        clock=VirtualClock(seed=1),
        factories={"Recovery": Recovery, "Locomotion": Locomotion},
        monitors={"Control": ControlMonitor},
    ) as run:
        lab = run.container("WebLabSide")
        navigator = run.container("UserSide").find("Navigator").instance
        navigator.port("NavLocomotionPort").call("move", 100.0, 5.0)
        assert lab.monitor("Control").attributes == {
            "cycleRate": 1.46,
            "angle": 5.0,
            "speed": 100.0,
        }
        assert abs(lab.get_property("Locomotion", "maxSpeed") - TABLE_1[1.46]) <= 10
        assert lab.faults.counts["total"] == 0
