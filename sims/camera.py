"""Cameras that keep slow motion visible: a fixed overview, and a trail drawn on the floor.

The chase camera (sims/render.py) keeps the robot in the middle of the frame, so a robot that
creeps at 0.05 m/s looks parked. Two remedies, chosen per clip:

- ``overview``: one fixed camera for the whole clip, framing everything the followed object
  visits (its trajectory's bounding box, with a margin), so motion is motion across the frame;
- ``trail``: the path travelled so far, drawn on the floor in every frame (with either camera).

Both need the whole trajectory before the first frame is drawn: clips record states first and
render frames afterwards (sims/clip_worker.py), so the positions are known, and the plan is a
pure function of them: every frame range rendered in any process gets the same camera.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TRAIL_RGB = (255, 96, 0)
FILL = 0.85  # the farthest point of the trajectory lands at 85% of the way to the frame's edge
TRAIL_Z = 0.002  # just above the floor, so the line is never hidden by the tiles


@dataclass(frozen=True)
class Overview:
    """A fixed camera: looks at ``target`` from ``distance`` at ``yaw``/``pitch`` (degrees)."""

    target: tuple[float, float, float]
    distance: float
    yaw: float
    pitch: float


def overview_for(
    positions: np.ndarray,
    yaw: float,
    fov_deg: float,
    aspect: float,
    pitch: float = -55.0,
    margin: float = 0.25,
    min_radius: float = 0.35,
) -> Overview:
    """The fixed camera that shows every position in ``positions`` (N×3, metres).

    The camera looks at the middle of the trajectory's bounding box, from as close as keeps
    every position (and ``margin`` around the box, ``min_radius`` at least) inside the frame.
    """
    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    lo, hi = pts[:, :2].min(axis=0), pts[:, :2].max(axis=0)
    centre = (lo + hi) / 2
    radius = max(float(np.linalg.norm(hi - lo)) / 2 + margin, min_radius)
    half_v = math.radians(fov_deg) / 2
    half = min(half_v, math.atan(math.tan(half_v) * aspect))
    target = (float(centre[0]), float(centre[1]), 0.0)
    nearest = min_radius / math.sin(half)
    ov = Overview(target, radius / math.sin(half), yaw, pitch)  # a safe start: a bounding circle
    for _ in range(4):  # then move in until the farthest point sits at `FILL` of the frame
        view, proj = matrices(ov, fov_deg, aspect)
        xy, _front = project(pts, view, proj, 2, 2)  # a 2×2 "image": pixel - 1 = NDC
        extent = float(np.abs(xy - 1).max())
        ov = Overview(target, max(nearest, ov.distance * extent / FILL), yaw, pitch)
    return ov


def matrices(ov: Overview, fov_deg: float, aspect: float, near: float = 0.01, far: float = 50.0):
    """pybullet's view and projection matrices for ``ov``."""
    from sims.quiet import pybullet as p

    view = p.computeViewMatrixFromYawPitchRoll(ov.target, ov.distance, ov.yaw, ov.pitch, 0.0, 2)
    proj = p.computeProjectionMatrixFOV(fov_deg, aspect, near, far)
    return view, proj


def project(points: np.ndarray, view: list[float], proj: list[float], width: int, height: int):
    """World points (N×3) -> pixel coordinates (N×2) and a mask of points in front of the camera.

    ``view`` and ``proj`` are pybullet's matrices (16 floats, column-major, as OpenGL).
    """
    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    v = np.asarray(view, dtype=np.float64).reshape(4, 4).T
    pr = np.asarray(proj, dtype=np.float64).reshape(4, 4).T
    homo = np.hstack([pts, np.ones((len(pts), 1))])
    clip = homo @ (pr @ v).T
    w = clip[:, 3]
    front = w > 1e-6
    safe = np.where(front, w, 1.0)
    x = (clip[:, 0] / safe + 1) / 2 * width
    y = (1 - clip[:, 1] / safe) / 2 * height
    return np.stack([x, y], axis=1), front


def draw_trail(
    image: np.ndarray,
    positions: np.ndarray,
    view: list[float],
    proj: list[float],
    rgb: tuple[int, int, int] = TRAIL_RGB,
) -> np.ndarray:
    """``image`` (H×W×3 RGB) with the floor path through ``positions`` drawn on it."""
    import cv2

    pts = np.asarray(positions, dtype=np.float64).reshape(-1, 3)
    if len(pts) < 2:
        return image
    floor = pts.copy()
    floor[:, 2] = TRAIL_Z
    height, width = image.shape[:2]
    xy, front = project(floor, view, proj, width, height)
    out = np.array(image, dtype=np.uint8, copy=True)
    thickness = max(2, height // 160)
    run: list[list[int]] = []
    for (x, y), ok in zip(xy, front, strict=True):
        if ok and abs(x) < 8 * width and abs(y) < 8 * height:
            run.append([int(round(x)), int(round(y))])
            continue
        _polyline(cv2, out, run, rgb, thickness)
        run = []
    _polyline(cv2, out, run, rgb, thickness)
    return out


def _polyline(cv2, image: np.ndarray, run: list[list[int]], rgb, thickness: int) -> None:
    if len(run) >= 2:
        line = np.asarray(run, dtype=np.int32).reshape(-1, 1, 2)
        cv2.polylines(image, [line], False, rgb, thickness, lineType=cv2.LINE_AA)
