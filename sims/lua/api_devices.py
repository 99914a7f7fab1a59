"""``sim.*`` functions on joints and sensors (proximity, vision)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from sims.remote_api import commands as cmd

from .api_core import Context, api

HANDLE_ALL, HANDLE_ALL_EXCEPT_EXPLICIT = -2, -3  # sim.handle_all, sim.handle_all_except_explicit


# -- joints ------------------------------------------------------------------------------------
def _joint_call(c: Context, h: Any, fn: Callable[..., Any], *args: Any) -> Any:
    try:
        return fn(c.world, c.handle(h), *args)
    except cmd.CommandError as exc:
        return c.state.fail(str(exc))


@api("getJointPosition")
def get_joint_position(c: Context, h: Any) -> Any:
    return _joint_call(c, h, cmd.joint_position)


@api("setJointPosition")
def set_joint_position(c: Context, h: Any, value: Any) -> Any:
    _joint_call(c, h, cmd.set_joint_position, float(value))
    return 1


@api("setJointTargetVelocity")
def set_joint_target_velocity(c: Context, h: Any, value: Any) -> Any:
    _joint_call(c, h, cmd.set_joint_target_velocity, float(value))
    return 1


@api("getJointTargetVelocity")
def get_joint_target_velocity(c: Context, h: Any) -> Any:
    j = _joint_call(c, h, cmd.joint)
    kind, value = c.world._commands.get(j.name, ("", 0.0))
    return value if kind == "velocity" else 0.0


@api("setJointTargetPosition")
def set_joint_target_position(c: Context, h: Any, value: Any) -> Any:
    _joint_call(c, h, cmd.set_joint_target_position, float(value))
    return 1


@api("getJointForce")
def get_joint_force(c: Context, h: Any) -> Any:
    return _joint_call(c, h, cmd.joint_force)


@api("setJointForce")
def set_joint_force(c: Context, h: Any, value: Any) -> Any:
    _joint_call(c, h, cmd.set_joint_force, float(value))
    return 1


@api("setJointMaxForce")
def set_joint_max_force(c: Context, h: Any, value: Any) -> Any:
    return set_joint_force(c, h, value)


@api("getJointVelocity")
def get_joint_velocity(c: Context, h: Any) -> Any:
    j = _joint_call(c, h, cmd.joint)
    return c.world.joint_velocity(j.name)


# -- sensors -----------------------------------------------------------------------------------
@api("readProximitySensor")
def read_proximity_sensor(c: Context, h: Any) -> Any:
    try:
        det, point, obj, normal = cmd.read_proximity_sensor(c.world, c.handle(h))
    except cmd.CommandError as exc:
        return c.state.fail(str(exc))
    if not det:
        return (0, 0.0, [0.0, 0.0, 0.0], -1, [0.0, 0.0, 0.0])
    return (1, math.sqrt(sum(v * v for v in point)), list(point), obj, list(normal))


@api("handleProximitySensor")
def handle_proximity_sensor(c: Context, h: Any) -> Any:
    """Cast now (the World's sensors="main-script" mode leaves explicit sensors to this):
    one sensor, or with sim.handle_all / sim.handle_all_except_explicit every such sensor,
    reporting the nearest detection of them all, as CoppeliaSim does."""
    sensors = c.world.proximity_sensors
    h = c.handle(h)
    if h in (HANDLE_ALL, HANDLE_ALL_EXCEPT_EXPLICIT):
        names = sensors.handle_all(except_explicit=h == HANDLE_ALL_EXCEPT_EXPLICIT)
        found = [(hit[0], n) for n in names if (hit := sensors.nearest(n)) is not None]
        if not found:
            return (0, 0.0, [0.0, 0.0, 0.0], -1, [0.0, 0.0, 0.0])
        return read_proximity_sensor(c, c.world.handle(min(found, key=lambda f: f[0])[1]))
    try:
        if c.world.kind(h) != "proximity_sensor":
            raise cmd.CommandError(f"object {cmd.name(c.world, h)!r} is not a proximity sensor")
        sensors.handle(cmd.name(c.world, h))
    except (cmd.CommandError, KeyError) as exc:
        return c.state.fail(str(exc).strip("'\""))
    return read_proximity_sensor(c, h)


@api("readVisionSensor")
def read_vision_sensor(c: Context, h: Any) -> Any:
    from .vision import read_vision_sensor as read

    try:
        detected, packet = read(c.world, c.handle(h))
    except (cmd.CommandError, KeyError, ValueError) as exc:
        return c.state.fail(str(exc))
    return (detected, packet)


@api("handleVisionSensor")
def handle_vision_sensor(c: Context, h: Any) -> Any:
    detected, packet = read_vision_sensor(c, h)
    return (1 if detected else 0, packet)


@api("getVisionSensorImage")
def get_vision_sensor_image(c: Context, h: Any, *rest: Any) -> Any:
    from sims.scene.camera import render_sensor

    h = c.handle(h)
    rgb = render_sensor(c.world, cmd.name(c.world, h))
    return [float(v) / 255.0 for v in rgb[::-1].reshape(-1)]
