"""The server side of the commands on joints and sensors: joint state and motors, joint
matrices, vision sensor images and proximity sensor reads, on a ``World``.

As in ``object_commands``: World and plain arguments in, reply values out, ``CommandError`` for
a handle of the wrong kind. A proximity sensor's frame has its z axis along the sensing
direction, as in CoppeliaSim. Callers use the one namespace ``sims.remote_api.commands``.
"""

from __future__ import annotations

import math
from typing import Any

from sims.quiet import pybullet as p

from . import geometry as g
from .object_commands import CommandError, joint, name


# --- joints ------------------------------------------------------------------------------------
def joint_position(world: Any, handle: int) -> float:
    return float(world.joint_position(joint(world, handle).name))


def joint_force(world: Any, handle: int) -> float:
    j = joint(world, handle)
    if j.kind == "spherical":
        return 0.0
    torque = p.getJointState(j.body, j.index, physicsClientId=world.client_id)[3]
    return float(torque)


def joint_max_force(world: Any, handle: int) -> float:
    return float(joint(world, handle).max_force)


def set_joint_target_position(world: Any, handle: int, rad: float) -> None:
    world.set_joint_target_position(joint(world, handle).name, rad)


def set_joint_target_velocity(world: Any, handle: int, rad_s: float) -> None:
    world.set_joint_target_velocity(joint(world, handle).name, rad_s)


def set_joint_position(world: Any, handle: int, rad: float) -> None:
    """Teleport a joint (its motor keeps its target, as in CoppeliaSim)."""
    world.set_joint_position(joint(world, handle).name, rad)


def set_joint_force(world: Any, handle: int, force: float) -> None:
    world.set_joint_max_force(joint(world, handle).name, abs(force))


def vision_image(world: Any, handle: int, grey: bool) -> tuple[list[int], list[int]]:
    from sims.scene.camera import image_for_remote_api, render_sensor

    n = name(world, handle)
    if world.kind(handle) != "vision_sensor":
        raise CommandError(f"object {n!r} is not a vision sensor")
    try:
        rgb = render_sensor(world, n)
    except (KeyError, ValueError) as exc:
        raise CommandError(str(exc)) from exc
    return image_for_remote_api(rgb, grey)


def joint_matrix(world: Any, handle: int) -> list[float]:
    """The joint's intrinsic transformation (its motion) as a 3x4 matrix, row by row."""
    j = joint(world, handle)
    cid = world.client_id
    if j.kind == "spherical":
        quat = p.getJointStateMultiDof(j.body, j.index, physicsClientId=cid)[0]
        if len(quat) != 4:
            quat = (0.0, 0.0, 0.0, 1.0)
        m, t = g.quat_to_matrix(tuple(quat)), (0.0, 0.0, 0.0)  # type: ignore[arg-type]
    else:
        q = world.joint_position(j.name)
        if j.kind == "prismatic":
            m, t = g.quat_to_matrix((0.0, 0.0, 0.0, 1.0)), (0.0, 0.0, q)
        else:
            m, t = g.quat_to_matrix((0.0, 0.0, math.sin(q / 2), math.cos(q / 2))), (0.0, 0.0, 0.0)
    return [v for row, tk in zip(m, t, strict=True) for v in (*row, tk)]


def set_spherical_matrix(world: Any, handle: int, values: list[float]) -> None:
    j = joint(world, handle)
    if j.kind != "spherical":
        raise CommandError(f"joint {j.name!r} is not spherical")
    rows = (tuple(values[0:3]), tuple(values[4:7]), tuple(values[8:11]))
    quat = g.matrix_to_quat(_orthonormal(rows))  # type: ignore[arg-type]
    p.resetJointStateMultiDof(j.body, j.index, list(quat), physicsClientId=world.client_id)
    world.moved()  # proximity readings see the new pose


def _orthonormal(m: tuple) -> g.Mat:
    """The nearest rotation (Gram-Schmidt on the columns; identity for a degenerate matrix)."""
    import numpy as np

    a = np.array(m, dtype=float)
    if not np.all(np.isfinite(a)) or abs(np.linalg.det(a)) < 1e-9:
        return ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    u, _, vt = np.linalg.svd(a)
    r = u @ vt
    if np.linalg.det(r) < 0:
        u[:, -1] *= -1
        r = u @ vt
    return tuple(tuple(float(x) for x in row) for row in r)  # type: ignore[return-value]


JOINT_TYPES = {"revolute": 10, "prismatic": 11, "spherical": 12}


def joint_properties(world: Any, handle: int) -> tuple[int, int, float, float]:
    """(joint type, joint mode, lower limit, range or -1 when cyclic): passive-mode joints
    report mode 0, every motor (force/torque mode) 5."""
    j = joint(world, handle)
    kind = JOINT_TYPES.get(j.kind, 10)
    mode = j.coppelia_mode if j.coppelia_mode is not None else (0 if j.mode == "hold" else 5)
    if j.lower is None or j.upper is None:
        return kind, mode, -math.pi, -1.0
    return kind, mode, float(j.lower), float(j.upper - j.lower)


# --- proximity sensors -------------------------------------------------------------------------
def read_proximity_sensor(world: Any, handle: int) -> tuple[bool, g.Vec, int, g.Vec]:
    """(detected, point in the sensor frame, detected object handle, surface normal).

    The nearest hit of the sensor's rays wins. A detected object without a name in the scene
    (a wall of a bundled arena) is reported with handle 0.
    """
    n = name(world, handle)
    if world.kind(handle) != "proximity_sensor":
        raise CommandError(f"object {n!r} is not a proximity sensor")
    hit = world.nearest_hit(n)
    if hit is None:
        return False, (0.0, 0.0, 0.0), 0, (0.0, 0.0, 0.0)
    _dist, point, normal, body, link = hit
    return True, tuple(point), _handle_of_body(world, body, link), tuple(normal)  # type: ignore[return-value]


def _handle_of_body(world: Any, body: int, link: int) -> int:
    owner = getattr(world.model, "data", {}).get(("link", body, link))
    if owner is not None:
        return int(world.handle(owner))
    for o in world.model.objects:
        if o.body == body and o.link == link:
            return int(world.handle(o.name))
    return 0
