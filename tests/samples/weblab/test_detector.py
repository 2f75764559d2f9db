"""The stripe detector on images rendered from the floor: its turn against the geometry."""

from __future__ import annotations

import math

import pytest
from weblab_sim import camera, detector, floor

X0, Y0 = floor.START[0] + 400.0, floor.START[1]  # on the first, straight segment (along +x)


def turn_at(x: float, y: float, heading: float = 0.0) -> float | None:
    return detector.find_stripe(camera.encode(camera.render(x, y, heading), 75), 300.0)


def test_a_straight_stripe_ahead_gives_about_no_turn() -> None:
    turn = turn_at(X0, Y0)
    assert turn is not None and abs(turn) < 3.0


@pytest.mark.parametrize("offset", [-80.0, -40.0, 40.0, 80.0])
def test_an_offset_stripe_gives_the_bearing_of_the_point_300_mm_away(offset: float) -> None:
    # The robot `offset` mm right of the stripe (y below it) sees it on its left: a left turn (+).
    # Oracle: the stripe point 300 mm from the robot is at lateral -offset.
    expected = math.degrees(math.asin(offset / 300.0))
    turn = turn_at(X0, Y0 - offset)
    assert turn is not None
    assert math.copysign(1.0, turn) == math.copysign(1.0, offset)
    assert turn == pytest.approx(expected, abs=3.0)


def test_a_robot_turned_right_of_the_stripe_is_told_to_turn_left() -> None:
    turn = turn_at(X0, Y0, math.radians(-20.0))
    assert turn is not None and turn == pytest.approx(20.0, abs=3.0)


def test_blank_floor_gives_none() -> None:
    # Near the north-east corner, facing east: floor and wall, no stripe.
    assert turn_at(3500.0, 2700.0, 0.0) is None


def test_bytes_that_are_not_an_image_give_none() -> None:
    assert detector.find_stripe(b"not a jpeg") is None


def test_at_a_left_corner_the_target_is_on_the_new_segment() -> None:
    # 150 mm before the first corner (a 75-degree left turn): steer left, well past straight.
    corner = floor.make_path().points[1]
    turn = turn_at(corner[0] - 150.0, corner[1])
    assert turn is not None and turn > 20.0


def test_a_stripe_seen_across_the_view_gives_a_crossing_each_way() -> None:
    # Facing north 250 mm south of the first segment (which runs east): the 300 mm ring meets the
    # stripe about 166 mm to the right and to the left (oracle: sqrt(300^2 - 250^2)).
    seen = detector.sight(camera.render(X0 + 600.0, Y0 - 250.0, math.radians(90.0)))
    assert seen is not None and len(seen.crossings) == 2
    bearings = sorted(detector.bearing(p) for p in seen.crossings)
    expected = math.degrees(math.atan2(math.sqrt(300.0**2 - 250.0**2), 250.0))
    assert bearings[0] == pytest.approx(-expected, abs=5.0)
    assert bearings[1] == pytest.approx(expected, abs=5.0)


def test_a_stripe_ahead_crosses_once_and_is_the_target() -> None:
    seen = detector.sight(camera.render(X0, Y0, 0.0))
    assert seen is not None and seen.crossings == (seen.target,)
