"""The simulator's physics and determinism: the robot against kinematics, runs against their seed."""

from __future__ import annotations

import math

import pytest
from weblab_sim import camera, detector, world
from weblab_sim.robot import Robot

from acordcs.runtime.clock import VirtualClock


def test_a_straight_command_moves_the_robot_speed_times_time() -> None:
    robot = Robot(1000.0, 1000.0, 0.0)
    robot.command(0.0, 100.0, 0.0)
    x, y, heading = robot.pose(2.0)
    # 0.3 g of traction reaches 100 mm/s in ~0.03 s: all but ~2 mm of 200 mm.
    assert x - 1000.0 == pytest.approx(200.0, abs=3.0)
    assert y == pytest.approx(1000.0, abs=1e-6) and heading == pytest.approx(0.0, abs=1e-9)


def test_a_turn_command_turns_at_the_rate_asked() -> None:
    robot = Robot(2000.0, 1500.0, 0.0)
    robot.command(0.0, 100.0, 0.5)
    assert robot.pose(2.0)[2] == pytest.approx(1.0, abs=0.03)


def test_command_times_are_not_rounded_to_the_physics_step() -> None:
    # A speed-up from 100 to 110 mm/s (within the traction limit) 5 ms later, a quarter of a
    # step, leaves the robot 10 mm/s x 5 ms = 0.05 mm behind.
    poses = []
    for at in (0.500, 0.505):
        robot = Robot(1000.0, 1000.0, 0.0)
        robot.command(0.0, 100.0, 0.0)
        robot.command(at, 110.0, 0.0)
        poses.append(robot.pose(2.0)[0])
    assert poses[0] - poses[1] == pytest.approx(0.05, abs=0.01)


def test_the_wheels_limit_speed() -> None:
    robot = Robot(1000.0, 1000.0, 0.0)
    robot.command(0.0, 1000.0, 0.0)
    robot.pose(1.0)
    assert robot.speed() == pytest.approx(300.0, abs=1.0)


def test_walls_stop_the_robot() -> None:
    robot = Robot(3500.0, 1500.0, 0.0)
    robot.command(0.0, 200.0, 0.0)
    # The east wall (x = 4000, 10 mm thick) stops the 300 mm long body at about x = 3840.
    assert robot.pose(10.0)[0] < 3850.0


def test_sonar_ranges_to_the_walls() -> None:
    robot = Robot(1000.0, 500.0, 0.0)
    east, north, south = robot.sonar(0.0, (0.0, 90.0, -90.0), 5000.0)
    assert east == pytest.approx(4000.0 - 10.0 - 1000.0, abs=1.0)
    assert north == pytest.approx(3000.0 - 10.0 - 500.0, abs=1.0)
    assert south == pytest.approx(500.0 - 10.0, abs=1.0)


def drive_world(seed: int) -> list[tuple[float, float, float]]:
    """A world on its own clock, driven by a fixed script: its sampled trajectory."""
    clock = VirtualClock(seed)
    lab = world.World(clock)
    for k in range(8):
        clock.call_at(k * 0.5, lambda k=k: lab.drive(120.0, 0.2 * math.sin(k)))
    clock.run_until(4.0)
    lab.grab_frame()
    lab.close()
    return [(s.t, s.x, s.y) for s in lab.samples]


def test_the_same_seed_gives_the_same_trajectory() -> None:
    assert drive_world(3) == drive_world(3)


def test_different_seeds_give_different_trajectories() -> None:
    a, b = drive_world(3), drive_world(4)
    assert len(a) == len(b) and a != b


@pytest.mark.parametrize("before", [400.0, 100.0, 10.0])
def test_a_person_puts_the_robot_where_its_camera_sees_the_stripe(before: float) -> None:
    # Lost just before the sharp (-100 degree) corner, or well before it: once put back, the
    # camera sees the stripe ahead.
    clock = VirtualClock(0)
    lab = world.World(clock)
    lab.progress = lab.path.corners()[3] - before
    lab.place_on_stripe()
    x, y, _ = lab.pose()
    assert lab.path.closest(x, y)[0] < 1.0
    frame = camera.encode(lab.grab_frame(), 75)
    assert detector.find_stripe(frame) is not None
    lab.close()
