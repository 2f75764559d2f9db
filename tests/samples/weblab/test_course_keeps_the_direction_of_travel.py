"""The Navigator's course (:mod:`weblab_sim.course`): where the camera sees the stripe run both
ways it steers the way the robot was going, it refuses a stripe that runs back the way it came,
and it forgets the way when someone carries the robot. Frames are rendered from the floor."""

from __future__ import annotations

import math

import pytest
from weblab_sim import camera, detector, floor
from weblab_sim.course import Course

X, Y = floor.START[0] + 1000.0, floor.START[1]  # on the first segment, which runs east


def course_going(heading: float, travel: float, side: float = 0.0) -> Course:
    course = Course()
    course.observe({"heading": heading})
    course.travel, course.side = travel, side
    return course


def seen_from(x: float, y: float, heading: float) -> detector.Sighting | None:
    return detector.sight(camera.render(x, y, math.radians(heading)))


def test_across_the_stripe_it_turns_the_way_the_robot_was_going() -> None:
    # Facing north just south of the stripe: east is to the right (turn < 0), west to the left.
    seen = seen_from(X, Y - 250.0, 90.0)
    assert len(seen.crossings) == 2
    assert course_going(90.0, travel=0.0).choose(seen) < -20.0  # it was going east
    assert course_going(90.0, travel=180.0).choose(seen) > 20.0  # it was going west


def test_it_leans_to_the_side_it_was_turning_to_at_a_sharp_corner() -> None:
    # Travel east, then a corner of about 110 degrees: the way on (+110) and the way back along
    # the new segment (-70) are both within 110 degrees; the last turn, to the left, decides.
    seen = seen_from(X, Y - 250.0, 90.0)
    going_on = course_going(90.0, travel=-110.0, side=1.0)  # stripe now runs 0, came from -110
    assert going_on.choose(seen) < -20.0  # east: 110 from the way it came, but to the left


def test_a_stripe_running_back_the_way_it_came_counts_as_none() -> None:
    # Facing west on the first segment, having travelled east: the stripe ahead runs backwards.
    seen = seen_from(X, Y, 180.0)
    assert seen is not None and len(seen.crossings) == 1
    assert course_going(180.0, travel=0.0).choose(seen) is None
    assert course_going(180.0, travel=180.0).choose(seen) is not None


def test_a_carried_robot_forgets_the_way_and_takes_the_stripe_it_is_put_on() -> None:
    course = course_going(0.0, travel=0.0)
    course.observe({"heading": 30.0})  # the wheels can turn it 30 degrees in 0.5 s
    assert course.travel == 0.0
    course.observe({"heading": 180.0})  # 150 degrees at once: someone carried it
    assert course.travel is None
    turn = course.choose(seen_from(X, Y, 180.0))
    assert turn is not None and abs(turn) < 5.0
    assert course.travel == pytest.approx(180.0 + turn)  # west: the way it is put on


def test_a_malformed_reading_leaves_the_heading_as_it_was() -> None:
    course = course_going(45.0, travel=45.0)
    for bad in ({"heading": "NaN"}, {"heading": "n/a"}, {"positionX": 1.0}, "garbage"):
        course.observe(bad)
    assert course.heading == 45.0 and course.travel == 45.0


def test_without_a_heading_it_steers_at_the_detectors_usual_point() -> None:
    seen = seen_from(X, Y - 250.0, 90.0)
    assert Course().choose(seen) == detector.bearing(seen.target)
