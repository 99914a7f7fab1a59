"""The rays that sample a proximity sensor's detection volume, in the sensor's frame.

CoppeliaSim computes the exact minimum distance between its volume and every detectable shape;
pybullet has ray tests, so each volume is sampled by a few rays from the near surface (``offset``)
to the far one (``range``), along +z as CoppeliaSim's sensors look: a ray volume is one ray; a
cone or disc a fan within its opening angle; a pyramid or cylinder a 3 x 3 bundle. The nearest
hit of any ray is the detection, so a thin object between two rays can be missed.
"""

from __future__ import annotations

import math

from sims.scene.model import ProximitySensorData

Vec3 = tuple[float, float, float]
RING = 8  # rays per ring of a cone


def _toward(direction: Vec3, near: float, far: float) -> tuple[Vec3, Vec3]:
    dx, dy, dz = direction
    n = math.sqrt(dx * dx + dy * dy + dz * dz) or 1.0
    dx, dy, dz = dx / n, dy / n, dz / n
    return (dx * near, dy * near, dz * near), (dx * far, dy * far, dz * far)


def rays(data: ProximitySensorData) -> tuple[tuple[Vec3, Vec3], ...]:
    near = max(0.0, data.offset)
    far = data.range if data.range > near else near + data.range
    if far <= near:
        far = near + 1e-3
    half = max(0.0, data.angle) / 2
    kind = data.volume
    if kind in ("cone", "disc") and half <= 1e-6:
        kind = "ray"
    if kind == "cone":
        out = [_toward((0.0, 0.0, 1.0), near, far)]
        for tilt in (half / 2, half):
            for k in range(RING):
                a = 2 * math.pi * k / RING
                d = (math.sin(tilt) * math.cos(a), math.sin(tilt) * math.sin(a), math.cos(tilt))
                out.append(_toward(d, near, far))
        return tuple(out)
    if kind == "disc":  # a flat sector in the sensor's x-z plane
        count = 9
        angles = [-half + 2 * half * i / (count - 1) for i in range(count)]
        return tuple(_toward((math.sin(a), 0.0, math.cos(a)), near, far) for a in angles)
    if kind in ("pyramid", "cylinder"):
        sx, sy = data.size
        if kind == "cylinder":
            sx = sy = max(sx, sy)
        out = []
        for gx in (-0.5, 0.0, 0.5):
            for gy in (-0.5, 0.0, 0.5):
                x, y = gx * sx * 0.9, gy * sy * 0.9
                out.append(((x, y, near), (x, y, far)))
        return tuple(out)
    return (((0.0, 0.0, near), (0.0, 0.0, far)),)
