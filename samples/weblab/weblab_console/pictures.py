"""What the console's cameras and map show: the Navigator's frame with the detected stripe drawn,
the panoramic camera's picture of the room, and the stripe path for the map."""

from __future__ import annotations

import math
from typing import Any

import cv2
import numpy as np
from weblab_sim import camera, detector, floor


def onboard(jpeg: bytes, turn: float | None) -> bytes:
    """The Navigator's frame, enlarged, with the stripe the detector sees outlined and the point
    it steers at (or "no stripe")."""
    img = camera.decode(jpeg)
    if img is None:
        img = np.zeros((camera.IMAGE_H, camera.IMAGE_W, 3), np.uint8)
    scale = 2
    big = cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_LINEAR)
    mask = cv2.resize(
        detector.stripe_mask(img), None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST
    )
    contours, _ = cv2.findContours(mask, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    cv2.drawContours(big, contours, -1, (80, 255, 80), 2)
    h, w = big.shape[:2]
    if turn is None:
        cv2.putText(big, "no stripe", (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (60, 60, 255), 2)
    else:
        a = math.radians(turn)
        tip = (int(w / 2 - math.sin(a) * h * 0.6), int(h - math.cos(a) * h * 0.6))
        cv2.arrowedLine(big, (w // 2, h - 2), tip, (255, 200, 60), 2, tipLength=0.15)
        cv2.putText(
            big,
            f"turn {turn:+.0f} deg",
            (8, 22),
            cv2.FONT_HERSHEY_SIMPLEX,
            0.55,
            (255, 255, 255),
            1,
        )
    return camera.encode(big, 80)


_ROOM: np.ndarray | None = None
PANORAMA_W = 400


def panoramic(x: float, y: float, heading: float, trail: list[list[float]]) -> bytes:
    """The room seen from above (the panoramic camera's view): floor, stripe, robot."""
    global _ROOM
    if _ROOM is None:
        room = floor.floor_image()
        h, w = room.shape[:2]
        _ROOM = cv2.resize(
            room, (PANORAMA_W, round(h * PANORAMA_W / w)), interpolation=cv2.INTER_AREA
        )
    img = _ROOM.copy()
    s = PANORAMA_W / floor.WIDTH_MM

    def px(px_x: float, px_y: float) -> tuple[int, int]:
        return int(px_x * s), int(img.shape[0] - px_y * s)

    if len(trail) > 1:
        pts = np.array([px(a, b) for a, b in trail[-400:]], np.int32)
        cv2.polylines(img, [pts], False, (255, 170, 60), 1, cv2.LINE_AA)
    centre = px(x, y)
    cv2.circle(img, centre, max(3, int(165 * s)), (40, 40, 40), -1, cv2.LINE_AA)
    nose = px(x + 200 * math.cos(heading), y + 200 * math.sin(heading))
    cv2.line(img, centre, nose, (255, 255, 255), 2, cv2.LINE_AA)
    return camera.encode(img, 70)


def path() -> dict[str, Any]:
    """The map's background: the stripe's vertices, the finish, the floor's size (mm)."""
    stripe = floor.make_path()
    points = [[round(float(a), 1), round(float(b), 1)] for a, b in stripe.points]
    return {
        "points": points,
        "finish": points[-1],  # the finish line is across the stripe's last vertex
        "floor": [floor.WIDTH_MM, floor.HEIGHT_MM],
    }
