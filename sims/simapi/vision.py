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

from sims.remote_api import commands as cmd
from sims.scene.camera import back_off, capture_sensor


def render_with_depth(world: Any, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(HxWx3 uint8 RGB, HxW linear depth 0..1), top row first."""
    sensor, rgba, zbuf = capture_sensor(world, name)
    return np.ascontiguousarray(rgba[:, :, :3]), linear_depth(sensor, zbuf)


def linear_depth(sensor: Any, zbuf: np.ndarray) -> np.ndarray:
    """Depth 0..1 between the sensor's clipping planes from the renderer's z-buffer: an
    orthographic sensor is drawn as a perspective from ``back_off`` behind it, whose planes
    are shifted by that distance."""
    near, far = max(sensor.near, 1e-4), max(sensor.far, sensor.near + 1e-3)
    shift = 0.0 if sensor.perspective else back_off(sensor)
    n, f = near + shift, far + shift
    eye = f * n / (f - (f - n) * zbuf)
    return np.clip((eye - n) / (f - n), 0.0, 1.0)


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
