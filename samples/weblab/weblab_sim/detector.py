"""The user's stripe detector (runs on the user's computer): HSV threshold, inverse-perspective
remap onto the floor ahead, connected components, and the point about ``look_ahead`` mm away
along the stripe to steer at (steering at a line fitted to the whole blob fails at corners)."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import cv2
import numpy as np

from weblab_sim import camera

GRID_MM = 10.0  # the remapped floor grid
MIN_AREA_PX = 10  # smaller blobs are noise (10 cells of 10 x 10 mm)
RING_MM = 20.0
# Orange in OpenCV's HSV (hue 0..180): the stripe; the grey floor has no saturation.
HSV_LOW = np.array([0, 110, 90], dtype=np.uint8)
HSV_HIGH = np.array([25, 255, 255], dtype=np.uint8)

_GW = round(2 * camera.FAR_HALF_MM / GRID_MM)
_GH = round((camera.FAR_MM - camera.NEAR_MM) / GRID_MM)
# Image -> floor grid (row 0 at the far edge, column 0 at the left edge).
_GRID_CORNERS = np.array([(0, 0), (_GW, 0), (_GW, _GH), (0, _GH)], dtype=np.float32)
_FOOT_GRID = np.array(
    [
        ((camera.FAR_HALF_MM - fy) / GRID_MM, (camera.FAR_MM - fx) / GRID_MM)
        for fx, fy in camera.FOOTPRINT
    ],
    dtype=np.float32,
)
_IMAGE_TO_GRID = cv2.getPerspectiveTransform(camera.IMAGE_CORNERS, _FOOT_GRID)
_rows, _cols = np.mgrid[0:_GH, 0:_GW]
_X = camera.FAR_MM - (_rows + 0.5) * GRID_MM  # robot frame, forward
_Y = camera.FAR_HALF_MM - (_cols + 0.5) * GRID_MM  # robot frame, left
_R = np.hypot(_X, _Y)
_VISIBLE = (
    cv2.warpPerspective(
        np.full((camera.IMAGE_H, camera.IMAGE_W), 255, np.uint8), _IMAGE_TO_GRID, (_GW, _GH)
    )
    > 127
)


def stripe_mask(img: np.ndarray) -> np.ndarray:
    """The stripe's pixels of a BGR image (uint8 0/255)."""
    hsv = cv2.cvtColor(img, cv2.COLOR_BGR2HSV)
    return cv2.inRange(hsv, HSV_LOW, HSV_HIGH)


@dataclass(frozen=True)
class Sighting:
    """What a frame shows of the stripe, as robot-frame points (x forward, y left; mm) about the
    look-ahead distance away: ``target``, the point to steer at (the crossing of that distance
    farthest along the stripe from where it enters the view), and ``crossings``, one point per
    place where the stripe crosses that distance, farthest from the entry first. A stripe seen
    across the view, as after a recovery, crosses it twice: one point in each direction along it
    (``target`` is then their middle when they are equally far from the entry)."""

    target: tuple[float, float]
    crossings: tuple[tuple[float, float], ...]


def sight(img: np.ndarray, look_ahead: float = 300.0) -> Sighting | None:
    """The stripe in a BGR image, or None when no stripe is seen."""
    grid = cv2.warpPerspective(stripe_mask(img), _IMAGE_TO_GRID, (_GW, _GH)) > 127
    grid &= _VISIBLE
    count, labels, stats, _ = cv2.connectedComponentsWithStats(grid.astype(np.uint8), 8)
    if count <= 1:
        return None
    best = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    if stats[best, cv2.CC_STAT_AREA] < MIN_AREA_PX:
        return None
    blob = labels == best
    r = _R[blob]
    x, y = _X[blob], _Y[blob]
    entry = int(np.argmin(r))  # where the stripe enters the view
    ring = np.abs(r - look_ahead) <= RING_MM
    crossing = bool(ring.any())
    if not crossing:
        # The whole visible stripe is nearer (it ends or turns away) or farther: its far or near end.
        ring = r >= np.max(r) - RING_MM if r.max() < look_ahead else r <= np.min(r) + RING_MM
    # The ring may cross the stripe twice (a sharp corner): take the crossing farthest from the
    # entry point, which is the one farther along the stripe.
    far = np.hypot(x - x[entry], y - y[entry])
    pick = ring & (far >= np.max(far[ring]) - 2 * RING_MM)
    target = (float(np.mean(x[pick])), float(np.mean(y[pick])))
    if not crossing:
        return Sighting(target, (target,))
    pieces = np.zeros(grid.shape, np.uint8)
    pieces[blob] = ring
    n, piece = cv2.connectedComponents(pieces, connectivity=8)
    at = piece[blob]
    order = sorted(range(1, n), key=lambda k: -float(np.max(far[at == k])))
    crossings = tuple((float(np.mean(x[at == k])), float(np.mean(y[at == k]))) for k in order)
    return Sighting(target, crossings)


def target_point(img: np.ndarray, look_ahead: float = 300.0) -> tuple[float, float] | None:
    """The robot-frame point (x forward, y left; mm) to steer at, or None when no stripe is seen."""
    seen = sight(img, look_ahead)
    return seen.target if seen is not None else None


def bearing(point: tuple[float, float]) -> float:
    """The turn (degrees, + left) towards a robot-frame point."""
    return math.degrees(math.atan2(point[1], point[0]))


def sight_frame(data: bytes, look_ahead: float = 300.0) -> Sighting | None:
    """:func:`sight` of a JPEG frame (None also when the bytes are not an image)."""
    img = camera.decode(data)
    return sight(img, look_ahead) if img is not None else None


def find_stripe(
    data: bytes,
    look_ahead: float = 300.0,
    choose: Callable[[Sighting | None], float | None] | None = None,
) -> float | None:
    """The turn (degrees, + left) towards the stripe in a JPEG frame, or None when there is none.
    ``choose`` picks the turn from the :class:`Sighting` (the Navigator's
    :meth:`weblab_sim.course.Course.choose`); without it, the turn towards ``target``."""
    seen = sight_frame(data, look_ahead)
    if choose is not None:
        return choose(seen)
    return bearing(seen.target) if seen is not None else None
