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
    got = c.world.motor_command(hh)
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
    ref = c.world.object_ref(hh)
    return ref is not None and ref.body >= 0


# -- forces --------------------------------------------------------------------------------------
def _dynamic_shape(c: Caller, h: Any) -> int:
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "shape":
        raise SimError(f"object {e.name!r} is not a shape")
    return hh


def add_force(c: Caller, h: Any, position: Any, force: Any) -> int | None:
    """A force given in the shape's frame, acting at ``position`` (the shape's frame), for the
    next simulation pass (``World.add_force``: CoppeliaSim clears added forces after handling
    the dynamics; a static shape ignores them)."""
    hh = _dynamic_shape(c, h)
    c.world.add_force(hh, tuple(vector(position, 3, 2)), tuple(vector(force, 3, 3)))
    return c.done


def add_force_and_torque(c: Caller, h: Any, force: Any = None, torque: Any = None) -> int:
    """A force at the centre of mass and a torque (world axes), for the next pass."""
    hh = _dynamic_shape(c, h)
    f = tuple(vector(force, 3, 2)) if force is not None else (0.0, 0.0, 0.0)
    t = tuple(vector(torque, 3, 3)) if torque is not None else (0.0, 0.0, 0.0)
    c.world.add_force_and_torque(hh, f, t)
    return c.done


# -- force sensors -------------------------------------------------------------------------------
def read_force_sensor(c: Caller, h: Any) -> tuple[int, list[float], list[float]]:
    """(state, force, torque) in the sensor's frame: the reaction of the fixed joint a force
    sensor is in pybullet (bit 0 of state: values available; bit 1: broken)."""
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "force_sensor":
        raise SimError(f"object {e.name!r} is not a force sensor")
    broken = c.world.force_sensor_broken(hh)
    j = c.world.force_sensor_joint(hh)
    if j is None or broken:
        return (3 if broken else 1), [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    body, index = j
    reaction = p.getJointState(body, index, physicsClientId=c.world.client_id)[2]
    return 1, [float(v) for v in reaction[:3]], [float(v) for v in reaction[3:6]]


def break_force_sensor(c: Caller, h: Any) -> int:
    """The sensor breaks: what hangs on it comes loose (``World.break_force_sensor``); reading
    it reports broken for the rest of the simulation."""
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "force_sensor":
        raise SimError(f"object {e.name!r} is not a force sensor")
    c.world.break_force_sensor(hh)
    return c.done
