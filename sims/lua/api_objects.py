"""``sim.*`` functions on objects: handles, names, the tree, poses, created objects."""

from __future__ import annotations

import math
import struct
from typing import Any

from sims.remote_api import commands as cmd
from sims.remote_api import geometry as g

from .api_core import WORLD, Context, _vec, api
from .runtime import numbers, text


# -- objects -----------------------------------------------------------------------------------
@api("getObjectHandle")
def get_object_handle(c: Context, name: Any) -> Any:
    n = text(name)
    found = c.host.find(n, c.script)
    if found is None:
        return c.host.not_found(c, f"object {n!r} does not exist")
    return found


@api("getObject")
def get_object(c: Context, path: Any, *rest: Any) -> Any:
    return get_object_handle(c, path)


@api("getObjectName")
def get_object_name(c: Context, h: Any) -> Any:
    h = c.handle(h)
    if h in c.host.created:
        return c.host.created[h]["name"]
    return cmd.name(c.world, h)


@api("setObjectName")
def set_object_name(c: Context, h: Any, name: Any) -> Any:
    h = c.handle(h)
    if h not in c.host.created:
        return c.state.fail("only objects created by scripts can be renamed here")
    n = text(name)
    if c.host.find(n) is not None:
        return c.host.not_found(c, f"an object named {n!r} exists already")
    c.host.created[h]["name"] = n
    return 1


@api("getObjectType")
def get_object_type(c: Context, h: Any) -> Any:
    h = c.handle(h)
    if h in c.host.created:
        return c.host.created[h]["type"]
    return cmd.object_type(c.world, h)


@api("getObjectParent")
def get_object_parent(c: Context, h: Any) -> Any:
    h = c.handle(h)
    if h in c.host.created:
        return c.host.created[h].get("parent", -1)
    if h in c.host.parents:
        return c.host.parents[h]
    return cmd.parent(c.world, h)


@api("getObjectChild")
def get_object_child(c: Context, h: Any, index: Any) -> Any:
    h = c.handle(h)
    if h not in c.host.created:
        c.check(h)
    kids = [e.handle for e in c.world.tree() if get_object_parent(c, e.handle) == h]
    kids += [k for k, o in c.host.created.items() if o.get("parent", -1) == h]
    i = int(index)
    return kids[i] if 0 <= i < len(kids) else -1


@api("getObjectsInTree")
def get_objects_in_tree(c: Context, base: Any, kind: Any = -2, options: Any = 0) -> Any:
    base, kind, options = c.handle(base), int(kind), int(options or 0)
    tree = c.world.tree()
    if base == -12 or base == -1:  # sim.handle_scene
        found = [e.handle for e in tree]
    else:
        below = {base}
        found = [base]
        for e in tree:  # parents come before children in the World's handle order
            if e.parent in below:
                below.add(e.handle)
                found.append(e.handle)
        if options & 2:  # only the first children
            found = [base] + [e.handle for e in tree if e.parent == base]
        if options & 1:
            found = found[1:]
    if kind != -2:
        found = [h for h in found if cmd.object_type(c.world, h) == kind]
    return found


@api("getObjectAssociatedWithScript")
def get_object_associated_with_script(c: Context, h: Any) -> Any:
    return c.script.object


def _pose(c: Context, h: int) -> tuple[tuple, tuple]:
    if h in c.host.created:
        o = c.host.created[h]
        return tuple(o["pos"]), tuple(o["quat"])
    return cmd.frame(c.world, h)


def _ref(c: Context, h: int, rel: int) -> tuple[tuple, tuple] | None:
    if rel == -11:
        rel = get_object_parent(c, h)
    if rel == WORLD:
        return None
    return _pose(c, rel)


@api("getObjectPosition")
def get_object_position(c: Context, h: Any, rel: Any = -1) -> Any:
    h, rel = c.handle(h), c.handle(rel, True)
    pos, _ = _pose(c, h)
    ref = _ref(c, h, rel)
    return list(pos if ref is None else g.relative_position(pos, *ref))


@api("getObjectOrientation")
def get_object_orientation(c: Context, h: Any, rel: Any = -1) -> Any:
    h, rel = c.handle(h), c.handle(rel, True)
    _, q = _pose(c, h)
    ref = _ref(c, h, rel)
    m = g.quat_to_matrix(q) if ref is None else g.relative_matrix(q, ref[1])
    return list(g.matrix_to_euler(m))


@api("getObjectQuaternion")
def get_object_quaternion(c: Context, h: Any, rel: Any = -1) -> Any:
    h, rel = c.handle(h), c.handle(rel, True)
    _, q = _pose(c, h)
    ref = _ref(c, h, rel)
    return list(q if ref is None else g.matrix_to_quat(g.relative_matrix(q, ref[1])))


@api("getObjectMatrix")
def get_object_matrix(c: Context, h: Any, rel: Any = -1) -> Any:
    h, rel = c.handle(h), c.handle(rel, True)
    pos, q = _pose(c, h)
    ref = _ref(c, h, rel)
    if ref is None:
        m = g.quat_to_matrix(q)
    else:
        pos, m = g.relative_position(pos, *ref), g.relative_matrix(q, ref[1])
    return [*m[0], pos[0], *m[1], pos[1], *m[2], pos[2]]


def _set_pose(c: Context, h: int, rel: int, pos: Any, quat: Any) -> Any:
    if h in c.host.created:
        o = c.host.created[h]
        ref = _ref(c, h, rel)
        if pos is not None:
            o["pos"] = list(pos if ref is None else g.to_world_position(pos, *ref))
        if quat is not None:
            o["quat"] = list(
                quat if ref is None else g.to_world_quat(g.quat_to_matrix(quat), ref[1])
            )
        return 1
    if rel == -11:
        rel = cmd.parent(c.world, h)
    try:
        cmd.set_frame(c.world, h, rel, pos, quat)
    except cmd.CommandError as exc:
        return c.state.fail(str(exc))
    return 1


@api("setObjectPosition")
def set_object_position(c: Context, h: Any, rel: Any, pos: Any) -> Any:
    return _set_pose(c, c.handle(h), c.handle(rel, True), tuple(_vec(pos)), None)


@api("setObjectOrientation")
def set_object_orientation(c: Context, h: Any, rel: Any, euler: Any) -> Any:
    q = g.euler_to_quat(tuple(_vec(euler)))
    return _set_pose(c, c.handle(h), c.handle(rel, True), None, q)


@api("setObjectQuaternion")
def set_object_quaternion(c: Context, h: Any, rel: Any, quat: Any) -> Any:
    return _set_pose(c, c.handle(h), c.handle(rel, True), None, tuple(_vec(quat, 4)))


@api("setObjectMatrix")
def set_object_matrix(c: Context, h: Any, rel: Any, matrix: Any) -> Any:
    m = _vec(matrix, 12)
    rot = ((m[0], m[1], m[2]), (m[4], m[5], m[6]), (m[8], m[9], m[10]))
    return _set_pose(
        c, c.handle(h), c.handle(rel, True), (m[3], m[7], m[11]), g.matrix_to_quat(rot)
    )


@api("createDummy")
def create_dummy(c: Context, size: Any, colors: Any = None) -> Any:
    return c.host.create("Dummy", 4, {"size": float(size)})


@api("createOctree")
def create_octree(c: Context, voxel_size: Any, options: Any = 0, point_size: Any = 1) -> Any:
    return c.host.create("Octree", 15, {"voxel_size": float(voxel_size), "voxels": []})


@api("insertVoxelsIntoOctree")
def insert_voxels(
    c: Context, h: Any, options: Any, points: Any, color: Any = None, tag: Any = None
) -> Any:
    h = c.handle(h)
    o = c.host.created.get(h)
    if o is None or o["type"] != 15:
        return c.state.fail("object is not an octree")
    pts = numbers(points)
    size = o["voxel_size"]
    cells = {tuple(math.floor(v / size) for v in pts[i : i + 3]) for i in range(0, len(pts) - 2, 3)}
    before = len(o["voxels"])
    o["voxels"] = sorted(set(o["voxels"]) | cells)
    return len(o["voxels"]) - before


@api("removeObject")
def remove_object(c: Context, h: Any) -> Any:
    h = c.handle(h)
    if h in c.host.created:
        del c.host.created[h]
        return 1
    return c.state.fail("objects loaded with the scene cannot be removed in this emulation")


@api("getObjectSelection")
def get_object_selection(c: Context) -> Any:
    return None  # headless: nothing is ever selected


@api("getObjectSizeFactor")
def get_object_size_factor(c: Context, h: Any) -> Any:
    c.check(c.handle(h))
    return 1.0  # objects keep the size they were saved with


@api("getObjectSpecialProperty")
def get_special(c: Context, h: Any) -> Any:
    h = c.handle(h)
    c.check(h)
    return c.host.special.get(h, 0x01F0 | 0x0001 | 0x0002 | 0x0200)


@api("setObjectSpecialProperty")
def set_special(c: Context, h: Any, value: Any) -> Any:
    h = c.handle(h)
    c.check(h)
    c.host.special[h] = int(value)
    return 1


@api("resetDynamicObject")
def reset_dynamic_object(c: Context, h: Any) -> Any:
    c.check(c.handle(h))
    return 1  # pybullet keeps no separate dynamic state to reset


@api("getConfigurationTree")
def get_configuration_tree(c: Context, h: Any) -> Any:
    h = c.handle(h)
    tree = get_objects_in_tree(c, h, -2, 0)
    out = []
    for o in tree:
        pos, q = _pose(c, o)
        jp = c.world.joint_position(o) if c.world.is_joint(o) else 0.0
        out += [o, *pos, *q, jp]
    return struct.pack(f"<{len(out)}d", *out)


@api("setConfigurationTree")
def set_configuration_tree(c: Context, data: Any) -> Any:
    raw = bytes(data)
    vals = struct.unpack(f"<{len(raw) // 8}d", raw)
    for i in range(0, len(vals) - 8, 9):
        h = int(vals[i])
        if c.world.is_joint(h):
            c.world.set_joint_position(h, vals[i + 8])
    for i in range(0, len(vals) - 8, 9):  # the base last: its children follow it
        h = int(vals[i])
        if cmd.parent(c.world, h) == -1 and not c.world.is_joint(h):
            try:
                cmd.set_frame(c.world, h, WORLD, vals[i + 1 : i + 4], vals[i + 4 : i + 8])
            except cmd.CommandError:
                pass
    return 1
