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
# Columns are the sensor frame's axes in its link's frame: x_s = y_link, y_s = z_link, z_s = x_link
# (the World's ray fan looks along the link's +x; CoppeliaSim's sensors look along their +z).
_SENSOR_M: g.Mat = ((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0))
_SENSOR_Q = g.matrix_to_quat(_SENSOR_M)


class CommandError(Exception):
    """The command failed on the server side (reply with ``simx_return_remote_error_flag``)."""


# --- names and kinds ---------------------------------------------------------------------------
def resolve_name(world: Any, name: Any) -> int | None:
    """Handle of ``name``; like CoppeliaSim, ``name#`` and ``name#0`` mean ``name``."""
    if isinstance(name, bytes):
        name = name.decode("utf-8", "replace")
    name = str(name)
    h = world.handle(name)
    if h is None and "#" in name:
        base, _, suffix = name.rpartition("#")
        if suffix in ("", "0"):
            h = world.handle(base)
    return h


def _sensors(world: Any) -> dict[str, Any]:
    return {s.name: s for s in getattr(world.model, "sensors", [])}


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
    n = name(world, handle)
    if n in _joints(world):
        return sim_object_joint_type
    if n in _sensors(world):
        return sim_object_proximitysensor_type
    return sim_object_shape_type


def joint(world: Any, handle: int) -> Any:
    n = name(world, handle)
    j = _joints(world).get(n)
    if j is None:
        raise CommandError(f"object {n!r} is not a joint")
    return j


def objects(world: Any, object_type_: int) -> list[int]:
    handles = [world.handle(n) for n in world.names()]
    if object_type_ == sim_handle_all:
        return handles
    return [h for h in handles if object_type(world, h) == object_type_]


# --- frames ------------------------------------------------------------------------------------
def frame(world: Any, handle: int) -> tuple[g.Vec, g.Quat]:
    n = name(world, handle)
    pos, quat = world.object_pose(n)
    if n in _sensors(world):
        quat = g.matrix_to_quat(g.matmul(g.quat_to_matrix(quat), _SENSOR_M))
    return tuple(pos), tuple(quat)  # type: ignore[return-value]


def parent(world: Any, handle: int) -> int:
    """Parent handle in CoppeliaSim's object tree (-1 for a model base).

    The tree follows the pybullet link chain: a link's object hangs under the joint that moves
    it, a joint under the object of its parent link, a sensor under its link's object; a link
    without a named joint (a fixed caster) hangs under the object of its parent link.
    """
    n = name(world, handle)
    objects_, joints_ = _objects(world), _joints(world)
    body, link = _body_link(world, n)
    if n in _sensors(world):
        return _object_at(world, body, link)
    if n in objects_:
        if link < 0:
            return -1
        for j in joints_.values():
            if j.body == body and j.index == link:
                return int(world.handle(j.name))
    parent_link = p.getJointInfo(body, link, physicsClientId=world.client_id)[16]
    return _object_at(world, body, parent_link)


def _object_at(world: Any, body: int, link: int) -> int:
    for o in world.model.objects:
        if o.body == body and o.link == link:
            return int(world.handle(o.name))
    if link < 0:
        return -1
    return _object_at(world, body, p.getJointInfo(body, link, physicsClientId=world.client_id)[16])


def children(world: Any, handle: int) -> list[int]:
    name(world, handle)
    return [h for h in objects(world, sim_handle_all) if parent(world, h) == handle]


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
    if link < 0:
        lin, ang = p.getBaseVelocity(body, physicsClientId=cid)
        com = p.getBasePositionAndOrientation(body, physicsClientId=cid)[0]
    else:
        st = p.getLinkState(
            body, link, computeLinkVelocity=1, computeForwardKinematics=1, physicsClientId=cid
        )
        com, lin, ang = st[0], st[6], st[7]
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
    s = _sensors(world)[n]
    return s.body, s.link


# --- joints ------------------------------------------------------------------------------------
def joint_position(world: Any, handle: int) -> float:
    return float(world.joint_position(joint(world, handle).name))


def joint_force(world: Any, handle: int) -> float:
    j = joint(world, handle)
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
    j = joint(world, handle)
    p.resetJointState(j.body, j.index, (rad - j.zero) * j.sign, physicsClientId=world.client_id)


def joint_properties(world: Any, handle: int) -> tuple[int, int, float, float]:
    """(joint type, joint mode, lower limit, range or -1 when cyclic)."""
    j = joint(world, handle)
    if j.lower is None or j.upper is None:
        return 10, 5, -math.pi, -1.0
    return 10, 5, float(j.lower), float(j.upper - j.lower)


# --- proximity sensors -------------------------------------------------------------------------
def read_proximity_sensor(world: Any, handle: int) -> tuple[bool, g.Vec, int, g.Vec]:
    """(detected, point in the sensor frame, detected object handle, surface normal).

    The nearest hit of the sensor's rays wins. A detected object without a name in the scene
    (a wall, an obstacle) is reported with handle 0.
    """
    n = name(world, handle)
    sensor = _sensors(world).get(n)
    if sensor is None:
        raise CommandError(f"object {n!r} is not a proximity sensor")
    origin, link_quat = world.object_pose(n)
    m_link = g.quat_to_matrix(link_quat)
    starts, ends = [], []
    for d in sensor.rays():
        tip = g.apply(m_link, tuple(c * sensor.max_range for c in d))  # type: ignore[arg-type]
        starts.append(tuple(origin))
        ends.append((origin[0] + tip[0], origin[1] + tip[1], origin[2] + tip[2]))
    hits = [h for h in p.rayTestBatch(starts, ends, physicsClientId=world.client_id) if h[0] >= 0]
    if not hits:
        return False, (0.0, 0.0, 0.0), 0, (0.0, 0.0, 0.0)
    hit = min(hits, key=lambda h: h[2])
    m_s = g.matmul(m_link, _SENSOR_M)
    m_t = g.transpose(m_s)
    point = g.apply(m_t, (hit[3][0] - origin[0], hit[3][1] - origin[1], hit[3][2] - origin[2]))
    normal = g.apply(m_t, tuple(hit[4]))  # type: ignore[arg-type]
    return True, point, _handle_of_body(world, hit[0], hit[1]), normal


def _handle_of_body(world: Any, body: int, link: int) -> int:
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
