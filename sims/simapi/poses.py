"""``sim.*`` functions on frames: positions, orientations, quaternions, poses and matrices of
objects (relative to the world, an object, its parent, or a joint's base frame with
``sim.handleflag_reljointbaseframe``), velocities, and the matrix helpers (``sim.buildMatrix``,
``sim.multiplyVector``...). CoppeliaSim's conventions: Euler angles ``R = Rx(a) Ry(b) Rz(g)``,
quaternions ``(x, y, z, w)``, matrices 3x4 row by row (12 numbers), poses ``[x y z qx qy qz
qw]``. Setters accept both argument orders CoppeliaSim has had: ``(h, relativeTo, values)``
(before 4.7) and ``(h, values, relativeTo)``."""

from __future__ import annotations

import math
from typing import Any

from sims.remote_api import commands as cmd
from sims.remote_api import geometry as g

from .constants import ADDED
from .context import HANDLE_PARENT, WORLD, Caller, SimError
from .values import number, numbers, vector

REL_JOINT_BASE = ADDED["handleflag_reljointbaseframe"]
Frame = tuple[tuple[float, float, float], tuple[float, float, float, float]]


def object_frame(c: Caller, h: int) -> Frame:
    try:
        pos, q = c.world.object_pose(h)
    except KeyError:
        raise SimError(f"object handle {h} does not exist", "handle") from None
    return tuple(pos), tuple(q)  # type: ignore[return-value]


def _reference(c: Caller, h: int, rel: Any, position: int = 2) -> Frame | None:
    """The frame values are expressed in (None: the world)."""
    if rel is None:
        return None
    if isinstance(rel, bool) or not isinstance(rel, (int, float)):
        raise SimError(f"argument {position}: object handle expected, got {rel!r}")
    r = int(rel)
    base_frame = r >= 0 and bool(r & REL_JOINT_BASE)
    r = c.handle(r, position)
    if r == HANDLE_PARENT:
        up = c.world.parent_of_object(h)
        if up is None:
            return None
        r = up
    if r == WORLD:
        return None
    frame = object_frame(c, r)
    if not base_frame and c.world.is_joint(r):  # relative to a joint: its moving frame
        m = cmd.joint_matrix(c.world, r)
        rot = ((m[0], m[1], m[2]), (m[4], m[5], m[6]), (m[8], m[9], m[10]))
        pos = g.to_world_position((m[3], m[7], m[11]), *frame)
        frame = (pos, g.to_world_quat(rot, frame[1]))
    return frame


def _rel_pose(c: Caller, h: Any, rel: Any) -> Frame:
    h = c.handle(h)
    pos, q = object_frame(c, h)
    ref = _reference(c, h, rel)
    if ref is None:
        return pos, q
    return g.relative_position(pos, *ref), g.matrix_to_quat(g.relative_matrix(q, ref[1]))


def get_object_position(c: Caller, h: Any, rel: Any = WORLD) -> list[float]:
    return list(_rel_pose(c, h, rel)[0])


def get_object_quaternion(c: Caller, h: Any, rel: Any = WORLD) -> list[float]:
    return list(_rel_pose(c, h, rel)[1])


def get_object_orientation(c: Caller, h: Any, rel: Any = WORLD) -> list[float]:
    return list(g.quat_to_euler(_rel_pose(c, h, rel)[1]))


def get_object_pose(c: Caller, h: Any, rel: Any = WORLD) -> list[float]:
    pos, q = _rel_pose(c, h, rel)
    return [*pos, *q]


def get_object_matrix(c: Caller, h: Any, rel: Any = WORLD) -> list[float]:
    pos, q = _rel_pose(c, h, rel)
    return matrix_of(pos, q)


def matrix_of(pos: Any, q: Any) -> list[float]:
    m = g.quat_to_matrix(tuple(q))
    return [*m[0], pos[0], *m[1], pos[1], *m[2], pos[2]]


def frame_of(m: list[float]) -> Frame:
    rot = ((m[0], m[1], m[2]), (m[4], m[5], m[6]), (m[8], m[9], m[10]))
    return (m[3], m[7], m[11]), g.matrix_to_quat(_orthonormal(rot))


def _orthonormal(rot: Any) -> Any:
    from sims.remote_api.device_commands import _orthonormal as ortho

    return ortho(rot)


def _order(a: Any, b: Any) -> tuple[Any, Any]:
    """(values, relativeTo) from either argument order."""
    if isinstance(a, (list, tuple, dict)):
        return a, b
    return b, a


def _set(c: Caller, h: Any, rel: Any, pos: Any, quat: Any) -> None:
    h = c.handle(h)
    c.entry(h)
    ref = _reference(c, h, WORLD if rel is None else rel, 3)
    cur_pos, cur_q = object_frame(c, h)
    if pos is not None and ref is not None:
        pos = g.to_world_position(tuple(pos), *ref)
    if quat is not None and ref is not None:
        quat = g.to_world_quat(g.quat_to_matrix(tuple(quat)), ref[1])
    new = (tuple(pos) if pos is not None else cur_pos, tuple(quat) if quat is not None else cur_q)
    try:
        c.world.set_object_pose(h, new)
    except (ValueError, KeyError) as exc:
        raise SimError(str(exc).strip("'\"")) from None


def set_object_position(c: Caller, h: Any, a: Any, b: Any = WORLD) -> None:
    values, rel = _order(a, b)
    _set(c, h, rel, vector(values, 3, 3), None)


def set_object_orientation(c: Caller, h: Any, a: Any, b: Any = WORLD) -> None:
    values, rel = _order(a, b)
    _set(c, h, rel, None, g.euler_to_quat(tuple(vector(values, 3, 3))))


def set_object_quaternion(c: Caller, h: Any, a: Any, b: Any = WORLD) -> None:
    values, rel = _order(a, b)
    _set(c, h, rel, None, vector(values, 4, 3))


def set_object_pose(c: Caller, h: Any, a: Any, b: Any = WORLD) -> None:
    values, rel = _order(a, b)
    v = vector(values, 7, 3)
    _set(c, h, rel, v[:3], v[3:7])


def set_object_matrix(c: Caller, h: Any, a: Any, b: Any = WORLD) -> None:
    values, rel = _order(a, b)
    pos, q = frame_of(vector(values, 12, 3))
    _set(c, h, rel, pos, q)


def get_object_velocity(c: Caller, h: Any, opts: Any = 0) -> tuple[list[float], list[float]]:
    h = c.handle(h)
    c.entry(h)
    try:
        lin, ang = cmd.velocity(c.world, h)
    except (cmd.CommandError, KeyError) as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return [float(v) for v in lin], [float(v) for v in ang]


def get_velocity(c: Caller, h: Any) -> tuple[list[float], list[float]]:
    return get_object_velocity(c, h)


# -- matrices ------------------------------------------------------------------------------------
def build_identity_matrix(c: Caller) -> list[float]:
    return [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0]


def build_matrix(c: Caller, pos: Any, euler: Any) -> list[float]:
    return matrix_of(vector(pos, 3, 1), g.euler_to_quat(tuple(vector(euler, 3, 2))))


def build_matrix_q(c: Caller, pos: Any, quat: Any) -> list[float]:
    return matrix_of(vector(pos, 3, 1), vector(quat, 4, 2))


def build_pose(c: Caller, pos: Any, euler: Any, *rest: Any) -> list[float]:
    return [*vector(pos, 3, 1), *g.euler_to_quat(tuple(vector(euler, 3, 2)))]


def _m(values: Any, position: int = 1) -> list[float]:
    v = numbers(values)
    if len(v) == 7:  # a pose
        return matrix_of(v[:3], v[3:7])
    if len(v) < 12:
        raise SimError(f"argument {position}: matrix (12 numbers) or pose (7) expected")
    return v[:12]


def _mul(a: list[float], b: list[float]) -> list[float]:
    out = []
    for i in range(3):
        r = a[4 * i : 4 * i + 4]
        for j in range(4):
            out.append(r[0] * b[j] + r[1] * b[4 + j] + r[2] * b[8 + j] + (r[3] if j == 3 else 0.0))
    return out


def multiply_matrices(c: Caller, a: Any, b: Any) -> list[float]:
    return _mul(_m(a, 1), _m(b, 2))


def multiply_poses(c: Caller, a: Any, b: Any) -> list[float]:
    pos, q = frame_of(_mul(_m(a, 1), _m(b, 2)))
    return [*pos, *q]


def _inverse(m: list[float]) -> list[float]:
    r = [[m[0], m[4], m[8]], [m[1], m[5], m[9]], [m[2], m[6], m[10]]]
    t = [m[3], m[7], m[11]]
    ti = [-(r[i][0] * t[0] + r[i][1] * t[1] + r[i][2] * t[2]) for i in range(3)]
    return [*r[0], ti[0], *r[1], ti[1], *r[2], ti[2]]


def get_matrix_inverse(c: Caller, m: Any) -> list[float]:
    return _inverse(_m(m))


def invert_matrix(c: Caller, m: Any) -> list[float]:
    return get_matrix_inverse(c, m)


def get_pose_inverse(c: Caller, pose: Any) -> list[float]:
    pos, q = frame_of(_inverse(_m(pose)))
    return [*pos, *q]


def multiply_vector(c: Caller, m: Any, v: Any) -> list[float]:
    """A matrix (or pose) times a vector, or times a table of vectors (3 numbers each)."""
    mm, vals = _m(m), numbers(v)
    out: list[float] = []
    for i in range(0, len(vals) - 2, 3):
        x, y, z = vals[i : i + 3]
        out += [
            mm[4 * k] * x + mm[4 * k + 1] * y + mm[4 * k + 2] * z + mm[4 * k + 3] for k in range(3)
        ]
    return out


def get_euler_angles_from_matrix(c: Caller, m: Any) -> list[float]:
    return list(g.quat_to_euler(frame_of(_m(m))[1]))


def get_quaternion_from_matrix(c: Caller, m: Any) -> list[float]:
    return list(frame_of(_m(m))[1])


def get_rotation_axis(c: Caller, a: Any, b: Any) -> tuple[list[float], float]:
    """The axis (world) and angle that turn frame ``a`` into frame ``b``."""
    qa, qb = frame_of(_m(a, 1))[1], frame_of(_m(b, 2))[1]
    rel = g.matrix_to_quat(g.matmul(g.quat_to_matrix(qb), g.transpose(g.quat_to_matrix(qa))))
    angle = 2.0 * math.acos(max(-1.0, min(1.0, rel[3])))
    s = math.sqrt(max(0.0, 1.0 - rel[3] * rel[3]))
    axis = [rel[0] / s, rel[1] / s, rel[2] / s] if s > 1e-9 else [0.0, 0.0, 1.0]
    return axis, angle


def rotate_around_axis(c: Caller, m: Any, axis: Any, pos: Any, angle: Any) -> list[float]:
    """``m`` turned by ``angle`` about the axis through ``pos`` (a pose in, a pose out)."""
    pose_in = len(numbers(m)) == 7
    mm = _m(m, 1)
    ax = vector(axis, 3, 2)
    n = math.sqrt(sum(v * v for v in ax)) or 1.0
    a = number(angle, 4) / 2
    q = (ax[0] / n * math.sin(a), ax[1] / n * math.sin(a), ax[2] / n * math.sin(a), math.cos(a))
    p0 = vector(pos, 3, 3)
    rot = matrix_of([0.0, 0.0, 0.0], q)
    shift = [1.0, 0.0, 0.0, -p0[0], 0.0, 1.0, 0.0, -p0[1], 0.0, 0.0, 1.0, -p0[2]]
    back = [1.0, 0.0, 0.0, p0[0], 0.0, 1.0, 0.0, p0[1], 0.0, 0.0, 1.0, p0[2]]
    out = _mul(back, _mul(rot, _mul(shift, mm)))
    if pose_in:
        fp, fq = frame_of(out)
        return [*fp, *fq]
    return out


def interpolate_matrices(c: Caller, a: Any, b: Any, t: Any) -> list[float]:
    ma, mb, s = _m(a, 1), _m(b, 2), number(t, 3)
    fa, fb = frame_of(ma), frame_of(mb)
    pos = [fa[0][i] + (fb[0][i] - fa[0][i]) * s for i in range(3)]
    return matrix_of(pos, _slerp(fa[1], fb[1], s))


def interpolate_poses(c: Caller, a: Any, b: Any, t: Any) -> list[float]:
    pos, q = frame_of(interpolate_matrices(c, a, b, t))
    return [*pos, *q]


def _slerp(qa: Any, qb: Any, t: float) -> tuple[float, float, float, float]:
    dot = sum(x * y for x, y in zip(qa, qb, strict=True))
    if dot < 0:
        qb, dot = tuple(-v for v in qb), -dot
    if dot > 0.9995:
        out = [a + (b - a) * t for a, b in zip(qa, qb, strict=True)]
    else:
        th = math.acos(dot)
        sa, sb = math.sin((1 - t) * th) / math.sin(th), math.sin(t * th) / math.sin(th)
        out = [a * sa + b * sb for a, b in zip(qa, qb, strict=True)]
    n = math.sqrt(sum(v * v for v in out)) or 1.0
    return tuple(v / n for v in out)  # type: ignore[return-value]


def pose_to_matrix(c: Caller, pose: Any) -> list[float]:
    return _m(pose)


def matrix_to_pose(c: Caller, m: Any) -> list[float]:
    pos, q = frame_of(_m(m))
    return [*pos, *q]


def get_object_float_param_abs_velocity(c: Caller, h: int) -> list[float]:
    lin, ang = get_object_velocity(c, h)
    return lin + [math.sqrt(sum(v * v for v in ang))]
