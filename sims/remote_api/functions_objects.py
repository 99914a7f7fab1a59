"""The legacy remote API functions on the scene: objects, their frames, joints and sensors.

Signatures and return shapes are those of CoppeliaSim 4.2's ``sim.py``; see ``execute`` for
how operation modes and return codes behave. Each call reads or drives the World through
``commands`` (shared with the Lua layer). Connection and simulation control are in
``functions_session``; signals, parameters and helpers are in ``extras``.
"""

from __future__ import annotations

from . import commands as cmd
from .client import current_session, script_site
from .execute import (
    execute,
    f32,
    f32s,
    float_arg,
    int_arg,
    str_arg,
)

_Z3 = (0.0, 0.0, 0.0)


# --- objects -------------------------------------------------------------------------------------
def simxGetObjectHandle(clientID, objectName, operationMode):
    name = str_arg(objectName, 2)
    site = script_site()

    def run(world):
        h = cmd.resolve_name(world, name)
        if h is None:
            session = current_session()
            if session is not None:
                session.note_missing("object", name, site, cmd.nearest_names(world, name))
            raise cmd.CommandError(f"object {name!r} does not exist")
        session = current_session()
        if session is not None:
            session.found_objects += 1
        return (h,)

    code, out = execute(clientID, operationMode, ("handle", name), run, (0,))
    return code, out[0]


def simxGetObjects(clientID, objectType, operationMode):
    kind = int_arg(objectType, 2)
    code, out = execute(
        clientID, operationMode, ("objects", kind), lambda w: (cmd.objects(w, kind),), ([],)
    )
    return code, list(out[0])


def simxGetObjectParent(clientID, childObjectHandle, operationMode):
    h = int_arg(childObjectHandle, 2)
    code, out = execute(clientID, operationMode, ("parent", h), lambda w: (cmd.parent(w, h),), (0,))
    return code, out[0]


def simxGetObjectChild(clientID, parentObjectHandle, childIndex, operationMode):
    h, i = int_arg(parentObjectHandle, 2), int_arg(childIndex, 3)

    def run(world):
        kids = cmd.children(world, h)
        return (kids[i] if 0 <= i < len(kids) else -1,)

    code, out = execute(clientID, operationMode, ("child", h, i), run, (0,))
    return code, out[0]


def _getter3(clientID, handle, relative, operationMode, what: str, fn, n: int = 3):
    h, rel = int_arg(handle, 2), int_arg(relative, 3)
    code, out = execute(
        clientID, operationMode, (what, h, rel), lambda w: (f32s(fn(w, h, rel)),), ([0.0] * n,)
    )
    return code, list(out[0])


def simxGetObjectPosition(clientID, objectHandle, relativeToObjectHandle, operationMode):
    return _getter3(
        clientID, objectHandle, relativeToObjectHandle, operationMode, "position", cmd.position
    )


def simxGetObjectOrientation(clientID, objectHandle, relativeToObjectHandle, operationMode):
    """Euler angles (alpha, beta, gamma) in radians: R = Rx(alpha) Ry(beta) Rz(gamma)."""
    return _getter3(
        clientID,
        objectHandle,
        relativeToObjectHandle,
        operationMode,
        "orientation",
        cmd.orientation,
    )


def simxGetObjectQuaternion(clientID, objectHandle, relativeToObjectHandle, operationMode):
    return _getter3(
        clientID,
        objectHandle,
        relativeToObjectHandle,
        operationMode,
        "quaternion",
        cmd.quaternion,
        4,
    )


def _setter_frame(clientID, objectHandle, relative, values, n, operationMode, what, convert):
    h, rel = int_arg(objectHandle, 2), int_arg(relative, 3)
    vals = [float_arg(v, 4) for v in values]
    if len(vals) < n:
        raise IndexError("invalid index")
    vals = vals[:n]

    def run(world):
        pos, quat = convert(vals)
        cmd.set_frame(world, h, rel, pos, quat)
        return ()

    return execute(clientID, operationMode, (what, h, rel), run, (), setter=True)[0]


def simxSetObjectPosition(clientID, objectHandle, relativeToObjectHandle, position, operationMode):
    """Move a model's base object (other objects: remote error)."""
    return _setter_frame(
        clientID,
        objectHandle,
        relativeToObjectHandle,
        position,
        3,
        operationMode,
        "set_position",
        lambda v: (tuple(v), None),
    )


def simxSetObjectOrientation(
    clientID, objectHandle, relativeToObjectHandle, eulerAngles, operationMode
):
    from .geometry import euler_to_quat

    return _setter_frame(
        clientID,
        objectHandle,
        relativeToObjectHandle,
        eulerAngles,
        3,
        operationMode,
        "set_orientation",
        lambda v: (None, euler_to_quat(tuple(v))),
    )


def simxSetObjectQuaternion(
    clientID, objectHandle, relativeToObjectHandle, quaternion, operationMode
):
    return _setter_frame(
        clientID,
        objectHandle,
        relativeToObjectHandle,
        quaternion,
        4,
        operationMode,
        "set_quaternion",
        lambda v: (None, tuple(v)),
    )


def simxGetObjectVelocity(clientID, objectHandle, operationMode):
    h = int_arg(objectHandle, 2)

    def run(world):
        lin, ang = cmd.velocity(world, h)
        return f32s(lin), f32s(ang)

    code, out = execute(clientID, operationMode, ("velocity", h), run, ([0.0] * 3, [0.0] * 3))
    return code, list(out[0]), list(out[1])


# --- joints --------------------------------------------------------------------------------------
def _joint_float(clientID, jointHandle, operationMode, what, fn):
    h = int_arg(jointHandle, 2)
    code, out = execute(clientID, operationMode, (what, h), lambda w: (f32(fn(w, h)),), (0.0,))
    return code, out[0]


def _joint_set(clientID, jointHandle, value, operationMode, what, fn):
    h, v = int_arg(jointHandle, 2), float_arg(value, 3)

    def run(world):
        fn(world, h, f32(v))
        return ()

    return execute(clientID, operationMode, (what, h), run, (), setter=True)[0]


def simxGetJointPosition(clientID, jointHandle, operationMode):
    """Joint angle in radians, in CoppeliaSim's convention for that joint."""
    return _joint_float(clientID, jointHandle, operationMode, "joint_position", cmd.joint_position)


def simxGetJointForce(clientID, jointHandle, operationMode):
    return _joint_float(clientID, jointHandle, operationMode, "joint_force", cmd.joint_force)


simxJointGetForce = simxGetJointForce


def simxGetJointMaxForce(clientID, jointHandle, operationMode):
    return _joint_float(
        clientID, jointHandle, operationMode, "joint_max_force", cmd.joint_max_force
    )


def simxSetJointTargetPosition(clientID, jointHandle, targetPosition, operationMode):
    return _joint_set(
        clientID,
        jointHandle,
        targetPosition,
        operationMode,
        "joint_target_position",
        cmd.set_joint_target_position,
    )


def simxSetJointTargetVelocity(clientID, jointHandle, targetVelocity, operationMode):
    return _joint_set(
        clientID,
        jointHandle,
        targetVelocity,
        operationMode,
        "joint_target_velocity",
        cmd.set_joint_target_velocity,
    )


def simxSetJointPosition(clientID, jointHandle, position, operationMode):
    return _joint_set(
        clientID, jointHandle, position, operationMode, "joint_position_set", cmd.set_joint_position
    )


# --- sensors -------------------------------------------------------------------------------------
def simxReadProximitySensor(clientID, sensorHandle, operationMode):
    """(code, detectionState, detectedPoint, detectedObjectHandle, detectedSurfaceNormalVector);
    the point and normal are in the sensor's frame (z = sensing direction)."""
    h = int_arg(sensorHandle, 2)

    def run(world):
        detected, point, obj, normal = cmd.read_proximity_sensor(world, h)
        return detected, f32s(point), obj, f32s(normal)

    code, out = execute(
        clientID, operationMode, ("proximity", h), run, (False, list(_Z3), 0, list(_Z3))
    )
    return code, bool(out[0]), list(out[1]), out[2], list(out[3])


def simxGetObjectGroupData(clientID, objectType, dataType, operationMode):
    kind, data = int_arg(objectType, 2), int_arg(dataType, 3)

    def run(world):
        handles, ints, floats, strings = cmd.group_data(world, kind, data)
        return handles, ints, f32s(floats), strings

    code, out = execute(clientID, operationMode, ("group", kind, data), run, ([], [], [], []))
    return code, list(out[0]), list(out[1]), list(out[2]), list(out[3])


def simxGetVisionSensorImage(clientID, sensorHandle, options, operationMode):
    """(code, [width, height], image): rendered from the scene's vision sensor, bottom row
    first, signed bytes (RGB, or grey when bit 0 of ``options`` is set), as CoppeliaSim
    sends them."""
    h, grey = int_arg(sensorHandle, 2), bool(int_arg(options, 3) & 1)

    def run(world):
        return cmd.vision_image(world, h, grey)

    code, out = execute(clientID, operationMode, ("vision_image", h, grey), run, ([], []))
    return code, list(out[0]), list(out[1])


def simxSetJointForce(clientID, jointHandle, force, operationMode):
    """The joint's maximum force/torque (what its motor may apply)."""
    return _joint_set(
        clientID, jointHandle, force, operationMode, "joint_max_force_set", cmd.set_joint_force
    )


simxSetJointMaxForce = simxSetJointForce


def simxGetJointMatrix(clientID, jointHandle, operationMode):
    """(code, 12 values): the joint's intrinsic transformation, a 3x4 matrix row by row."""
    h = int_arg(jointHandle, 2)
    code, out = execute(
        clientID,
        operationMode,
        ("joint_matrix", h),
        lambda w: (f32s(cmd.joint_matrix(w, h)),),
        ([0.0] * 12,),
    )
    return code, list(out[0])


def simxSetSphericalJointMatrix(clientID, jointHandle, matrix, operationMode):
    """Orient a spherical joint by the rotation part of a 3x4 matrix (12 values, row by row)."""
    h = int_arg(jointHandle, 2)
    values = [float_arg(v, 3) for v in matrix]
    if len(values) < 12:
        raise IndexError("invalid index")

    def run(world):
        cmd.set_spherical_matrix(world, h, values[:12])
        return ()

    return execute(clientID, operationMode, ("spherical_matrix", h), run, (), setter=True)[0]
