"""On the right-angle path, where the stripe's third segment runs 700 mm from the first and the
fifth 700 mm from the third, a robot that overshoots a corner can pick up another segment and
follow it the wrong way (before the lab's telemetry said where along the stripe the robot is, it
did: 2.2 m back towards the start). Its place along the stripe, recomputed here from the
trajectory, never falls back while it drives forward, and no run finishes by a short cut."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from weblab_sim import camera, detector, experiment, floor
from weblab_sim.course import Course


def segments_apart(path: floor.Path) -> float:
    """The least distance between two segments of ``path`` that are not neighbours (mm)."""

    def to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
        t = np.clip((p - a) @ (b - a) / ((b - a) @ (b - a)), 0.0, 1.0)
        return float(np.linalg.norm(a + t * (b - a) - p))

    pts = path.points
    pairs = [(i, j) for i, j in itertools.combinations(range(len(pts) - 1), 2) if j > i + 1]
    return min(
        min(
            to_segment(pts[i], pts[j], pts[j + 1]),
            to_segment(pts[i + 1], pts[j], pts[j + 1]),
            to_segment(pts[j], pts[i], pts[i + 1]),
            to_segment(pts[j + 1], pts[i], pts[i + 1]),
        )
        for i, j in pairs
    )


def fallen_back(path: floor.Path, series: dict) -> float:
    """The most the robot's place along the stripe fell below its peak within a stretch of
    driving forward on the stripe, from the trajectory and the commanded speed."""
    worst, peak, last = 0.0, None, None
    for (_, x, y), (_, speed) in zip(series["trajectory"], series["speed"], strict=True):
        dist, s = path.closest(x, y)
        if dist >= 150.0 or speed <= 0.0 or (last is not None and abs(s - last) > 100.0):
            peak = None if dist >= 150.0 or speed <= 0.0 else s
            last = s if peak is not None else None
            continue
        peak = s if peak is None else max(peak, s)
        worst = max(worst, peak - s)
        last = s
    return worst


def test_the_right_angle_path_has_segments_within_700_mm_of_each_other() -> None:
    turns = floor.make_path("right").turns()
    assert [abs(round(t)) for t in turns] == [90] * 5
    assert segments_apart(floor.make_path("right")) == pytest.approx(700.0)


@pytest.mark.parametrize(("profile", "seed"), [("residential", 1), ("LAN", 2)])
def test_on_the_right_angle_path_progress_along_the_stripe_is_monotone(
    weblab_app, profile: str, seed: int
) -> None:
    metrics = experiment.run(profile, seed, "adaptive", path="right", series=True, time_cap=300.0)
    path = floor.make_path("right")
    assert metrics["finished"] == 1
    assert metrics["progress_mm"] == pytest.approx(path.length, abs=1.0)  # no short cut
    worst = fallen_back(path, metrics["series"])
    assert worst <= experiment.BACKWARDS_MM, worst
    assert metrics["backwards_mm"] == pytest.approx(worst, abs=20.0)  # the lab's own measure
    assert metrics["followed_backwards"] == 0
    assert metrics["user_requests"] == 0  # not even at the second corner (below)


def reading(heading: float, along: float, progress: float, runs: float) -> dict[str, float]:
    return {"heading": heading, "along": along, "progress": progress, "stripeHeading": runs}


def test_a_robot_driving_against_the_stripe_stops_and_takes_the_way_the_stripe_runs() -> None:
    course = Course()
    course.observe(reading(0.0, 1000.0, 1000.0, 0.0), forward=True)
    course.observe(reading(10.0, 1000.0, 1000.0, 180.0), forward=True)  # heading 170 off
    assert course.halt and course.travel == 180.0
    assert course.choose(None) is None and not course.halt  # it stopped once


def test_a_robot_on_a_segment_far_ahead_is_astray_until_it_is_back() -> None:
    course = Course()
    course.observe(reading(180.0, 5600.0, 3100.0, 0.0), forward=True)
    assert course.astray
    course.observe(reading(180.0, 5600.0, 3100.0, 0.0), forward=False)  # backed up: still there
    assert course.astray
    course.observe(reading(180.0, 3150.0, 3100.0, 180.0), forward=False)  # put back by a person
    assert not course.astray


def test_at_the_second_right_angle_a_stripe_seen_only_far_ahead_is_not_steered_at() -> None:
    # 50 mm before the second corner, facing north: the third segment (west from the corner) is
    # nearer than the camera's near edge, and the fifth, 700 mm north, is all the camera sees.
    x, y = floor.make_path("right").points[2]
    seen = detector.sight(camera.render(x, y - 50.0, math.radians(90.0), path="right"))
    assert seen is not None and math.hypot(*seen.target) > 650.0  # the fifth segment
    course = Course()
    course.observe(reading(90.0, 3050.0, 3050.0, 90.0), forward=True)
    course.travel = 90.0  # it was following the second segment north
    assert course.choose(seen) is None
    # Backed up and turned left (what the recovery does), it sees the third segment, and takes it.
    nearer = detector.sight(camera.render(x, y - 200.0, math.radians(100.0), path="right"))
    turn = course.choose(nearer)
    assert nearer is not None and math.hypot(*nearer.target) < 400.0
    assert turn is not None and turn > 20.0  # left, onto the third segment


def test_after_the_lab_stopped_it_the_robot_takes_no_point_back_along_the_stripe() -> None:
    # Past the right-angle path's fourth corner, on the fifth segment (running east), facing
    # north-west: the lab stopped it for driving the stripe backwards.
    course = Course()
    course.observe(reading(141.0, 5568.0, 5568.0, 0.0), forward=False)
    course.travel = 145.0  # where it had been steering
    stopped = {**reading(142.0, 5529.0, 5568.0, 0.0), "stoppedBackwards": 1.0}
    course.observe(stopped, forward=True)
    assert course.choose(None) is None  # it stops once
    back = detector.Sighting((216.0, 16.0), ((216.0, 16.0),))  # 145 degrees from east
    assert course.choose(back) is None
    on = (150.0, -300.0)  # 63 degrees right of heading 142: 79 degrees from east
    both = detector.Sighting(back.target, (back.target, on))
    turn = course.choose(both)
    assert turn == pytest.approx(detector.bearing(on))
    # Facing along the stripe again (turned by the recovery), the bound is lifted.
    course.observe(reading(20.0, 5600.0, 5600.0, 0.0), forward=False)
    assert course.against is None


def test_the_run_that_drove_the_fifth_segment_backwards_no_longer_does(weblab_app) -> None:
    # Seed 8203, campus, SpeedLimiting off: facing back along the fifth segment, the robot took
    # it the wrong way after each back-up of the recovery (the lab stopped it each time), 119 mm
    # back in all.
    metrics = experiment.run("campus", 8203, "no_speed_policy", path="right", series=True)
    assert metrics["finished"] == 1
    worst = fallen_back(floor.make_path("right"), metrics["series"])
    assert metrics["backwards_mm"] <= experiment.BACKWARDS_MM, metrics["backwards_mm"]
    assert worst <= experiment.BACKWARDS_MM, worst
    assert metrics["followed_backwards"] == 0
