"""The robot's on-board camera (160 x 120, rendered from the floor) and the room's panoramic camera.

Fixed beforehand: the on-board camera looks down at the floor ahead of the robot; its footprint
is the trapezoid :data:`FOOTPRINT` in the robot's frame (x forward, y left, mm): 150 mm ahead,
260 mm wide at the bottom of the image; 750 mm ahead, 960 mm wide at the top. A tilted pinhole
camera sees such a trapezoid; the homography between it and the image is all the rendering (here)
and the stripe detector's inverse-perspective remap (:mod:`.detector`) need. Each frame gets a
little sensor noise from the run's random stream.
"""

from __future__ import annotations

import math
from functools import lru_cache

import cv2
import numpy as np

from weblab_sim import floor

IMAGE_W, IMAGE_H = 160, 120
NEAR_MM, FAR_MM = 150.0, 750.0
NEAR_HALF_MM, FAR_HALF_MM = 130.0, 480.0
# Robot-frame points seen at the image corners: top-left, top-right, bottom-right, bottom-left.
FOOTPRINT = np.array(
    [
        (FAR_MM, FAR_HALF_MM),
        (FAR_MM, -FAR_HALF_MM),
        (NEAR_MM, -NEAR_HALF_MM),
        (NEAR_MM, NEAR_HALF_MM),
    ],
    dtype=np.float32,
)
IMAGE_CORNERS = np.array([(0, 0), (IMAGE_W, 0), (IMAGE_W, IMAGE_H), (0, IMAGE_H)], dtype=np.float32)
WALL_BGR = (60, 60, 60)
NOISE_SIGMA = 3.0
GRAIN_SEED = 7

# The panoramic camera: 640 x 480 MJPEG. Its frame size is tuned (see the package docstring):
# 12 fps take 2.4 Mbit/s, more than a 2 Mbit/s residential line carries; 4 fps take 0.8 Mbit/s.
PANORAMA_FRAME_BYTES = 25_000


def render(
    x: float,
    y: float,
    heading: float,
    noise: np.random.Generator | None = None,
    path: str = floor.DEFAULT_PATH,
) -> np.ndarray:
    """The on-board image (BGR uint8, 120 x 160) with the robot at (x, y) mm, heading in radians,
    on the floor with the stripe ``path`` (:data:`weblab_sim.floor.PATHS`)."""
    c, s = math.cos(heading), math.sin(heading)
    wx = x + FOOTPRINT[:, 0] * c - FOOTPRINT[:, 1] * s
    wy = y + FOOTPRINT[:, 0] * s + FOOTPRINT[:, 1] * c
    src = np.stack(floor.to_px(wx, wy), axis=1).astype(np.float32)
    h = cv2.getPerspectiveTransform(src, IMAGE_CORNERS)
    img = cv2.warpPerspective(
        floor.floor_image(path),
        h,
        (IMAGE_W, IMAGE_H),
        flags=cv2.INTER_LINEAR,
        borderMode=cv2.BORDER_CONSTANT,
        borderValue=WALL_BGR,
    )
    if noise is not None:
        # Sensor grain: a window of a fixed noise field at an offset drawn from the run's stream
        # (drawing 57,600 normals per frame would cost more than rendering it).
        field = _grain()
        dy = int(noise.integers(0, field.shape[0] - IMAGE_H))
        dx = int(noise.integers(0, field.shape[1] - IMAGE_W))
        img = cv2.add(img, field[dy : dy + IMAGE_H, dx : dx + IMAGE_W], dtype=cv2.CV_8U)
    return img


@lru_cache(maxsize=1)
def _grain() -> np.ndarray:
    rng = np.random.default_rng(GRAIN_SEED)
    return rng.normal(0.0, NOISE_SIGMA, size=(2 * IMAGE_H, 2 * IMAGE_W, 3)).astype(np.float32)


def encode(img: np.ndarray, quality: int) -> bytes:
    """JPEG bytes at ``quality`` (what the vision service sends)."""
    ok, buf = cv2.imencode(".jpg", img, [cv2.IMWRITE_JPEG_QUALITY, int(quality)])
    if not ok:
        raise ValueError("JPEG encoding failed")
    return buf.tobytes()


def decode(data: bytes) -> np.ndarray | None:
    """A BGR image from JPEG bytes, or None if they are not an image."""
    img = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_COLOR)
    return img if img is not None and img.size else None
