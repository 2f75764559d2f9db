"""The WebLab's monitors and policies on scripted inputs, in the application generated from
``weblab.xmi`` with the WebLab's own code (its user classes), both containers in one process: the
Navigator's port calls at a scripted rate feed the Control monitor, whose cycle rate and angle the
SpeedLimiting policy turns into the speed limit of Table 1; stops make the Recovering policy
recover three times, then ask the user, and a recovery counts only once the telemetry shows the
robot ahead of where it lost the stripe; the Usage monitor's poll and the BandwidthLimiting policy
set the panoramic camera's frame rate from the cycle rate and the number of users."""

from __future__ import annotations

import pytest
from weblab_sim import world
from weblab_sim.world import World

from acordcs.runtime.api import VirtualClock
from tests.support.generator import imported

from .conftest import APP_DIR

# Table 1 of the paper: cycles/s -> mean speed in mm/s (residential, campus, LAN).
TABLE_1 = {0.90: 69, 1.46: 127, 1.72: 143}


@pytest.fixture
def lab(weblab_app):
    clock = VirtualClock(seed=3)
    here = World(clock)
    world.install(here)
    try:
        with (
            imported(APP_DIR, "weblab_app") as package,
            package.assemble_application(clock=clock) as app,
        ):
            yield app, clock
    finally:
        world.install(None)
        here.close()


def move_at(app, clock, rate: float, turn: float, moves: int = 6) -> None:
    """The Navigator's control actions, ``moves`` of them at ``rate`` per second."""
    port = app.container("UserSide").find("Navigator").instance.port("NavLocomotionPort")
    for _ in range(moves):
        port.call("move", 100.0, turn)
        clock.sleep(1.0 / rate)


def test_the_control_monitor_computes_rate_and_angle_from_the_calls(lab):
    app, clock = lab
    move_at(app, clock, 1.46, -12.0)
    control = app.container("WebLabSide").monitor("Control")
    assert control.attributes["cycleRate"] == pytest.approx(1.46, rel=0.02)
    assert control.attributes["angle"] == 12.0 and control.attributes["speed"] == 100.0


def test_speed_limiting_reproduces_table_1_on_a_straight_path(lab):
    app, clock = lab
    weblab = app.container("WebLabSide")
    limits = {}
    for rate in TABLE_1:
        move_at(app, clock, rate, 3.0)
        limits[rate] = weblab.get_property("Locomotion", "maxSpeed")
    assert limits[0.90] < limits[1.46] < limits[1.72]
    for rate, paper in TABLE_1.items():
        assert abs(limits[rate] - paper) <= 25, (rate, limits[rate], paper)


def test_sharper_turns_slow_the_robot_down(lab):
    app, clock = lab
    weblab = app.container("WebLabSide")
    limits = []
    for angle in (3.0, 20.0, 45.0, 80.0):
        move_at(app, clock, 1.46, angle)
        limits.append(weblab.get_property("Locomotion", "maxSpeed"))
    assert limits == sorted(limits, reverse=True) and limits[0] > limits[-1]


def test_recovering_retries_three_times_then_asks_the_user(lab):
    app, clock = lab
    weblab = app.container("WebLabSide")
    navigator = app.container("UserSide").find("Navigator").instance
    recovery = weblab.find("Recovery").instance
    loco = navigator.port("NavLocomotionPort")
    move_at(app, clock, 1.0, 5.0, moves=2)
    steps = []
    for _ in range(5):
        loco.call("stop")  # the control lost the stripe
        steps.append((recovery.actions, recovery.user_requests))
    # three recoveries, then the user, whose help starts the count again: a recovery again
    assert steps == [(1, 0), (2, 0), (3, 0), (3, 1), (4, 1)]
    assert weblab.get_property("Recovery", "retries") == 1
    lost_at = weblab.get_property("Recovery", "lostAt")
    assert lost_at == weblab.monitor("Telemetry").attributes["progress"]


def creep(app, clock, seconds: float = 2.0) -> None:
    """The control moving again at 1 mm/s: the telemetry goes out, the robot gets nowhere."""
    port = app.container("UserSide").find("Navigator").instance.port("NavLocomotionPort")
    for _ in range(round(seconds / 0.5)):
        port.call("move", 1.0, 0.0)
        clock.sleep(0.5)


def test_a_recovery_succeeds_only_ahead_of_where_the_stripe_was_lost(lab):
    app, clock = lab
    weblab = app.container("WebLabSide")
    loco = app.container("UserSide").find("Navigator").instance.port("NavLocomotionPort")
    move_at(app, clock, 1.0, 5.0, moves=2)
    loco.call("stop")  # the control lost the stripe: a recovery
    lost_at = weblab.get_property("Recovery", "lostAt")
    creep(app, clock)  # moving again where it lost the stripe: not recovered yet
    assert weblab.monitor("Telemetry").attributes["progress"] < lost_at + 100
    assert weblab.get_property("Recovery", "recoveries") == 0
    assert weblab.get_property("Recovery", "retries") == 1
    world.installed().progress = lost_at + 150  # the lab sees it 150 mm further along
    creep(app, clock)
    assert weblab.get_property("Recovery", "recoveries") == 1
    assert weblab.get_property("Recovery", "retries") == 0
    assert weblab.faults.counts["total"] == 0


def test_bandwidth_limiting_lowers_the_frame_rate_on_a_slow_control_loop(lab):
    app, clock = lab
    weblab = app.container("WebLabSide")
    navigator = app.container("UserSide").find("Navigator").instance
    navigator.port("NavAccessPort").call("authenticate", "navigator", "token")
    move_at(app, clock, 1.72, 3.0, moves=8)  # fast control, one user: full frame rate
    fast = weblab.get_property("PanoramicCamera", "fps")
    move_at(app, clock, 0.85, 3.0, moves=8)  # a slow control loop: the camera gives way
    slow = weblab.get_property("PanoramicCamera", "fps")
    assert weblab.monitor("Usage").attributes["numUsers"] == 1  # polled from Access
    assert slow < fast, (slow, fast)
