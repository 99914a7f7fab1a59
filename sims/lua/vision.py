"""Vision sensors as CoppeliaSim's default image processing reads them.

``read_vision_sensor`` renders the sensor (its pose, resolution, view angle and clipping planes,
through ``sims.scene.camera``) with depth, and returns the auxiliary packet CoppeliaSim's
default filter produces: minimum, maximum and average of intensity, red, green, blue and depth,
all in 0..1 (15 values; depth linear between the near and far planes). The detection state is
False: the default filter has no trigger.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from sims.quiet import pybullet as p
from sims.quiet import quiet_fd
from sims.remote_api import commands as cmd
from sims.scene.camera import MAX_SIDE, _projection


def render_with_depth(world: Any, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(HxWx3 uint8 RGB, HxW linear depth 0..1), top row first."""
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
    z, y = (m[2], m[5], m[8]), (m[1], m[4], m[7])
    view = p.computeViewMatrix(pos, [pos[i] + z[i] for i in range(3)], y)
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
    rgb = np.asarray(img[2], dtype=np.uint8).reshape(height, width, 4)[:, :, :3]
    zbuf = np.asarray(img[3], dtype=np.float64).reshape(height, width)
    near, far = max(sensor.near, 1e-4), max(sensor.far, sensor.near + 1e-3)
    if sensor.perspective:
        eye = far * near / (far - (far - near) * zbuf)
        depth = (eye - near) / (far - near)
    else:
        depth = zbuf
    return np.ascontiguousarray(rgb), np.clip(depth, 0.0, 1.0)


def aux_packet(rgb: np.ndarray, depth: np.ndarray) -> list[float]:
    colour = rgb.reshape(-1, 3).astype(np.float64) / 255.0
    intensity = colour.mean(axis=1)
    d = depth.reshape(-1)
    columns = [intensity, colour[:, 0], colour[:, 1], colour[:, 2], d]
    out = [float(c.min()) for c in columns]
    out += [float(c.max()) for c in columns]
    out += [float(c.mean()) for c in columns]
    return out


def read_vision_sensor(world: Any, handle: int) -> tuple[bool, list[float]]:
    n = cmd.name(world, handle)
    if world.kind(handle) != "vision_sensor":
        raise cmd.CommandError(f"object {n!r} is not a vision sensor")
    rgb, depth = render_with_depth(world, n)
    return False, aux_packet(rgb, depth)
