"""``sim.*`` motion functions: Ruckig profiles (``sim.rmlPos``/``rmlVel``/``rmlStep``/
``rmlRemove`` and their 4.x names ``ruckig*``), and the blocking moves that step them once per
simulation pass (``sim.moveToConfig``, ``sim.moveToPose``, ``sim.rmlMoveToJointPositions``,
``sim.rmlMoveToPosition``), as CoppeliaSim's ``sim.lua`` writes them over ``sim.rmlStep``.

The blocking ones are generators (``sims.simapi.table``): they yield once per pass until the
motion is done, so a threaded script's coroutine, or a stepping ZeroMQ client, advances with
the simulation. Outside a thread CoppeliaSim's loop never yields (``sim.switchThread`` does
nothing there), so the whole motion happens in one call; the same here."""

from __future__ import annotations

import math
from collections.abc import Iterator
from typing import Any

from sims.motion import MotionError, Profile

from .context import Caller, SimError
from .poses import frame_of, get_rotation_axis, interpolate_matrices, matrix_of
from .values import integer, number, numbers, options, table, vector


def _profile(c: Caller, *args: Any, **kw: Any) -> Profile:
    try:
        return Profile(*args, **kw)
    except (MotionError, ValueError, TypeError) as exc:
        raise SimError(str(exc)) from None


# -- rmlPos / rmlVel objects ---------------------------------------------------------------------
def rml_pos(
    c: Caller,
    dofs: Any,
    smallest: Any,
    flags: Any,
    state: Any,
    limits: Any,
    selection: Any,
    target: Any,
) -> int:
    n, f = integer(dofs, 1), integer(flags, 3, -1)
    s, lim, tg = numbers(state), numbers(limits), numbers(target)
    if len(s) < 3 * n or len(lim) < 3 * n or len(tg) < 2 * n:
        raise SimError("argument tables are too short for the number of degrees of freedom")
    extra = lim[3 * n :]
    min_vel = extra[:n] if f >= 0 and f & 0x100 else None
    min_acc = (extra[n : 2 * n] if min_vel else extra[:n]) if f >= 0 and f & 0x200 else None
    prof = _profile(
        c,
        s[:n],
        s[n : 2 * n],
        s[2 * n : 3 * n],
        lim[:n],
        lim[n : 2 * n],
        lim[2 * n : 3 * n],
        tg[:n],
        tg[n : 2 * n],
        flags=f,
        selection=[bool(v) for v in numbers(selection)][:n] or None,
        min_velocity=min_vel,
        min_acceleration=min_acc,
        smallest_step=number(smallest, 2) or 1e-4,
    )
    h = c.store.new_handle("motion", 1)
    c.store.motions[h] = prof
    return h


def rml_vel(
    c: Caller,
    dofs: Any,
    smallest: Any,
    flags: Any,
    state: Any,
    limits: Any,
    selection: Any,
    target: Any,
) -> int:
    n, f = integer(dofs, 1), integer(flags, 3, -1)
    s, lim, tg = numbers(state), numbers(limits), numbers(target)
    prof = _profile(
        c,
        s[:n],
        s[n : 2 * n],
        s[2 * n : 3 * n],
        [],
        lim[:n],
        lim[n : 2 * n],
        s[:n],
        tg[:n],
        flags=f,
        velocity_control=True,
        selection=[bool(v) for v in numbers(selection)][:n] or None,
        smallest_step=number(smallest, 2) or 1e-4,
    )
    h = c.store.new_handle("motion", 1)
    c.store.motions[h] = prof
    return h


def rml_step(c: Caller, h: Any, dt: Any) -> tuple[int, list[float], float]:
    prof = c.store.motions.get(integer(h, 1))
    if prof is None:
        return -1, [], 0.0
    s = prof.step(number(dt, 2))
    return s.result, s.position + s.velocity + s.acceleration, s.time_left


def rml_remove(c: Caller, h: Any) -> int:
    return 1 if c.store.motions.pop(integer(h, 1), None) is not None else -1


# -- joints --------------------------------------------------------------------------------------
def _drive_joints(c: Caller, joints: list[int], conf: list[float]) -> None:
    """What sim.lua's callback does: a joint in force mode with dynamics follows the position
    as its motor's target, any other joint is put there."""
    from .joints import get_joint_mode

    for h, q in zip(joints, conf, strict=False):
        mode = get_joint_mode(c, h)[0]
        if mode == 5 and c.world.is_joint(h):
            c.world.set_joint_target_position(h, q)
        else:
            c.world.set_joint_position(h, q)
    c.world.moved()


def _cyclic(c: Caller, h: int) -> bool:
    from .joints import get_joint_interval, get_joint_type

    return get_joint_type(c, h) == 10 and get_joint_interval(c, h)[0]


def _move_to_config(
    c: Caller,
    flags: int,
    pos: list[float],
    vel: list[float],
    acc: list[float],
    max_vel: list[float],
    max_acc: list[float],
    max_jerk: list[float],
    target: list[float],
    target_vel: list[float],
    cyclic: list[bool],
    time_step: float,
    on_step: Any,
) -> Iterator[None]:
    n = len(pos)
    goal = list(target[:n])
    for i in range(n):
        if i < len(cyclic) and cyclic[i]:
            w = goal[i]
            while w - pos[i] >= 2 * math.pi:
                w -= 2 * math.pi
            while w - pos[i] < 0:
                w += 2 * math.pi
            if w - pos[i] > math.pi:
                w -= 2 * math.pi
            goal[i] = w
    prof = _profile(
        c,
        pos,
        (vel + [0.0] * n)[:n],
        (acc + [0.0] * n)[:n],
        max_vel[:n],
        max_acc[:n],
        max_jerk[:n],
        goal,
        (target_vel + [0.0] * n)[:n],
        flags=flags,
    )
    out = (list(pos), (vel + [0.0] * n)[:n], (acc + [0.0] * n)[:n], 0.0)
    while True:
        s = prof.step(time_step or c.pass_dt)
        out = (s.position, s.velocity, s.acceleration, 0.0 if s.result else -s.time_left)
        on_step(s)
        if s.result != 0:
            return out
        if c.threaded:
            yield


def rml_move_to_joint_positions(
    c: Caller,
    joints: Any,
    flags: Any,
    cur_vel: Any,
    cur_acc: Any,
    max_vel: Any,
    max_acc: Any,
    max_jerk: Any,
    target: Any,
    target_vel: Any = None,
    direction: Any = None,
):
    """(1, end position, end velocity, end acceleration, time left) once the joints are there."""
    hs = [c.handle(h) for h in table(joints)]
    for h in hs:
        c.entry(h)
    pos = [c.world.joint_position(h) for h in hs]
    goal = numbers(target)
    dirs = [int(v) for v in numbers(direction)] if direction is not None else [0] * len(hs)
    cyc = []
    for i, h in enumerate(hs):
        cy = _cyclic(c, h)
        if cy and i < len(dirs) and dirs[i] != 0:
            cy = False
            d = dirs[i]
            if d > 0:
                while goal[i] > pos[i] + 2 * math.pi * d:
                    goal[i] -= 2 * math.pi
                while goal[i] < pos[i] + 2 * math.pi * (d - 1):
                    goal[i] += 2 * math.pi
            else:
                while goal[i] < pos[i] + 2 * math.pi * d:
                    goal[i] += 2 * math.pi
                while goal[i] > pos[i] + 2 * math.pi * (d + 1):
                    goal[i] -= 2 * math.pi
        cyc.append(cy)
    end = yield from _move_to_config(
        c,
        integer(flags, 2, -1),
        pos,
        numbers(cur_vel),
        numbers(cur_acc),
        numbers(max_vel),
        numbers(max_acc),
        numbers(max_jerk),
        goal,
        numbers(target_vel),
        cyc,
        0.0,
        lambda s: _drive_joints(c, hs, s.position),
    )
    return 1, end[0], end[1], end[2], end[3]


def move_to_config(c: Caller, *args: Any):
    """4.3+: ``sim.moveToConfig(params)`` (joints, targetPos, maxVel... ; returns a table with
    pos, vel, accel, timeLeft); 4.1/4.2: ``(flags, currentPos, currentVel, currentAccel, maxVel,
    maxAccel, maxJerk, targetPos, targetVel, callback, auxData, cyclicJoints, timeStep)``."""
    if args and isinstance(args[0], dict):
        o = options(args[0])
        hs = [c.handle(h) for h in table(o.get("joints"))]
        pos = numbers(o.get("pos")) or [c.world.joint_position(h) for h in hs]
        cb = o.get("callback")
        cyc = [bool(v) for v in table(o.get("cyclicJoints"))] or [_cyclic(c, h) for h in hs]

        def on_step(s: Any) -> None:
            if cb is not None and not isinstance(cb, str):
                c.call(cb, s.position, s.velocity, s.acceleration, o.get("auxData"))
            elif hs:
                _drive_joints(c, hs, s.position)

        end = yield from _move_to_config(
            c,
            integer(o.get("flags", -1), 1),
            pos,
            numbers(o.get("vel")),
            numbers(o.get("accel")),
            numbers(o.get("maxVel")),
            numbers(o.get("maxAccel")),
            numbers(o.get("maxJerk")),
            numbers(o.get("targetPos")),
            numbers(o.get("targetVel")),
            cyc,
            float(o.get("timeStep") or 0.0),
            on_step,
        )
        return {"pos": end[0], "vel": end[1], "accel": end[2], "timeLeft": end[3]}
    a = list(args) + [None] * 13
    cb, aux = a[9], a[10]
    end = yield from _move_to_config(
        c,
        integer(a[0], 1, -1),
        numbers(a[1]),
        numbers(a[2]),
        numbers(a[3]),
        numbers(a[4]),
        numbers(a[5]),
        numbers(a[6]),
        numbers(a[7]),
        numbers(a[8]),
        [bool(v) for v in table(a[11])],
        float(a[12] or 0.0),
        lambda s: c.call(cb, s.position, s.velocity, s.acceleration, aux) if cb else None,
    )
    return end


# -- poses ---------------------------------------------------------------------------------------
def _move_to_pose(
    c: Caller,
    flags: int,
    start: list[float],
    max_vel: list[float],
    max_acc: list[float],
    max_jerk: list[float],
    goal: list[float],
    metric: list[float] | None,
    time_step: float,
    on_step: Any,
) -> Iterator[None]:
    axis, angle = get_rotation_axis(c, start, goal)
    del axis
    dt = time_step or c.pass_dt
    if metric:
        d = [
            (goal[3] - start[3]) * metric[0],
            (goal[7] - start[7]) * metric[1],
            (goal[11] - start[11]) * metric[2],
            angle * metric[3],
        ]
        dist = math.sqrt(sum(v * v for v in d))
        if dist <= 1e-6:
            return list(start), 0.0
        prof = _profile(
            c,
            [0.0],
            [0.0],
            [0.0],
            max_vel[:1],
            max_acc[:1],
            max_jerk[:1],
            [dist],
            [0.0],
            flags=flags,
        )
        while True:
            s = prof.step(dt)
            m = interpolate_matrices(c, start, goal, s.position[0] / dist)
            on_step(m, s.velocity, s.acceleration)
            if s.result != 0:
                return m, 0.0
            if c.threaded:
                yield
    dx = [goal[3] - start[3], goal[7] - start[7], goal[11] - start[11], angle]
    prof = _profile(
        c,
        [0.0] * 4,
        [0.0] * 4,
        [0.0] * 4,
        max_vel[:4],
        max_acc[:4],
        max_jerk[:4],
        dx,
        [0.0] * 4,
        flags=flags,
    )
    while True:
        s = prof.step(dt)
        t = s.position[3] / angle if abs(angle) > math.pi * 1e-5 else 0.0
        m = interpolate_matrices(c, start, goal, t)
        m[3], m[7], m[11] = (
            start[3] + s.position[0],
            start[7] + s.position[1],
            start[11] + s.position[2],
        )
        on_step(m, s.velocity, s.acceleration)
        if s.result != 0:
            return m, 0.0
        if c.threaded:
            yield


def _set_matrix(c: Caller, h: int, rel: Any, m: list[float]) -> None:
    from .poses import set_object_matrix

    set_object_matrix(c, h, rel, m)


def move_to_pose(c: Caller, *args: Any):
    """4.3+: ``sim.moveToPose(params)`` (object, targetPose [x y z qx qy qz qw], maxVel of 4 or
    1 with metric...; returns a table with pose and timeLeft); 4.1/4.2: ``(flags, currentMatrix,
    maxVel, maxAccel, maxJerk, targetMatrix, callback, auxData, metric, timeStep)``."""
    if args and isinstance(args[0], dict):
        o = options(args[0])
        obj = o.get("object")
        rel = o.get("relObject", -1)
        h = c.handle(obj) if obj is not None else None
        from .poses import get_object_pose

        start = numbers(o.get("pose")) or (get_object_pose(c, h, rel) if h is not None else [])
        goal = numbers(o.get("targetPose"))
        cb = o.get("callback")
        if len(start) < 7 or len(goal) < 7:
            raise SimError("moveToPose: 'targetPose' (and 'object' or 'pose') are needed")
        ms, mg = matrix_of(start[:3], start[3:7]), matrix_of(goal[:3], goal[3:7])

        def on_step(m: list[float], v: Any, a: Any) -> None:
            pos, q = frame_of(m)
            if cb is not None and not isinstance(cb, str):
                c.call(cb, [*pos, *q], v, a, o.get("auxData"))
            elif h is not None:
                _set_matrix(c, h, rel, m)

        mv = numbers(o.get("maxVel"))
        metric = numbers(o.get("metric")) or ([1.0, 1.0, 1.0, 0.1] if len(mv) < 4 else None)
        end, left = yield from _move_to_pose(
            c,
            integer(o.get("flags", -1), 1),
            ms,
            mv,
            numbers(o.get("maxAccel")),
            numbers(o.get("maxJerk")),
            mg,
            metric,
            float(o.get("timeStep") or 0.0),
            on_step,
        )
        pos, q = frame_of(end)
        return {"pose": [*pos, *q], "timeLeft": left}
    a = list(args) + [None] * 10
    cb, aux = a[6], a[7]
    metric = numbers(a[8]) or None
    end, left = yield from _move_to_pose(
        c,
        integer(a[0], 1, -1),
        vector(a[1], 12, 2),
        numbers(a[2]),
        numbers(a[3]),
        numbers(a[4]),
        vector(a[5], 12, 6),
        metric,
        float(a[9] or 0.0),
        lambda m, v, ac: c.call(cb, m, v, ac, aux) if cb else None,
    )
    return end, left


def rml_move_to_position(
    c: Caller,
    h: Any,
    rel: Any,
    flags: Any,
    cur_vel: Any,
    cur_acc: Any,
    max_vel: Any,
    max_acc: Any,
    max_jerk: Any,
    target_pos: Any = None,
    target_quat: Any = None,
    target_vel: Any = None,
):
    """(1, end position, end quaternion, [0]*4, [0]*4, time left) once the object is there."""
    from .poses import get_object_matrix, get_object_quaternion

    hh = c.handle(h)
    c.entry(hh)
    r = integer(rel, 2, -1)
    start = get_object_matrix(c, hh, r)
    pos = numbers(target_pos) or [start[3], start[7], start[11]]
    quat = numbers(target_quat) or get_object_quaternion(c, hh, r)
    goal = matrix_of(pos[:3], quat[:4])
    end, left = yield from _move_to_pose(
        c,
        integer(flags, 3, -1),
        start,
        numbers(max_vel),
        numbers(max_acc),
        numbers(max_jerk),
        goal,
        None,
        0.0,
        lambda m, v, a: _set_matrix(c, hh, r, m),
    )
    fpos, fq = frame_of(end)
    return 1, list(fpos), list(fq), [0.0] * 4, [0.0] * 4, left
