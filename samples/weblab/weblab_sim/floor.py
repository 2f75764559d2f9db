"""The lab's floor: a 4 x 3 m raster at 5 mm/px with a coloured stripe path and a finish line.

A family of four paths (:data:`PATHS`), each six straight segments from the same start (the
stripe runs on 350 mm past the finish line), given by its segment lengths and the turns between
them; a 50 mm orange stripe on a grey, faintly textured floor:

- ``default``, fixed beforehand (not tuned to the paper): 6.4 m, turning by +75, +80, +45, -100
  and -70 degrees; the experiment's Table 1 runs on it;
- ``sharp``, for robustness (designed after the default path's results were known, to be harder):
  6.6 m, turning by +115, -115, +110, +70 and +45 degrees, three of them sharper than any turn of
  the default path; segments that are not neighbours are at least 810 mm apart, so the camera
  (750 mm ahead, 960 mm wide) never sees two of them at once;
- ``right``, a serpentine of right angles (designed after the first two were run, not changed
  after its own runs): 7.7 m, segments of 2400, 700, 1600, 700, 1700 and 600 mm turning +90,
  +90, -90, -90, +90 degrees; the third segment runs 700 mm from the first and the fifth 700 mm
  from the third, within the camera's reach: a robot that overshoots a corner can see them;
- ``gentle``, turns of 60 degrees only (designed with ``right``, not changed after its runs):
  5.5 m, segments of 1300, 800, 800, 800, 800 and 1000 mm turning +60, -60, +60, +60, +60
  degrees; the longest path of 60 degree turns with segments of 800 to 1300 mm that keeps
  450 mm from the walls and 800 mm between segments that are not neighbours.

The texture has its own fixed seed (:data:`TEXTURE_SEED`), so every run sees the same floor; a
run's seed changes only what happens on it. World coordinates are millimetres, x east, y north,
origin at the floor's south-west corner; raster row 0 is the north edge.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

WIDTH_MM = 4000.0
HEIGHT_MM = 3000.0
MM_PER_PX = 5.0
STRIPE_WIDTH_MM = 50.0
STRIPE_BGR = (40, 120, 235)  # orange: hue ~12 of 180 in OpenCV's HSV
FLOOR_GREY = 150
TEXTURE_SEED = 2011  # the floor is part of the set-up, the same in every run
START = (500.0, 450.0)
START_HEADING = 0.0  # radians
# Segment lengths (mm) and the turn (degrees, + left) before each segment but the first.
PATHS: dict[str, tuple[tuple[float, float], ...]] = {
    "default": (
        (2300.0, 0.0),
        (900.0, 75.0),
        (1300.0, 80.0),
        (700.0, 45.0),
        (750.0, -100.0),
        (450.0, -70.0),
    ),
    "sharp": (
        (1800.0, 0.0),
        (1000.0, 115.0),
        (1200.0, -115.0),
        (900.0, 110.0),
        (1200.0, 70.0),
        (500.0, 45.0),
    ),
    "right": (
        (2400.0, 0.0),
        (700.0, 90.0),
        (1600.0, 90.0),
        (700.0, -90.0),
        (1700.0, -90.0),
        (600.0, 90.0),
    ),
    "gentle": (
        (1300.0, 0.0),
        (800.0, 60.0),
        (800.0, -60.0),
        (800.0, 60.0),
        (800.0, 60.0),
        (1000.0, 60.0),
    ),
}
DEFAULT_PATH = "default"
RUN_OUT_MM = 350.0  # the stripe goes on past the finish line, so the camera sees it to the end
FINISH_HALF_WIDTH_MM = 300.0


@dataclass(frozen=True)
class Path:
    """The stripe's centre line: its vertices (mm) and arc-length helpers."""

    points: np.ndarray  # (n, 2)

    @property
    def length(self) -> float:
        return float(np.sum(np.linalg.norm(np.diff(self.points, axis=0), axis=1)))

    def closest(self, x: float, y: float) -> tuple[float, float]:
        """(distance from (x, y) to the centre line, arc length of the closest point)."""
        p = np.array([x, y])
        a, b = self.points[:-1], self.points[1:]
        ab = b - a
        seg_len = np.linalg.norm(ab, axis=1)
        t = np.clip(np.einsum("ij,ij->i", p - a, ab) / seg_len**2, 0.0, 1.0)
        foot = a + ab * t[:, None]
        dist = np.linalg.norm(foot - p, axis=1)
        i = int(np.argmin(dist))
        before = float(np.sum(seg_len[:i]))
        return float(dist[i]), before + float(t[i] * seg_len[i])

    def nearest(self, x: float, y: float) -> tuple[float, float, float]:
        """(distance from (x, y) to the centre line, arc length of the closest point, the
        direction the stripe runs there in degrees counter-clockwise from east)."""
        dist, s = self.closest(x, y)
        return dist, s, math.degrees(self.pose_at(s)[2])

    def pose_at(self, s: float) -> tuple[float, float, float]:
        """The point at arc length ``s`` and the stripe's heading there (radians)."""
        for a, b in zip(self.points[:-1], self.points[1:], strict=True):
            d = b - a
            n = float(np.hypot(*d))
            if s <= n:
                q = a + d * (max(s, 0.0) / n)
                return float(q[0]), float(q[1]), math.atan2(d[1], d[0])
            s -= n
        d = self.points[-1] - self.points[-2]
        return float(self.points[-1][0]), float(self.points[-1][1]), math.atan2(d[1], d[0])

    def corners(self) -> list[float]:
        """The arc length of each inner vertex (where the stripe turns)."""
        lengths = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        return [float(v) for v in np.cumsum(lengths)[:-1]]

    def crossed_finish(self, x: float, y: float) -> bool:
        """True once (x, y) is past the end of the last segment, within the finish line's width."""
        a, b = self.points[-2], self.points[-1]
        u = (b - a) / np.linalg.norm(b - a)
        rel = np.array([x, y]) - b
        along = float(rel @ u)
        across = abs(float(rel[0] * -u[1] + rel[1] * u[0]))
        return along >= 0.0 and across <= FINISH_HALF_WIDTH_MM

    def turns(self) -> list[float]:
        """The turn at each inner vertex, degrees (+ left)."""
        out = []
        for a, b, c in zip(self.points[:-2], self.points[1:-1], self.points[2:], strict=True):
            h1 = math.atan2(*(b - a)[::-1])
            h2 = math.atan2(*(c - b)[::-1])
            out.append(math.degrees((h2 - h1 + math.pi) % (2 * math.pi) - math.pi))
        return out


def make_path(name: str = DEFAULT_PATH) -> Path:
    """The stripe's centre line of the path ``name`` (one of :data:`PATHS`)."""
    if name not in PATHS:
        raise ValueError(f"no path {name!r} (paths: {', '.join(PATHS)})")
    x, y = START
    heading = math.degrees(START_HEADING)
    points = [(x, y)]
    for length, turn in PATHS[name]:
        heading += turn
        x += length * math.cos(math.radians(heading))
        y += length * math.sin(math.radians(heading))
        points.append((x, y))
    return Path(np.array(points))


def to_px(x: float, y: float) -> tuple[float, float]:
    """World mm -> raster (column, row) in pixels (sub-pixel, row 0 at the north edge)."""
    return x / MM_PER_PX, (HEIGHT_MM - y) / MM_PER_PX


@lru_cache(maxsize=len(PATHS))
def floor_image(name: str = DEFAULT_PATH) -> np.ndarray:
    """The floor raster with the path ``name`` (BGR uint8, 600 x 800), built once per process and
    path: it never changes."""
    h, w = int(HEIGHT_MM / MM_PER_PX), int(WIDTH_MM / MM_PER_PX)
    rng = np.random.default_rng(TEXTURE_SEED)
    noise = rng.normal(0.0, 12.0, size=(h // 2, w // 2)).astype(np.float32)
    noise = cv2.resize(cv2.GaussianBlur(noise, (3, 3), 0), (w, h))
    grey = np.clip(FLOOR_GREY + noise, 0, 255).astype(np.uint8)
    img = cv2.merge([grey, grey, grey])
    path = make_path(name)
    a, b = path.points[-2], path.points[-1]
    run_out = b + (b - a) / np.linalg.norm(b - a) * RUN_OUT_MM
    drawn = np.vstack([path.points, run_out])
    pts = np.array([to_px(*p) for p in drawn]) * 16  # 4 fractional bits
    thickness = max(1, round(STRIPE_WIDTH_MM / MM_PER_PX))
    cv2.polylines(img, [pts.astype(np.int32)], False, STRIPE_BGR, thickness, cv2.LINE_AA, shift=4)
    # Round joints, so the stripe has no notch at the corners.
    for p in pts[1:-2]:
        cv2.circle(img, tuple(int(v) for v in p), thickness * 8, STRIPE_BGR, -1, cv2.LINE_AA, 4)
    # The finish line: a dark bar across the end of the last segment.
    u = (b - a) / np.linalg.norm(b - a)
    n = np.array([-u[1], u[0]]) * FINISH_HALF_WIDTH_MM
    ends = [to_px(*(b + n)), to_px(*(b - n))]
    cv2.line(img, *(tuple(round(v) for v in e) for e in ends), (30, 30, 30), thickness)
    img.setflags(write=False)
    return img
