"""The server side of the commands on scene objects: names, kinds, handles and frames.

Every function takes the World and plain arguments and returns the reply values, or raises
``CommandError`` (the reply then carries the remote error flag, as CoppeliaSim's does for an
unknown handle or an object of the wrong kind). Frames are CoppeliaSim's: positions of an
object's frame, Euler angles ``R = Rx(a) Ry(b) Rz(g)``, quaternions ``(x, y, z, w)``.
Callers use the one namespace ``sims.remote_api.commands``.
"""

from __future__ import annotations

from typing import Any

from sims.quiet import pybullet as p

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
    from sims.scene.paths import PathError

    if isinstance(name, bytes):
        name = name.decode("utf-8", "replace")
    try:
        return world.find(str(name))
    except PathError:
        return None


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
    try:
        return world.joint(n)
    except KeyError:
        raise CommandError(f"object {n!r} is not a joint") from None


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


def set_frame(
    world: Any, handle: int, relative_to: int, pos: g.Vec | None, quat: g.Quat | None
) -> None:
    """Move an object so that its frame is (pos, quat) relative to ``relative_to``; None keeps
    that part. What hangs on it moves with it, never what it hangs on (``World.set_object_pose``:
    a dummy on a mobile robot moves alone; a model's base moves the model)."""
    name(world, handle)
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
    try:
        world.set_object_pose(handle, (tuple(pos), tuple(quat)))
    except ValueError as exc:
        raise CommandError(str(exc)) from exc


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
    s = world.proximity_sensor(n)
    return s.body, s.link
