"""A loaded scene model becomes pybullet bodies, following CoppeliaSim's dynamics rules.

How the object tree maps onto multibodies (CoppeliaSim's "designing dynamic simulations"):
- a *dynamic* (non-static) shape is a rigid body. It is a link of its parent's body only when
  its parent is a joint or a force sensor (the joint's first dynamic child); a dynamic shape
  parented directly to another shape is a separate, free body, as in CoppeliaSim;
- a joint (revolute, prismatic, spherical) is a pybullet joint whose axis is the joint frame's
  z; a force sensor is a fixed joint. A joint without a dynamic child still moves what hangs on
  it, carried by a light virtual link. A joint under no moving body starts a fixed-base body;
- static shapes, dummies, sensors, cameras and lights ride on the nearest moving link above them
  (static shapes add their geometry to it); at the top they are fixed in the world;
- respondable shapes collide, CoppeliaSim's respondable masks deciding which pairs; two links
  joined directly by a joint do not (their meshes, as convex hulls, overlap at the pivot);
  non-respondable shapes are only seen by proximity sensors.
Each pybullet link is built in the saved pose with the joint at its saved position, so a joint
reports CoppeliaSim's value directly (``JointRef.zero = 0``) and frames need no conversion.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

from sims.models.common import (
    CameraSetup,
    JointRef,
    ObjectRef,
    ProxSensor,
    SceneModel,
    TreeNode,
    add_checker_floor,
)
from sims.quiet import pybullet as p
from sims.scene import loops
from sims.scene import sensors as sensor_rays
from sims.scene import shapes as S
from sims.scene.bodies import IDENTITY_TF, STATIC, Body, Created, Link, Tf, create_body, inv, mul
from sims.scene.model import Pose, Scene, SceneObject

MOVING = ("revolute", "prismatic", "spherical")
HOLD_MODES = ("passive", "ik", "dependent")


def _tf(pose: Pose) -> Tf:
    return pose.position, pose.quaternion


def _displacement(obj: SceneObject) -> Tf:
    j = obj.joint
    if j is not None and j.kind == "spherical":
        rotation = getattr(j, "spherical_rotation", None)
        return ((0.0, 0.0, 0.0), tuple(rotation)) if rotation else IDENTITY_TF
    if j is None:
        return IDENTITY_TF
    if j.kind == "prismatic":
        return (0.0, 0.0, j.position), (0.0, 0.0, 0.0, 1.0)
    return (0.0, 0.0, 0.0), (0.0, 0.0, math.sin(j.position / 2), math.cos(j.position / 2))


def _is_joint(o: SceneObject) -> bool:
    return (o.kind == "joint" and o.joint is not None) or o.kind == "force_sensor"


class _Planner:
    """Walks the object tree once: world frames in the saved pose and which link carries what."""

    def __init__(self, scene: Scene):
        self.table = {o.handle: o for o in scene.objects}
        self.kids: dict[int | None, list[SceneObject]] = {}
        self.notes: list[str] = []
        for o in scene.objects:
            parent = o.parent if o.parent in self.table else None
            if o.parent is not None and parent is None:
                self.notes.append(f"{o.name}: its parent {o.parent} is missing: put at the top")
            self.kids.setdefault(parent, []).append(o)
        self.full: dict[int, Tf] = {}  # world frame (a joint's: after its saved motion)
        self.base: dict[int, Tf] = {}  # world frame before a joint's saved motion
        self.closing = loops.closing_joints(scene, self.kids)
        self.closing_parent: dict[int, tuple[int, int] | None] = {}  # closing joint -> link
        self.bodies: list[Body] = []
        self.where: dict[int, tuple[int, int]] = {}  # handle -> (body, planned link)
        self.model_of: dict[int, int | None] = {}  # handle -> its tree's top object
        seen: set[int] = set()
        for o in self.kids.get(None, []):
            self._visit(o, IDENTITY_TF, None, None, seen)
        for o in scene.objects:
            if o.handle not in seen:
                self.notes.append(f"{o.name}: in a parent loop: put at the top")
                self._visit(o, IDENTITY_TF, None, None, seen)
        for cj in self.closing.values():  # what hangs from a closing joint rides on body B
            at = self.where.get(cj.partner.handle)
            for h in cj.below:
                if at is not None:
                    self.where[h] = at
                else:
                    self.where.pop(h, None)

    def joined(self) -> set[frozenset[tuple[int, int]]]:
        """Pairs of planned links (body, link) that a closing joint joins."""
        out = set()
        for h, cj in self.closing.items():
            a, b = self.closing_parent.get(h), self.where.get(cj.partner.handle)
            if a is not None and b is not None:
                out.add(frozenset((a, b)))
        return out

    def _visit(self, top, parent_frame, at, model, seen) -> None:
        """``top`` and everything below it, depth first in file order, without recursion (a
        file may nest objects deep)."""
        stack = [(top, parent_frame, at, model)]
        while stack:
            o, frame, where, owner = stack.pop()
            if o.handle in seen:
                continue
            seen.add(o.handle)
            full, where, owner = self._place(o, frame, where, owner)
            stack.extend((c, full, where, owner) for c in reversed(self.kids.get(o.handle, [])))

    def _place(self, o, parent_frame, at, model):
        """Plan one object; returns its frame, link and model for its children."""
        base = mul(parent_frame, _tf(o.pose))
        full = mul(base, _displacement(o))
        self.full[o.handle] = full
        self.base[o.handle] = base
        model = o.handle if model is None else model  # the tree's root (see _filter_pairs)
        self.model_of[o.handle] = model
        shape = o.shape if o.kind == "shape" else None
        if shape is not None and not shape.dynamics.static:
            link = None if at is None else self.bodies[at[0]].links[at[1]]
            if link is not None and link.joint is not None and link.joint.handle == o.parent:
                if link.carrier is None:
                    link.carrier, link.carrier_frame = o, full
                else:
                    at = self._new_body(full, o, fixed=False)
            else:
                at = self._new_body(full, o, fixed=False)
        elif o.handle in self.closing:
            self.closing_parent[o.handle] = at
            at = None
        elif _is_joint(o):
            if o.kind == "joint" and o.joint is not None and o.joint.kind not in MOVING:
                self.notes.append(f"{o.name}: joint kind {o.joint.kind!r} held rigid")
            if at is None:
                at = self._new_body(base, None, fixed=True)
            body = self.bodies[at[0]]
            body.links.append(Link(full, parent=at[1], joint=o, joint_base=base))
            at = (at[0], len(body.links) - 1)
        elif shape is not None and at is None:
            at = self._new_body(full, None, fixed=True)
        if at is not None:
            self.where[o.handle] = at
            if shape is not None:
                link = self.bodies[at[0]].links[at[1]]
                rel = mul(inv(link.frame), full)
                for mesh in shape.meshes:
                    pose = mul(rel, _tf(mesh.local))
                    d = shape.dynamics
                    part = S.Part(mesh, Pose(*pose), d.respondable, d.static, o.visible, o.name)
                    link.parts.append((part, o))
        return full, at, model

    def _new_body(self, frame: Tf, carrier: SceneObject | None, fixed: bool) -> tuple[int, int]:
        link = Link(frame, carrier=carrier, carrier_frame=frame)
        self.bodies.append(Body([link], fixed=fixed))
        return len(self.bodies) - 1, 0


def build(scene: Scene, client: int, seed: int = 0, floor: bool | None = None) -> SceneModel:
    """Create the scene's bodies in ``client`` and return the World's name table.

    ``floor``: add sitegen's checker floor (default: only when the scene has no fixed
    respondable shape to stand on)."""
    del seed  # a scene file has no random parts
    scene = model_overrides(scene)
    plan = _Planner(scene)
    created = [create_body(client, body) for body in plan.bodies]
    _filter_pairs(client, plan, created)
    closing = loops.close(client, scene, plan, created, joint_ref)
    has_ground = any(
        body.fixed and any(part.respondable for part, _ in body.links[0].parts)
        for body in plan.bodies
    )
    if floor or (floor is None and not has_ground):
        ground = add_checker_floor(client, 5.0, 0.5)
        p.setCollisionFilterGroupMask(
            ground, -1, STATIC, S.RESPONDABLE | S.RAY, physicsClientId=client
        )
    return _model(scene, plan, created, closing)


def model_overrides(scene: Scene) -> Scene:
    """A model's "not dynamic" / "not respondable" override applies to every shape of its
    tree (CoppeliaSim's cumulative model property): such shapes are built static or not
    respondable. The Pioneer scene's walls are dynamic shapes in not-dynamic models."""
    table = scene.by_handle()
    if not any(o.not_dynamic or o.not_respondable for o in scene.objects):
        return scene
    objects = []
    for o in scene.objects:
        static = respondable_off = False
        cur, seen = o, 0
        while cur is not None and seen < len(table):
            static |= cur.not_dynamic
            respondable_off |= cur.not_respondable
            cur = table.get(cur.parent) if cur.parent is not None else None
            seen += 1
        if o.shape is not None and (static or respondable_off):
            d = o.shape.dynamics
            d = dataclasses.replace(
                d, static=d.static or static, respondable=d.respondable and not respondable_off
            )
            o = dataclasses.replace(o, shape=dataclasses.replace(o.shape, dynamics=d))
        objects.append(o)
    return dataclasses.replace(scene, objects=tuple(objects))


def _filter_pairs(client: int, plan: _Planner, created: list[Created]) -> None:
    """Switch off the link pairs that must not collide: respondable masks (the low byte
    between shapes of one tree, the high byte between trees: CoppeliaSim's Bullet plugin
    compares the shapes' topmost ancestors), parts of one link, links joined by a joint."""
    links: dict[tuple, list] = {}  # (body, uid, row, planned) -> [mask, model]
    for b, made in enumerate(created):
        for row, planned, part, owner in made.parts:
            if part.respondable and owner.shape is not None:
                entry = links.setdefault((b, made.uid, row, planned), [0, None])
                entry[0] |= owner.shape.dynamics.respondable_mask
                entry[1] = entry[1] if entry[1] is not None else plan.model_of[owner.handle]
    items = [(*key, mask, model) for key, (mask, model) in links.items()]
    joined = plan.joined()
    for i, a in enumerate(items):
        for bb in items[i + 1 :]:
            same_body = a[0] == bb[0]
            if not same_body and a[4] == 0xFFFF and bb[4] == 0xFFFF:
                continue
            same_model = a[5] is not None and a[5] == bb[5]
            if same_body and a[3] == 0 and bb[3] == 0 and plan.bodies[a[0]].fixed:
                continue  # fixed parts never touch each other anyway
            adjacent = same_body and (a[3] == bb[3] or _joined(plan.bodies[a[0]], a[3], bb[3]))
            adjacent = adjacent or frozenset(((a[0], a[3]), (bb[0], bb[3]))) in joined
            if adjacent or not S.mask_allows(a[4], bb[4], same_model):
                p.setCollisionFilterPair(a[1], bb[1], a[2], bb[2], 0, physicsClientId=client)


def _joined(body: Any, a: int, b: int) -> bool:
    """Links ``a`` and ``b`` are joined directly by a joint (one is the other's parent)."""
    return body.links[a].parent == b or body.links[b].parent == a


#: CoppeliaSim's joint mode codes (simxGetObjectGroupData type 16) by the model's mode.
MODE_CODES = {"passive": 0, "ik": 2, "dependent": 4}


def _mode_code(o: SceneObject, notes: tuple) -> int:
    if any(n.where == o.name and "'motion'" in n.message for n in notes):
        return 1  # V-REP 3.x's (deprecated) motion mode, read as passive
    return MODE_CODES.get(o.joint.mode if o.joint else "", 5)


def joint_ref(o: SceneObject, uid: int, row: int) -> JointRef:
    j = o.joint
    assert j is not None
    lower = upper = None
    if not (j.kind == "revolute" and j.cyclic) and j.range > 0:
        lower, upper = j.minimum, j.minimum + j.range
    modes = {"position": "position", "velocity": "velocity", "spring": "spring", "free": "free"}
    mode = modes.get(j.mode, "hold")
    if mode in ("velocity", "position") and not j.motor_enabled:
        mode = "free"  # torque/force mode with the motor off: turns freely
    return JointRef(
        o.name,
        uid,
        row,
        max_force=j.max_force,
        position_gain=j.p_gain if j.p_gain > 0 else 0.1,
        max_velocity=j.max_velocity if j.max_velocity and j.max_velocity > 0 else None,
        lower=lower,
        upper=upper,
        mode=mode,
        kind=j.kind if j.kind in MOVING else "revolute",
        own_frame=True,
        spring_k=j.spring_k,
        spring_c=j.spring_c,
        initial_velocity=j.target_velocity,
        initial_target=j.target if mode in ("position", "spring") else None,
    )


def _model(
    scene: Scene, plan: _Planner, created: list[Created], closing: dict[int, JointRef]
) -> SceneModel:
    objects: list[ObjectRef] = []
    joints: list[JointRef] = []
    prox: list[ProxSensor] = []
    data: dict[Any, Any] = {}
    for o in scene.objects:
        data[o.name] = o
        at = plan.where.get(o.handle)
        if at is None:
            uid, row, frame = -1, -1, IDENTITY_TF
        else:
            made, link = created[at[0]], plan.bodies[at[0]].links[at[1]]
            uid, row, frame = made.uid, made.rows[at[1]], link.frame
        if o.handle in closing or (
            o.kind == "joint" and o.joint is not None and at is not None and at[1] > 0
        ):
            ref = closing.get(o.handle) or joint_ref(o, uid, row)
            joints.append(dataclasses.replace(ref, coppelia_mode=_mode_code(o, scene.notes)))
            continue
        offset = mul(inv(frame), plan.full[o.handle])
        if o.kind == "proximity_sensor" and o.proximity_sensor is not None:
            ps = o.proximity_sensor
            prox.append(ProxSensor(o.name, uid, row, *offset, sensor_rays.rays(ps), ps.explicit))
            continue
        objects.append(ObjectRef(o.name, uid, row, *offset, *_via(plan, o)))
    rows: dict[str, list[tuple[int, int]]] = {}
    for made in created:
        for row, _planned, _part, owner in made.parts:
            data.setdefault(("link", made.uid, row), owner.name)
            if (made.uid, row) not in rows.setdefault(owner.name, []):
                rows[owner.name].append((made.uid, row))
    data["collision_rows"] = rows  # shape name -> the pybullet links its collision parts are on
    names = {o.handle: o.name for o in scene.objects}
    tree = [
        TreeNode(o.name, o.kind, names.get(o.parent) if o.parent is not None else None, o.alias)
        for o in scene.objects
    ]
    robot, extent = _main_object(scene, plan)
    data["looks"] = [look for made in created for look in made.looks]
    return SceneModel(
        robot=robot,
        forward_axis=(1.0, 0.0, 0.0),
        objects=objects,
        joints=joints,
        prox=prox,
        tree=tree,
        data=data,
        notes=plan.notes + [f"{n.where}: {n.message}" for n in scene.notes],
        camera=CameraSetup(max(0.5, 3.0 * extent), 35.0, -30.0, 0.05),
    )


def _via(plan: _Planner, o: SceneObject) -> tuple[str, Tf]:
    """An object under a closing joint hangs from that joint's moved frame (its pose shows
    how well the loop is closed); others: ("", identity)."""
    for h, cj in plan.closing.items():
        if o.handle in cj.below:
            return cj.joint.name, mul(inv(plan.full[h]), plan.full[o.handle])
    return "", IDENTITY_TF


def _main_object(scene: Scene, plan: _Planner) -> tuple[str, float]:
    """The object a camera follows, and the size of what hangs on it: the base of a body one
    can see (a body of invisible shapes only, such as a heavy counterweight, is never
    followed), a jointed one (a robot) before a single free part (a cup, a ball), then a free
    one before a fixed one, then the one with the most links."""
    if not scene.objects:
        raise ValueError(f"{scene.source or 'scene'}: the scene has no objects")
    shown = {
        at[0]
        for h, at in plan.where.items()
        if h in plan.table and plan.table[h].visible and plan.table[h].kind == "shape"
    }
    best, best_key = None, (-1, -1, -1)
    for b, body in enumerate(plan.bodies):
        if b not in shown or (len(body.links) < 2 and body.fixed):
            continue
        key = (1 if len(body.links) > 1 else 0, 0 if body.fixed else 1, len(body.links))
        if key > best_key:
            best, best_key = b, key
    if best is None:  # nothing moves under physics (a kinematic arm): the most jointed model
        return _most_jointed(scene), 0.5
    handles = [h for h, at in plan.where.items() if at[0] == best]
    top = min(handles, key=lambda h: _depth(plan, h))
    origin = plan.full[top][0]
    extent = max(math.dist(origin, plan.full[h][0]) for h in handles)
    return plan.table[top].name, max(extent, 0.05)


def _most_jointed(scene: Scene) -> str:
    """The top object with the most joints below it (ties: the first; no joints: the first
    visible top-level shape, then any visible shape, else the first object)."""
    parent = {o.handle: o.parent for o in scene.objects}
    count: dict[int, int] = {}
    for o in scene.objects:
        if o.kind == "joint":
            up = o.parent
            while up is not None and up in parent:
                count[up] = count.get(up, 0) + 1
                up = parent[up]
    tops = [o for o in scene.objects if o.parent is None and count.get(o.handle)]
    if tops:
        return max(tops, key=lambda o: count[o.handle]).name
    shapes = [o for o in scene.objects if o.kind == "shape" and o.visible]
    top_shapes = [o for o in shapes if o.parent is None]
    return (top_shapes or shapes or list(scene.objects))[0].name


def _depth(plan: _Planner, handle: int) -> int:
    d, cur = 0, plan.table.get(handle)
    while cur is not None and cur.parent in plan.table and d < 1000:
        d, cur = d + 1, plan.table[cur.parent]
    return d
