"""Images from a scene's vision sensors, rendered by pybullet's TinyRenderer (CPU, headless).

A CoppeliaSim vision sensor looks along its frame's +z with the image's up along its +y; its
view angle spans the larger side of the image (perspective), or ``ortho_size`` metres
(orthographic). CoppeliaSim hands images out bottom row first (OpenGL order), RGB or grey, and
the legacy remote API delivers them as signed bytes: ``image_for_remote_api`` does the same so
that scripts which flip and reinterpret the buffer see what they would see in CoppeliaSim.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from sims.quiet import pybullet as p
from sims.quiet import quiet_fd
from sims.scene.model import VisionSensorData

MAX_SIDE = 1024  # px: larger saved resolutions are refused (render time)


BACK_OFF = 100.0  # an orthographic sensor's eye sits this many times its depth range behind it


def back_off(data: VisionSensorData) -> float:
    """How far behind an orthographic sensor its view is drawn from (see _projection)."""
    return BACK_OFF * max(data.far, data.ortho_size)


def _projection(data: VisionSensorData, width: int, height: int) -> list[float]:
    near, far = max(data.near, 1e-4), max(data.far, data.near + 1e-3)
    if not data.perspective:
        # pybullet's TinyRenderer draws nothing through an orthographic matrix (measured:
        # glOrtho's, and computeProjectionMatrix is glFrustum, a wide perspective), so an
        # orthographic sensor is drawn as a perspective from far behind it whose view spans
        # ortho_size at the sensor: straight rays to within (far - near) / BACK_OFF.
        back = back_off(data)
        half = data.ortho_size / 2
        ratio = width / height
        hy = half if width < height else half / ratio
        vertical = 2 * math.atan(hy / back)
        return list(
            p.computeProjectionMatrixFOV(
                math.degrees(vertical), width / height, back + near, back + far
            )
        )
    angle = min(max(data.view_angle, 1e-3), math.pi - 1e-3)
    if width >= height:
        vertical = 2 * math.atan(math.tan(angle / 2) * height / width)
    else:
        vertical = angle
    return list(p.computeProjectionMatrixFOV(math.degrees(vertical), width / height, near, far))


def capture_sensor(world: Any, name: str) -> tuple[VisionSensorData, np.ndarray, np.ndarray]:
    """(sensor data, HxWx4 uint8 RGBA, HxW z-buffer), top row first, rendered from the vision
    sensor ``name`` of a scene World: its pose, resolution, view angle and clipping planes."""
    data = world.model.data.get(name)
    sensor = getattr(data, "vision_sensor", None)
    if sensor is None:
        raise KeyError(f"{name!r} is not a vision sensor")
    width, height = (max(1, int(v)) for v in sensor.resolution)
    if width > MAX_SIDE or height > MAX_SIDE:
        raise ValueError(f"{name}: resolution {width}x{height} is larger than {MAX_SIDE}")
    world.sync_visuals()
    pos, orn = world.object_pose(name)
    m = p.getMatrixFromQuaternion(orn)
    z = (m[2], m[5], m[8])
    y = (m[1], m[4], m[7])
    target = (pos[0] + z[0], pos[1] + z[1], pos[2] + z[2])
    eye = tuple(pos)
    if not sensor.perspective:
        back = back_off(sensor)
        eye = (pos[0] - back * z[0], pos[1] - back * z[1], pos[2] - back * z[2])
    view = p.computeViewMatrix(eye, target, y)
    with quiet_fd(1), quiet_fd(2):
        img = p.getCameraImage(
            width,
            height,
            view,
            _projection(sensor, width, height),
            renderer=p.ER_TINY_RENDERER,
            flags=p.ER_NO_SEGMENTATION_MASK,
            physicsClientId=world.client_id,
        )
    rgba = np.asarray(img[2], dtype=np.uint8).reshape(height, width, 4)
    zbuf = np.asarray(img[3], dtype=np.float64).reshape(height, width)
    return sensor, rgba, zbuf


def render_sensor(world: Any, name: str) -> np.ndarray:
    """HxWx3 uint8 RGB, top row first, from the vision sensor ``name`` of a scene World."""
    _, rgba, _ = capture_sensor(world, name)
    return np.ascontiguousarray(rgba[:, :, :3])


def image_for_remote_api(rgb: np.ndarray, grey: bool) -> tuple[list[int], list[int]]:
    """([width, height], flat signed-byte image, bottom row first) as simxGetVisionSensorImage
    returns them."""
    height, width = rgb.shape[:2]
    rows = rgb[::-1]
    if grey:
        rows = np.round(rows.astype(np.float32).mean(axis=2)).astype(np.uint8)
    flat = rows.reshape(-1).astype(np.int16)
    signed = np.where(flat > 127, flat - 256, flat)
    return [width, height], signed.astype(int).tolist()
