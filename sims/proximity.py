"""Proximity sensors of one World: each sensor's rays cast into the scene as one pybullet batch.

Kept apart from the stepping core in sims/world.py because scripts poll their sonars every step
(bench/lua_bench.py), so this is the code a speed change touches. A sensor is a frame whose z is
its sensing axis and a tuple of (start, end) rays in that frame; a bundled scene's ray fan
(sims.models.common.RaySensor) is turned into that form here.
"""

from __future__ import annotations

import math
from typing import Any, Protocol

import numpy as np

from sims.models.common import ProxSensor, RaySensor, SceneModel
from sims.quiet import pybullet as p


class World(Protocol):
    """What the sensors read of ``sims.world.World`` (which creates them: a Protocol, so that
    this module does not import the world back)."""

    client_id: int

    def object_pose(self, handle: Any) -> tuple: ...

    def _lookup(self, handle: int | str) -> str: ...


#: (distance from the sensor origin, point and normal in the sensor frame, body, link)
Hit = tuple[float, tuple, tuple, int, int]
#: A bundled ray fan looks along its link's +x; its CoppeliaSim frame has z there (x_s = y_link,
#: y_s = z_link, z_s = x_link).
LEGACY_SENSOR_ORN = (0.5, 0.5, 0.5, 0.5)


class ProximitySensors:
    """The proximity sensors of one built scene, by name; rebuilt with the scene."""

    def __init__(self, world: World, model: SceneModel):
        self.world = world
        self.by_name: dict[str, ProxSensor] = {s.name: s for s in model.prox}
        for legacy in model.sensors:
            self.by_name[legacy.name] = _from_fan(legacy)
        #: per sensor: its rays' starts then ends, stacked (sensor frame), and the number of rays
        self._ray_ends: dict[str, tuple[np.ndarray, int]] = {}

    def hits(self, name: str) -> list[Hit | None]:
        """Each ray of a sensor: None, or its hit in the sensor frame."""
        origin, rot, hits = self._cast(name)
        return [None if h[0] < 0 else _hit_in_frame(h, origin, rot) for h in hits]

    def nearest(self, name: str) -> Hit | None:
        """The nearest of ``hits`` (the first of equals), what a proximity sensor reports,
        without bringing every other ray's hit into the sensor frame."""
        origin, rot, hits = self._cast(name)
        ox, oy, oz = origin
        best = None
        best_d2 = math.inf
        for h in hits:
            if h[0] < 0:
                continue
            x, y, z = h[3]
            d2 = (x - ox) * (x - ox) + (y - oy) * (y - oy) + (z - oz) * (z - oz)
            if d2 < best_d2:
                best, best_d2 = h, d2
        return None if best is None else _hit_in_frame(best, origin, rot)

    def _cast(self, name: str) -> tuple[tuple, tuple, Any]:
        """Cast a sensor's rays in one batch: (origin, row-major rotation, pybullet hits).

        The rays go into the world with one matrix product per read rather than two pybullet
        transforms per ray: scripts poll their sonars every step (bench/lua_bench.py). This is
        also more exact: pybullet's multiplyTransforms returns single-precision results.
        """
        name = self.world._lookup(name)
        ends = self._ray_ends.get(name)
        if ends is None:
            rays = self.by_name[name].rays
            ends = (np.array([a for a, _ in rays] + [b for _, b in rays], float), len(rays))
            self._ray_ends[name] = ends
        origin, orn = self.world.object_pose(name)
        rot = p.getMatrixFromQuaternion(orn)  # double precision, row-major
        m = np.array(rot, float).reshape(3, 3).T
        world = (ends[0] @ m + np.array(origin, float)).tolist()  # starts and tips: one product
        n = ends[1]
        return (
            origin,
            rot,
            p.rayTestBatch(world[:n], world[n:], physicsClientId=self.world.client_id),
        )


def _hit_in_frame(h: Any, origin: tuple, rot: tuple) -> Hit:
    """A pybullet ray hit as (distance from the sensor origin, point and normal in the sensor
    frame, body, link); ``rot`` is the sensor's row-major rotation (its transpose maps back)."""
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
    dx, dy, dz = h[3][0] - origin[0], h[3][1] - origin[1], h[3][2] - origin[2]
    nx, ny, nz = h[4]
    point = (r0 * dx + r3 * dy + r6 * dz, r1 * dx + r4 * dy + r7 * dz, r2 * dx + r5 * dy + r8 * dz)
    normal = (r0 * nx + r3 * ny + r6 * nz, r1 * nx + r4 * ny + r7 * nz, r2 * nx + r5 * ny + r8 * nz)
    return math.sqrt(dx * dx + dy * dy + dz * dz), point, normal, h[0], h[1]


def _from_fan(s: RaySensor) -> ProxSensor:
    """A bundled ray fan as a sensor frame with z along the link's +x, rays in that frame."""
    rays = []
    for d in s.rays():  # link frame (x forward) -> sensor frame (z forward)
        tip = (d[1] * s.max_range, d[2] * s.max_range, d[0] * s.max_range)
        rays.append(((0.0, 0.0, 0.0), tip))
    return ProxSensor(s.name, s.body, s.link, s.origin, LEGACY_SENSOR_ORN, tuple(rays))
