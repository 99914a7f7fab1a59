"""The server side of the commands: what CoppeliaSim does with each request, on a ``World``.

One namespace (``from sims.remote_api import commands as cmd``) for the remote API functions
and the Lua layer: objects and frames live in ``object_commands``, joints and sensors in
``device_commands``; group data, which reads both, is here.

Every function takes the World and plain arguments and returns the reply values, or raises
``CommandError`` (the reply then carries the remote error flag, as CoppeliaSim's does for an
unknown handle or an object of the wrong kind). Frames are CoppeliaSim's: positions of an
object's frame, Euler angles ``R = Rx(a) Ry(b) Rz(g)``, quaternions ``(x, y, z, w)``. A
proximity sensor's frame has its z axis along the sensing direction, as in CoppeliaSim.
"""

from __future__ import annotations

from typing import Any

from .constants import (
    sim_handle_all,
    sim_handle_parent,
    sim_object_joint_type,
    sim_object_proximitysensor_type,
)
from .device_commands import (
    JOINT_TYPES,
    joint_force,
    joint_matrix,
    joint_max_force,
    joint_position,
    joint_properties,
    read_proximity_sensor,
    set_joint_force,
    set_joint_position,
    set_joint_target_position,
    set_joint_target_velocity,
    set_spherical_matrix,
    vision_image,
)
from .object_commands import (
    OBJECT_TYPES,
    WORLD_FRAME,
    CommandError,
    children,
    frame,
    joint,
    name,
    nearest_names,
    object_type,
    objects,
    orientation,
    parent,
    position,
    quaternion,
    resolve_name,
    set_frame,
    velocity,
)

__all__ = [
    "JOINT_TYPES",
    "OBJECT_TYPES",
    "WORLD_FRAME",
    "CommandError",
    "children",
    "frame",
    "group_data",
    "joint",
    "joint_force",
    "joint_matrix",
    "joint_max_force",
    "joint_position",
    "joint_properties",
    "name",
    "nearest_names",
    "object_type",
    "objects",
    "orientation",
    "parent",
    "position",
    "quaternion",
    "read_proximity_sensor",
    "resolve_name",
    "set_frame",
    "set_joint_force",
    "set_joint_position",
    "set_joint_target_position",
    "set_joint_target_velocity",
    "set_spherical_matrix",
    "velocity",
    "vision_image",
]


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
