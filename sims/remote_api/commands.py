"""The server side of the commands: what CoppeliaSim does with each request, on a ``World``.

Every function takes the World and plain arguments and returns the reply values, or raises
``CommandError`` (the reply then carries the remote error flag, as CoppeliaSim's does for an
unknown handle or an object of the wrong kind). Frames are CoppeliaSim's: positions of an
object's frame, Euler angles ``R = Rx(a) Ry(b) Rz(g)``, quaternions ``(x, y, z, w)``. A
proximity sensor's frame has its z axis along the sensing direction, as in CoppeliaSim.
"""

from __future__ import annotations

import math
from typing import Any

import pybullet as p

from . import geometry as g
from .constants import (
    sim_handle_all,
    sim_handle_parent,
    sim_object_joint_type,
    sim_object_proximitysensor_type,
    sim_object_shape_type,
)

WORLD_FRAME = -1
#: simxGetObjects / group data object types by scene object kind.
OBJECT_TYPES = {
    "shape": sim_object_shape_type,
    "joint": sim_object_joint_type,
    "graph": 2,
    "camera": 3,
    "dummy": 4,
    "proximity_sensor": sim_object_proximitysensor_type,
    "path": 8,
    "vision_sensor": 9,
    "mill": 11,
    "force_sensor": 12,
    "light": 13,
    "mirror": 14,
    "octree": 15,
    "point_cloud": 16,
}


class CommandError(Exception):
    """The command failed on the server side (reply with ``simx_return_remote_error_flag``)."""


# --- names and kinds ---------------------------------------------------------------------------
def resolve_name(world: Any, name: Any) -> int | None:
    """Handle of ``name`` (an old-style name, ``name#``/``name#0``, or a 4.x object path)."""
    if isinstance(name, bytes):
        name = name.decode("utf-8", "replace")
    return world.find(str(name))


def nearest_names(world: Any, name: str, count: int = 3) -> tuple[str, ...]:
    """The scene's names (and aliases) closest to ``name`` (difflib), best first."""
    import difflib

    pool = sorted({e.name for e in world.tree()} | {e.alias for e in world.tree() if e.alias})
    return tuple(difflib.get_close_matches(name, pool, n=count, cutoff=0.5))


def _joints(world: Any) -> dict[str, Any]:
    return {j.name: j for j in world.model.joints}


def _objects(world: Any) -> dict[str, Any]:
    return {o.name: o for o in world.model.objects}


def name(world: Any, handle: int) -> str:
    n = world.name_of(handle) if isinstance(handle, int) else None
    if n is None:
        raise CommandError(f"object handle {handle} does not exist")
    return n


def object_type(world: Any, handle: int) -> int:
    name(world, handle)
    return OBJECT_TYPES.get(world.kind(handle), sim_object_shape_type)


def joint(world: Any, handle: int) -> Any:
    n = name(world, handle)
    j = world._joints.get(n)
    if j is None:
        raise CommandError(f"object {n!r} is not a joint")
    return j


def objects(world: Any, object_type_: int) -> list[int]:
    entries = world.tree()
    if object_type_ == sim_handle_all:
        return [e.handle for e in entries]
    return [
        e.handle for e in entries if OBJECT_TYPES.get(e.kind, sim_object_shape_type) == object_type_
    ]


# --- frames ------------------------------------------------------------------------------------
def frame(world: Any, handle: int) -> tuple[g.Vec, g.Quat]:
    """World pose of the object's frame (a proximity sensor's z is its sensing axis)."""
    pos, quat = world.object_pose(name(world, handle))
    return tuple(pos), tuple(quat)  # type: ignore[return-value]


def parent(world: Any, handle: int) -> int:
    """Parent handle in CoppeliaSim's object tree (-1 at the top)."""
    name(world, handle)
    up = world.parent(handle)
    return -1 if up is None else int(up)


def children(world: Any, handle: int) -> list[int]:
    name(world, handle)
    return [e.handle for e in world.tree() if e.parent == handle]


def _reference(
    world: Any, relative_to: int, handle: int | None = None
) -> tuple[g.Vec, g.Quat] | None:
    if relative_to == sim_handle_parent and handle is not None:
        relative_to = parent(world, handle)
    if relative_to == WORLD_FRAME:
        return None
    return frame(world, relative_to)


def position(world: Any, handle: int, relative_to: int) -> g.Vec:
    pos, _ = frame(world, handle)
    ref = _reference(world, relative_to, handle)
    return pos if ref is None else g.relative_position(pos, *ref)


def quaternion(world: Any, handle: int, relative_to: int) -> g.Quat:
    _, quat = frame(world, handle)
    ref = _reference(world, relative_to, handle)
    return quat if ref is None else g.matrix_to_quat(g.relative_matrix(quat, ref[1]))


def orientation(world: Any, handle: int, relative_to: int) -> g.Vec:
    _, quat = frame(world, handle)
    ref = _reference(world, relative_to, handle)
    m = g.quat_to_matrix(quat) if ref is None else g.relative_matrix(quat, ref[1])
    return g.matrix_to_euler(m)


def _base_ref(world: Any, handle: int) -> Any:
    n = name(world, handle)
    ref = _objects(world).get(n)
    if ref is None or ref.link != -1:
        raise CommandError(
            f"object {n!r} is part of a dynamic chain: only a model's base can be moved"
        )
    return ref


def set_frame(
    world: Any, handle: int, relative_to: int, pos: g.Vec | None, quat: g.Quat | None
) -> None:
    """Move a model's base object so that its frame is (pos, quat); None keeps that part."""
    ref = _base_ref(world, handle)
    cur_pos, cur_quat = frame(world, handle)
    reference = _reference(world, relative_to, handle)
    if pos is None:
        pos = cur_pos
    elif reference is not None:
        pos = g.to_world_position(pos, *reference)
    if quat is None:
        quat = cur_quat
    elif reference is not None:
        quat = g.to_world_quat(g.quat_to_matrix(quat), reference[1])
    cid = world.client_id
    inv_pos, inv_orn = p.invertTransform(ref.offset_pos, ref.offset_orn)
    link_pos, link_orn = p.multiplyTransforms(pos, quat, inv_pos, inv_orn)
    info = p.getDynamicsInfo(ref.body, -1, physicsClientId=cid)
    com_pos, com_orn = p.multiplyTransforms(link_pos, link_orn, info[3], info[4])
    p.resetBasePositionAndOrientation(ref.body, com_pos, com_orn, physicsClientId=cid)


def velocity(world: Any, handle: int) -> tuple[g.Vec, g.Vec]:
    """Linear velocity of the object's frame origin and angular velocity, world frame."""
    n = name(world, handle)
    body, link = _body_link(world, n)
    cid = world.client_id
    if body < 0:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    if link < 0:
        lin, ang = p.getBaseVelocity(body, physicsClientId=cid)
        com = p.getBasePositionAndOrientation(body, physicsClientId=cid)[0]
    else:
        st = p.getLinkState(
            body, link, computeLinkVelocity=1, computeForwardKinematics=1, physicsClientId=cid
        )
        com, lin, ang = st[0], st[6], st[7]
    if body < 0:
        return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    origin = world.object_pose(n)[0]
    r = (origin[0] - com[0], origin[1] - com[1], origin[2] - com[2])
    cross = (
        ang[1] * r[2] - ang[2] * r[1],
        ang[2] * r[0] - ang[0] * r[2],
        ang[0] * r[1] - ang[1] * r[0],
    )
    return (lin[0] + cross[0], lin[1] + cross[1], lin[2] + cross[2]), tuple(ang)  # type: ignore[return-value]


def _body_link(world: Any, n: str) -> tuple[int, int]:
    if n in _objects(world):
        o = _objects(world)[n]
        return o.body, o.link
    if n in _joints(world):
        j = _joints(world)[n]
        return j.body, j.index
    s = world._sensors[n]
    return s.body, s.link


# --- joints ------------------------------------------------------------------------------------
def joint_position(world: Any, handle: int) -> float:
    return float(world.joint_position(joint(world, handle).name))


def joint_force(world: Any, handle: int) -> float:
    j = joint(world, handle)
    if j.kind == "spherical":
        return 0.0
    torque = p.getJointState(j.body, j.index, physicsClientId=world.client_id)[3]
    return float(j.sign * torque)


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


# --- group data --------------------------------------------------------------------------------
def group_data(world: Any, object_type_: int, data_type: int) -> tuple[list, list, list, list]:
    """simxGetObjectGroupData: (handles, ints, floats, strings) for the supported data types."""
    from .constants import sim_appobj_object_type

    kind = sim_handle_all if object_type_ == sim_appobj_object_type else object_type_
    handles = objects(world, kind)
    ints: list[int] = []
    floats: list[float] = []
    strings: list[str] = []
    for h in handles:
        rel = sim_handle_parent if data_type in (4, 6, 8, 10, 12) else WORLD_FRAME
        if data_type == 0:
            strings.append(name(world, h))
        elif data_type == 1:
            ints.append(object_type(world, h))
        elif data_type == 2:
            ints.append(parent(world, h))
        elif data_type in (3, 4):
            floats += position(world, h, rel)
        elif data_type in (5, 6):
            floats += orientation(world, h, rel)
        elif data_type in (7, 8):
            floats += quaternion(world, h, rel)
        elif data_type in (9, 10):
            floats += position(world, h, rel) + orientation(world, h, rel)
        elif data_type in (11, 12):
            floats += position(world, h, rel) + quaternion(world, h, rel)
        elif data_type == 13:
            if object_type(world, h) == sim_object_proximitysensor_type:
                det, pt, obj, nrm = read_proximity_sensor(world, h)
                ints += [int(det), obj]
                floats += list(pt) + list(nrm)
            else:
                ints += [-1, -1]
                floats += [0.0] * 6
        elif data_type == 15:
            is_joint = object_type(world, h) == sim_object_joint_type
            floats += [joint_position(world, h), joint_force(world, h)] if is_joint else [0.0, 0.0]
        elif data_type == 16:
            if object_type(world, h) == sim_object_joint_type:
                jt, mode, lo, rng = joint_properties(world, h)
                ints += [jt, mode]
                floats += [lo, rng]
            else:
                ints += [-1, -1]
                floats += [0.0, 0.0]
        elif data_type in (17, 18, 19):
            lin, ang = velocity(world, h)
            floats += list(lin) * (data_type != 18) + list(ang) * (data_type != 17)
        else:
            raise CommandError(f"simxGetObjectGroupData data type {data_type} is not supported")
    return handles, ints, floats, strings
