"""``sim.*`` functions on joints (positions, motors, modes, intervals) and on forces (added
forces, force sensors), over the World's joint motors (``sims/joint_motors.py``)."""

from __future__ import annotations

import math
from typing import Any

from sims.quiet import pybullet as p
from sims.remote_api import commands as cmd

from .context import Caller, SimError
from .values import finite, integer, number, vector

#: sim.jointmode_* -> World joint modes (mech's set_joint_mode)
JOINT_MODES = {0: "passive", 1: "passive", 2: "ik", 4: "dependent", 5: "force"}
MODE_NUMBERS = {"passive": 0, "ik": 2, "dependent": 4, "force": 5}


def _joint(c: Caller, h: Any) -> int:
    """A joint handle; the commands check it (the hot path of motor scripts checks once)."""
    return c.handle(h)


def _run(fn: Any, *args: Any) -> Any:
    try:
        return fn(*args)
    except (cmd.CommandError, KeyError) as exc:
        text_ = str(exc).strip("'\"")
        raise SimError(text_, "handle" if "does not exist" in text_ else "argument") from None


def get_joint_position(c: Caller, h: Any) -> float:
    return float(_run(cmd.joint_position, c.world, _joint(c, h)))


def set_joint_position(c: Caller, h: Any, value: Any) -> int:
    v = finite(value, 2)
    _run(cmd.set_joint_position, c.world, _joint(c, h), v)
    return c.done


def set_joint_target_position(c: Caller, h: Any, value: Any, *motion: Any) -> int:
    v = finite(value, 2)
    _run(cmd.set_joint_target_position, c.world, _joint(c, h), v)
    return c.done


def set_joint_target_velocity(c: Caller, h: Any, value: Any, *motion: Any) -> int:
    v = finite(value, 2)
    _run(cmd.set_joint_target_velocity, c.world, _joint(c, h), v)
    return c.done


def _target(c: Caller, h: Any, kind: str) -> float:
    hh = _joint(c, h)
    _run(cmd.joint, c.world, hh)
    command = getattr(c.world, "motor_command", None)  # World.motor_command (issue 34)
    got = command(hh) if command is not None else c.world._commands.get(c.world.name_of(hh))
    if got is not None and got[0] == kind:
        return float(got[1])
    return get_joint_position(c, hh) if kind == "position" else 0.0


def get_joint_target_position(c: Caller, h: Any) -> float:
    return _target(c, h, "position")


def get_joint_target_velocity(c: Caller, h: Any) -> float:
    return _target(c, h, "velocity")


def get_joint_velocity(c: Caller, h: Any) -> float:
    j = _run(cmd.joint, c.world, _joint(c, h))
    return float(c.world.joint_velocity(j.name))


def get_joint_force(c: Caller, h: Any) -> float:
    return float(_run(cmd.joint_force, c.world, _joint(c, h)))


def set_joint_force(c: Caller, h: Any, value: Any) -> int:
    v = number(value, 2)
    _run(cmd.set_joint_force, c.world, _joint(c, h), v)
    return c.done


def set_joint_target_force(c: Caller, h: Any, value: Any, signed: Any = True) -> None:
    set_joint_force(c, h, value)


def get_joint_max_force(c: Caller, h: Any) -> float:
    return float(_run(cmd.joint_max_force, c.world, _joint(c, h)))


def get_joint_type(c: Caller, h: Any) -> int:
    return int(_run(cmd.joint_properties, c.world, _joint(c, h))[0])


def get_joint_interval(c: Caller, h: Any) -> tuple[bool, list[float]]:
    """(cyclic, [low, range])."""
    _kind, _mode, low, rng = _run(cmd.joint_properties, c.world, _joint(c, h))
    if rng < 0:
        return True, [-math.pi, 2 * math.pi]
    return False, [float(low), float(rng)]


def get_joint_mode(c: Caller, h: Any) -> tuple[int, int]:
    hh = _joint(c, h)
    _run(cmd.joint, c.world, hh)
    mode = getattr(c.world, "joint_mode", None)
    if mode is not None:
        name, hybrid = mode(hh)
        return MODE_NUMBERS.get(name, 5), int(bool(hybrid))
    got = c.store.object_params.get((hh, "mode"))
    if got is not None:
        return got
    return int(_run(cmd.joint_properties, c.world, hh)[1]), 0


def set_joint_mode(c: Caller, h: Any, mode: Any, opts: Any = 0) -> int:
    """Passive/IK/dependent joints are set, not driven (CoppeliaSim's kinematic modes); force
    mode gives the motor back (``World.set_joint_mode``, mech's; before it lands, a joint left
    to kinematics holds its position with its motor)."""
    hh = _joint(c, h)
    _run(cmd.joint, c.world, hh)
    m = integer(mode, 2)
    name = JOINT_MODES.get(m)
    if name is None:
        raise SimError(f"argument 2: unknown joint mode {m}")
    hybrid = bool(integer(opts, 3, 0) & 1)
    setter = getattr(c.world, "set_joint_mode", None)
    if setter is not None:
        setter(hh, name, hybrid)
    else:
        c.store.object_params[(hh, "mode")] = (MODE_NUMBERS[name], int(hybrid))
    return c.done


def is_dynamically_enabled(c: Caller, h: Any) -> bool:
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind == "joint":
        return get_joint_mode(c, hh)[0] == 5
    ref = c.world._carried(hh) if hasattr(c.world, "_carried") else None
    return ref is not None and ref.body >= 0


# -- forces --------------------------------------------------------------------------------------
def _body_link(c: Caller, hh: int) -> tuple[int, int]:
    name = c.world.name_of(hh)
    ref = c.world._objects.get(name)
    if ref is None or ref.body < 0:
        raise SimError(f"object {name!r} is not a dynamic shape")
    return ref.body, ref.link


def add_force(c: Caller, h: Any, position: Any, force: Any) -> int | None:
    """A force given in the shape's frame, acting at ``position`` (the shape's frame): the force
    at the centre of mass and the torque ``position x force``, both turned into world axes, as
    CoppeliaSim's simAddForce does; applied during the whole next simulation pass (CoppeliaSim
    clears added forces after handling the dynamics)."""
    hh = c.handle(h)
    c.entry(hh)
    body, link = _body_link(c, hh)
    r, f = vector(position, 3, 2), vector(force, 3, 3)
    t = (r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0])
    q = c.world.object_pose(hh)[1]
    fw = p.multiplyTransforms((0, 0, 0), q, f, (0, 0, 0, 1))[0]
    tw = p.multiplyTransforms((0, 0, 0), q, t, (0, 0, 0, 1))[0]
    _add(c, body, link, tuple(fw), None, tuple(tw))
    return c.done


def add_force_and_torque(c: Caller, h: Any, force: Any = None, torque: Any = None) -> int:
    """A force at the centre of mass and a torque (world axes), for the next pass."""
    hh = c.handle(h)
    c.entry(hh)
    body, link = _body_link(c, hh)
    f = tuple(vector(force, 3, 2)) if force is not None else (0.0, 0.0, 0.0)
    t = tuple(vector(torque, 3, 3)) if torque is not None else (0.0, 0.0, 0.0)
    _add(c, body, link, f, None, t)
    return c.done


def _add(c: Caller, body: int, link: int, force: Any, at: Any, torque: Any) -> None:
    """Keep an added force for the pass it was added for: applied now (for the next physics
    step) and, by a step hook, before each further physics step of that pass."""
    world = c.world
    state = getattr(world, "_added_forces", None)
    if state is None:
        state = world._added_forces = {"items": []}

        def apply_next(w: Any) -> None:
            items = state["items"]
            if items:
                items[:] = [i for i in items if i[1] <= w.steps < i[0]]
                _apply(w, [i[2] for i in items if i[1] != w.steps])

        world.add_step_hook(apply_next)
    spp = max(1, round(c.pass_dt / world.timestep))
    item = (body, link, force, at, torque)
    state["items"].append((world.steps + spp, world.steps, item))
    _apply(world, [item])


def _apply(world: Any, forces: list[Any]) -> None:
    cid = world.client_id
    for body, link, force, at, torque in forces:
        if at is None:
            com = (
                p.getBasePositionAndOrientation(body, physicsClientId=cid)[0]
                if link < 0
                else p.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=cid)[0]
            )
            at = tuple(com)
        if any(force):
            p.applyExternalForce(body, link, force, at, p.WORLD_FRAME, physicsClientId=cid)
        if torque is not None and any(torque):
            p.applyExternalTorque(body, link, torque, p.WORLD_FRAME, physicsClientId=cid)


# -- force sensors -------------------------------------------------------------------------------
def read_force_sensor(c: Caller, h: Any) -> tuple[int, list[float], list[float]]:
    """(state, force, torque) in the sensor's frame: the reaction of the fixed joint a force
    sensor is in pybullet (bit 0 of state: values available; bit 1: broken)."""
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "force_sensor":
        raise SimError(f"object {e.name!r} is not a force sensor")
    broken = c.store.object_params.get((hh, "broken"), False)
    j = c.world._joints.get(e.name)
    if j is None or broken:
        return (3 if broken else 1), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    cid = c.world.client_id
    if not c.store.object_params.get((hh, "ft_enabled")):
        p.enableJointForceTorqueSensor(j.body, j.index, True, physicsClientId=cid)
        c.store.object_params[(hh, "ft_enabled")] = True
    reaction = p.getJointState(j.body, j.index, physicsClientId=cid)[2]
    return 1, [float(v) for v in reaction[:3]], [float(v) for v in reaction[3:6]]


def break_force_sensor(c: Caller, h: Any) -> int:
    """The sensor breaks: what hangs on it comes loose (``World.break_force_sensor``, mech's);
    reading it reports broken."""
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "force_sensor":
        raise SimError(f"object {e.name!r} is not a force sensor")
    c.store.object_params[(hh, "broken")] = True
    breaker = getattr(c.world, "break_force_sensor", None)
    if breaker is not None:
        breaker(hh)
    return c.done
