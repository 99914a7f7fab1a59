"""The ``sim.*`` object, joint and sensor functions of the ZeroMQ remote API, on the World.

Signatures, return values and errors follow CoppeliaSim 4.3-4.8's regular API as the ZeroMQ
client sees it: one value returns as itself, several as a tuple, vectors as lists (positions
``[x, y, z]``, quaternions ``[qx, qy, qz, qw]``, poses ``[x, y, z, qx, qy, qz, qw]``); an unknown
object path or handle is an error (the client raises it). Setters accept both argument orders
CoppeliaSim accepts (``setObjectPosition(h, rel, pos)`` before 4.7, ``(h, pos, rel)`` after).
Geometry comes from the legacy API's ``commands`` (one definition of frames for both APIs).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from .. import commands as cmd
from . import paths
from .constants import HANDLE_ALL, HANDLE_PARENT, HANDLE_SCENE, HANDLE_WORLD, KIND_TYPES
from .registry import FUNCTIONS, Fn, api
from .server import ZmqServer


# --- objects -----------------------------------------------------------------------------------
@api("getObject")
def get_object(srv: ZmqServer, path: Any, options: Any = None) -> int:
    func = "sim.getObject"
    text = srv.string_arg(path, func, 1)
    opts = options if isinstance(options, dict) else {}
    index = srv.handle_arg(opts.get("index", 0) or 0, func, 2)
    try:
        h = paths.resolve(srv.tree(), text, index=index)
    except paths.PathError as exc:
        srv.fail("path", str(exc), func, text)
    if h is None:
        if opts.get("noError"):
            return -1
        near = paths.nearest(srv.tree(), text)
        srv.fail("path", f"object does not exist: {text!r}", func, text, near)
    return int(h)


@api("getObjectHandle")
def get_object_handle(srv: ZmqServer, name: Any, options: Any = None) -> int:
    """Deprecated since 4.3 but still served: old-style names and paths."""
    return get_object(srv, name, options)


@api("isHandle")
def is_handle(srv: ZmqServer, handle: Any) -> bool:
    return isinstance(handle, int) and handle in srv.tree().by_handle


@api("getObjectAlias")
def get_object_alias(srv: ZmqServer, handle: Any, options: Any = -1) -> str:
    """Options -1/0: the alias; 1 and up: the full path ``/a/b/c``."""
    e = srv.entry(handle, "sim.getObjectAlias")
    if isinstance(options, int) and options >= 1:
        return paths.full_path(srv.tree(), e.handle)
    return paths.alias_of(e)


@api("getObjectParent")
def get_object_parent(srv: ZmqServer, handle: Any) -> int:
    e = srv.entry(handle, "sim.getObjectParent")
    return int(e.parent) if e.parent is not None and e.parent in srv.tree().by_handle else -1


@api("getObjectChild")
def get_object_child(srv: ZmqServer, handle: Any, index: Any) -> int:
    e = srv.entry(handle, "sim.getObjectChild")
    kids = srv.tree().children.get(e.handle, [])
    i = srv.handle_arg(index, "sim.getObjectChild", 2)
    return int(kids[i].handle) if 0 <= i < len(kids) else -1


@api("getObjectType")
def get_object_type(srv: ZmqServer, handle: Any) -> int:
    e = srv.entry(handle, "sim.getObjectType")
    return KIND_TYPES.get(getattr(e, "kind", "shape"), 0)


def _tree_order(srv: ZmqServer, root: int | None) -> list[Any]:
    tree, out = srv.tree(), []

    def walk(parent: int | None) -> None:
        for e in tree.children.get(parent, []):
            out.append(e)
            walk(e.handle)

    walk(root)
    return out


@api("getObjectsInTree")
def get_objects_in_tree(
    srv: ZmqServer, base: Any, object_type: Any = HANDLE_ALL, options: Any = 0
) -> list[int]:
    """Bit 0 of ``options``: leave the base out; bit 1: only its direct children."""
    func = "sim.getObjectsInTree"
    kind = srv.handle_arg(object_type, func, 2)
    opts = srv.handle_arg(options, func, 3)
    if base == HANDLE_SCENE:
        found = _tree_order(srv, None)
    else:
        root = srv.entry(base, func)
        below = (
            srv.tree().children.get(root.handle, []) if opts & 2 else _tree_order(srv, root.handle)
        )
        found = ([] if opts & 1 else [root]) + list(below)
    return [
        int(e.handle)
        for e in found
        if kind == HANDLE_ALL or KIND_TYPES.get(getattr(e, "kind", "shape"), 0) == kind
    ]


@api("getObjects")
def get_objects(srv: ZmqServer, index: Any, object_type: Any = HANDLE_ALL) -> int:
    """The ``index``-th object of a type, or -1 past the last (the 4.x way to list objects)."""
    found = get_objects_in_tree(srv, HANDLE_SCENE, object_type)
    i = srv.handle_arg(index, "sim.getObjects", 1)
    return found[i] if 0 <= i < len(found) else -1


def _relative(srv: ZmqServer, value: Any, func: str, position: int) -> int:
    return HANDLE_WORLD if value is None else srv.handle_arg(value, func, position)


def _getter(name: str, run: Callable[..., Any]) -> Fn:
    func = "sim." + name

    def getter(srv: ZmqServer, handle: Any, relative_to: Any = HANDLE_WORLD) -> list[float]:
        h = srv.handle_arg(handle, func, 1)
        rel = _relative(srv, relative_to, func, 2)
        if rel == HANDLE_PARENT:
            rel = get_object_parent(srv, h)
        return [float(v) for v in srv.world_call(func, run, h, rel)]

    FUNCTIONS[func] = getter
    return getter


def _pose(world: Any, h: int, rel: int) -> list[float]:
    return list(cmd.position(world, h, rel)) + list(cmd.quaternion(world, h, rel))


_getter("getObjectPosition", cmd.position)
_getter("getObjectOrientation", cmd.orientation)
_getter("getObjectQuaternion", cmd.quaternion)
_getter("getObjectPose", _pose)


def _setter(name: str, n: int, convert: Callable[[list[float]], tuple]) -> Fn:
    func = "sim." + name

    def setter(srv: ZmqServer, handle: Any, a: Any, b: Any = HANDLE_WORLD) -> None:
        h = srv.handle_arg(handle, func, 1)
        # (handle, relativeTo, values) before 4.7; (handle, values, relativeTo) since
        values, rel = (a, b) if isinstance(a, list) else (b, a)
        vals = srv.vector_arg(values, n, func, 2 if values is a else 3)
        rel = _relative(srv, rel, func, 3 if values is a else 2)
        if rel == HANDLE_PARENT:
            rel = get_object_parent(srv, h)
        pos, quat = convert(vals)
        srv.world_call(func, cmd.set_frame, h, rel, pos, quat)

    FUNCTIONS[func] = setter
    return setter


def _euler(v: list[float]) -> tuple:
    from ..geometry import euler_to_quat

    return None, euler_to_quat((v[0], v[1], v[2]))


_setter("setObjectPosition", 3, lambda v: (tuple(v), None))
_setter("setObjectOrientation", 3, _euler)
_setter("setObjectQuaternion", 4, lambda v: (None, tuple(v)))
_setter("setObjectPose", 7, lambda v: (tuple(v[:3]), tuple(v[3:7])))


@api("getObjectVelocity")
def get_object_velocity(srv: ZmqServer, handle: Any) -> tuple[list[float], list[float]]:
    h = srv.handle_arg(handle, "sim.getObjectVelocity", 1)
    lin, ang = srv.world_call("sim.getObjectVelocity", cmd.velocity, h)
    return [float(v) for v in lin], [float(v) for v in ang]


# --- joints ------------------------------------------------------------------------------------
def _joint_getter(name: str, run: Callable[[Any, int], float]) -> None:
    func = "sim." + name

    def getter(srv: ZmqServer, handle: Any) -> float:
        return float(srv.world_call(func, run, srv.handle_arg(handle, func, 1)))

    FUNCTIONS[func] = getter


_joint_getter("getJointPosition", cmd.joint_position)
_joint_getter("getJointForce", cmd.joint_force)
_joint_getter("getJointVelocity", lambda w, h: w.joint_velocity(cmd.joint(w, h).name))


def _joint_setter(name: str, run: Callable[[Any, int, float], None], target: str | None) -> None:
    func = "sim." + name

    def setter(srv: ZmqServer, handle: Any, value: Any, *_motion: Any) -> None:
        h = srv.handle_arg(handle, func, 1)
        v = srv.number_arg(value, func, 2)
        if not math.isfinite(v):
            srv.fail("argument", f"argument 2: finite number expected, got {v!r}", func)
        srv.world_call(func, run, h, v)
        if target is not None:
            srv.targets[h] = (target, v)

    FUNCTIONS[func] = setter


_joint_setter("setJointTargetPosition", cmd.set_joint_target_position, "position")
_joint_setter("setJointTargetVelocity", cmd.set_joint_target_velocity, "velocity")
_joint_setter("setJointPosition", cmd.set_joint_position, None)


def _joint_target(kind: str) -> Fn:
    func = "sim.getJointTarget" + kind.capitalize()

    def getter(srv: ZmqServer, handle: Any) -> float:
        h = srv.handle_arg(handle, func, 1)
        srv.world_call(func, cmd.joint, h)
        got = srv.targets.get(h)
        if got is not None and got[0] == kind:
            return got[1]
        return float(srv.world_call(func, cmd.joint_position, h)) if kind == "position" else 0.0

    FUNCTIONS[func] = getter
    return getter


_joint_target("position")
_joint_target("velocity")


# --- sensors -----------------------------------------------------------------------------------
@api("readProximitySensor")
def read_proximity_sensor(srv: ZmqServer, handle: Any) -> tuple:
    """(result, distance, detectedPoint, detectedObjectHandle, normal); the point and normal in
    the sensor's frame. Nothing detected: (0, 0.0, [0, 0, 0], -1, [0, 0, 0])."""
    func = "sim.readProximitySensor"
    h = srv.handle_arg(handle, func, 1)
    detected, point, obj, normal = srv.world_call(func, cmd.read_proximity_sensor, h)
    if not detected:
        return 0, 0.0, [0.0, 0.0, 0.0], -1, [0.0, 0.0, 0.0]
    distance = math.sqrt(sum(c * c for c in point))
    return 1, distance, [float(c) for c in point], int(obj), [float(c) for c in normal]


FUNCTIONS["sim.handleProximitySensor"] = read_proximity_sensor


def _vision(srv: ZmqServer, handle: Any, func: str, grey: bool = False) -> tuple[bytes, list[int]]:
    """The sensor's image rendered from the scene (``sims.scene.camera``): bytes bottom row
    first, as CoppeliaSim sends them (scripts flip them with ``cv2.flip(img, 0)``)."""
    from sims.scene.camera import render_sensor

    e = srv.entry(handle, func)
    if getattr(e, "kind", "") != "vision_sensor":
        srv.fail("argument", f"object {paths.alias_of(e)!r} is not a vision sensor", func)
    try:
        rgb = render_sensor(srv.world, e.name)
    except (KeyError, ValueError) as exc:
        srv.fail("argument", str(exc).strip("'\""), func)
    rows = rgb[::-1]
    if grey:
        rows = rows.astype("float32").mean(axis=2).round()
    height, width = int(rgb.shape[0]), int(rgb.shape[1])
    return bytes(rows.astype("uint8").tobytes()), [width, height]


@api("getVisionSensorImg")
def get_vision_sensor_img(srv: ZmqServer, handle: Any, options: Any = 0, *_rest: Any) -> tuple:
    """(image bytes, [resX, resY]); bit 0 of ``options``: one grey byte per pixel."""
    grey = isinstance(options, int) and bool(options & 1)
    return _vision(srv, handle, "sim.getVisionSensorImg", grey)


@api("handleVisionSensor")
def handle_vision_sensor(srv: ZmqServer, handle: Any) -> tuple:
    """Renders (checks) the sensor; returns (detection count, packet 1, packet 2) = (0, [], [])
    as for a sensor without image processing filters."""
    _vision(srv, handle, "sim.handleVisionSensor")
    return 0, [], []
