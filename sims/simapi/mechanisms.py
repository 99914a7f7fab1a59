"""``sim.*`` functions on the scene's mechanisms: IK groups (``sim.getIkGroupHandle``,
``handleIkGroup``, ``getConfigForTipPose``, ``generateIkPath``) and V-REP 3.x path objects
(``sim.getPathPosition``, ``setPathPosition``, ``setPathTargetNominalVelocity``,
``followPath``...). The solving and the path curves are the World's (``world.kinematics``,
``world.paths``: sims/kinematics.py, sims/path_objects.py); this module binds them. A World
without them (a bundled scene) answers as CoppeliaSim does for a scene without IK groups or
paths: an error naming the object."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from .context import Caller, SimError
from .values import integer, number, numbers, table, text


def _kinematics(c: Caller) -> Any:
    kin = getattr(c.world, "kinematics", None)
    if kin is None:
        raise SimError("the scene has no IK groups")
    return kin


def get_ik_group_handle(c: Caller, name: Any) -> int:
    n = text(name)
    try:
        return int(_kinematics(c).group_handle(n))
    except KeyError:
        return c.not_found(f"IK group {n!r} does not exist", n)


def handle_ik_group(c: Caller, h: Any) -> int:
    try:
        return int(_kinematics(c).handle(integer(h, 1)))
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None


def get_config_for_tip_pose(
    c: Caller,
    group: Any,
    joints: Any,
    threshold: Any = 0.65,
    max_time: Any = 100,
    metric: Any = None,
    pairs: Any = None,
    options: Any = None,
    lows: Any = None,
    ranges: Any = None,
) -> Any:
    """A configuration that puts the group's tip on its target, or nil (a seeded search)."""
    hs = [c.handle(h) for h in table(joints)]
    kw: dict[str, Any] = {"threshold": number(threshold or 0.65, 3)}
    if metric is not None:
        kw["metric"] = tuple(numbers(metric))
    if lows is not None:
        kw["lows"] = numbers(lows)
    if ranges is not None:
        kw["ranges"] = numbers(ranges)
    try:
        found = _kinematics(c).config_for_tip_pose(integer(group, 1), hs, **kw)
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return None if found is None else [float(v) for v in found]


def generate_ik_path(c: Caller, group: Any, joints: Any, count: Any, *rest: Any) -> Any:
    """A straight tip path to the target, solved at ``count`` points: the joint values, point
    after point (nil when one point cannot be reached); the joints are left as they were."""
    from .poses import get_object_matrix, interpolate_matrices, set_object_matrix

    kin = _kinematics(c)
    g = integer(group, 1)
    hs = [c.handle(h) for h in table(joints)]
    n = max(2, integer(count, 3))
    try:
        tip, target = kin.tip_and_target(g)
    except (AttributeError, KeyError) as exc:
        raise SimError(f"IK group {g}: tip and target unknown ({exc})") from None
    start = [c.world.joint_position(h) for h in hs]
    m0, m1 = get_object_matrix(c, tip, -1), get_object_matrix(c, target, -1)
    out: list[float] = []
    ok = True
    for i in range(1, n + 1):
        set_object_matrix(c, target, -1, interpolate_matrices(c, m0, m1, i / n))
        if kin.handle(g) != 1:
            ok = False
            break
        out += [c.world.joint_position(h) for h in hs]
    set_object_matrix(c, target, -1, m1)
    for h, q in zip(hs, start, strict=True):
        c.world.set_joint_position(h, q)
    return out if ok else None


# -- paths ---------------------------------------------------------------------------------------
def _paths(c: Caller) -> Any:
    paths = getattr(c.world, "paths", None)
    if paths is None:
        raise SimError("the scene has no path objects")
    return paths


def _path_call(c: Caller, name: str, h: Any, *args: Any) -> Any:
    hh = c.handle(h)
    c.entry(hh)
    try:
        return getattr(_paths(c), name)(hh, *args)
    except KeyError as exc:
        raise SimError(str(exc).strip("'\"")) from None


def get_path_position(c: Caller, h: Any) -> float:
    return float(_path_call(c, "position", h))


def set_path_position(c: Caller, h: Any, s: Any) -> int | None:
    _path_call(c, "set_position", h, number(s, 2))
    return c.done


def get_path_length(c: Caller, h: Any) -> float:
    return float(_path_call(c, "length", h))


def set_path_target_nominal_velocity(c: Caller, h: Any, v: Any) -> int | None:
    paths = _paths(c)
    name = (
        "set_target_velocity" if hasattr(paths, "set_target_velocity") else "set_nominal_velocity"
    )
    _path_call(c, name, h, number(v, 2))
    return c.done


def get_position_on_path(c: Caller, h: Any, rel: Any) -> list[float]:
    length = get_path_length(c, h)
    pose = _path_call(c, "pose_at", h, number(rel, 2) * length)
    return [float(v) for v in pose[0]]


def get_orientation_on_path(c: Caller, h: Any, rel: Any) -> list[float]:
    from sims.remote_api import geometry as g

    length = get_path_length(c, h)
    pose = _path_call(c, "pose_at", h, number(rel, 2) * length)
    return list(g.quat_to_euler(tuple(pose[1])))


def follow_path(
    c: Caller, obj: Any, path: Any, what: Any, rel: Any, velocity: Any, accel: Any
) -> Iterator[None]:
    """3.x ``sim.followPath``: the object travels along the path from ``rel`` (0..1) to its
    end at ``velocity`` (m/s; the acceleration is taken as instant), position (bit 0 of
    ``what``) and/or orientation (bit 1); one step per pass. Returns the time left over."""
    from .poses import _set

    if not c.threaded:
        raise SimError("sim.followPath can only be called from a threaded script")
    h = c.handle(obj)
    length = get_path_length(c, path)
    s = number(rel, 4) * length
    v = abs(number(velocity, 5)) or 0.1
    bits = integer(what, 3)
    while True:
        pose = _path_call(c, "pose_at", path, min(s, length))
        _set(c, h, -1, pose[0] if bits & 1 else None, pose[1] if bits & 2 else None)
        if s >= length - 1e-9:
            return 0.0
        yield
        s += v * c.pass_dt


def get_path_distance(c: Caller, h: Any, point: Any) -> float:
    p = numbers(point)[:3]
    length = get_path_length(c, h)
    best = math.inf
    for i in range(201):
        q = _path_call(c, "pose_at", h, length * i / 200)[0]
        best = min(best, math.dist(p, q))
    return best
