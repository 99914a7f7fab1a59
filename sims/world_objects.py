"""Objects that come and go and move between passes: the World's bookkeeping for them (a mixin).

Both script APIs change the scene: ``sim.createDummy`` / ``simxCreateDummy``,
``sim.createPrimitiveShape``, ``sim.removeObject``, ``sim.setObjectParent``, and moving an
object with ``sim.setObjectPosition``. This mixin gives ``World`` those operations, on the
same tables the scene builder fills, so every resolver and reader (``tree()``, ``find()``,
``object_pose()``) sees created objects like loaded ones:

- a created object gets the next handle; handles are never reused (CoppeliaSim's rule); a
  removed object leaves a hole (``None``) in the handle table;
- objects created while the simulation runs are removed at its end (``reset()``), those created
  while it is stopped stay (CoppeliaSim's default, ``removeNewObjectsAtSimulationEnd``);
- a dummy rides on the link that carries its parent (or is fixed in the world); a primitive
  shape is a pybullet body of its own (dynamic or static, respondable or not);
- moving an object (``set_object_pose``) moves what hangs on it and never what it hangs on: a
  non-dynamic object (dummy, sensor, static shape riding a link) gets a new offset on its link,
  with its non-dynamic descendants; a body whose root lies in the moved subtree is moved whole;
  the dynamic body an object rides on stays where it is. Only a body's root moves the body.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

from sims.models.common import ObjectRef, ProxSensor
from sims.quiet import pybullet as p
from sims.scene.bodies import collision_group, inv, mul
from sims.scene.paths import Entry, Tree
from sims.world_tree import TreeEntry

Tf = tuple[tuple[float, float, float], tuple[float, float, float, float]]
IDENTITY: Tf = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))
#: primitive kinds of sim.createPrimitiveShape / createPureShape
PRIMITIVES = ("cuboid", "sphere", "cylinder", "cone", "plane", "disc", "capsule")


@dataclass
class Created:
    """An object a script or client created: what rebuilding it needs."""

    handle: int
    name: str
    kind: str  # "dummy", "shape", "octree", "point_cloud", "drawing"...
    parent: int | None
    pose: Tf  # world pose when created or last moved
    persistent: bool  # created while the simulation was stopped: kept at its end
    size: tuple[float, ...] = (0.01,)
    primitive: str = ""  # a shape's primitive kind
    mass: float = 0.0  # 0: static
    respondable: bool = True
    color: tuple[float, float, float] = (0.8, 0.8, 0.8)
    body: int = -1
    extra: dict[str, Any] = field(default_factory=dict)


class WorldObjects:
    """Mixin of ``World``: created objects, removal, re-parenting and moving objects."""

    _tree: list[Any]
    _names: list[Any]
    _handles: dict[str, int]
    _objects: dict[str, ObjectRef]
    _joints: dict[str, Any]
    _sensors: dict[str, ProxSensor]

    # -- lifecycle (called by World._build) ------------------------------------------------------
    def _objects_rebuilt(self) -> None:
        """After the scene was (re)built: objects created while stopped come back with their
        handles; the others are gone (their handles stay unused)."""
        created: dict[int, Created] = getattr(self, "_created", {})
        self._created = {}
        self._roots: dict[int, int] | None = None
        self._tree_version = getattr(self, "_tree_version", 0) + 1
        top = max(created, default=0)
        for h in range(len(self._tree) + 1, top + 1):
            keep = created.get(h)
            if keep is not None and keep.persistent:
                self._place(keep)
            else:
                self._tree.append(None)
                self._names.append(None)

    @property
    def tree_version(self) -> int:
        """Changes whenever objects are created, removed or re-parented (cache keys)."""
        return self._tree_version

    # -- creating ------------------------------------------------------------------------------
    def _new_name(self, base: str) -> str:
        """CoppeliaSim's naming of new objects: ``Dummy``, then ``Dummy0``, ``Dummy1``..."""
        name, i = base, 0
        while name in self._handles:
            name, i = f"{base}{i}", i + 1
        return name

    def create_dummy(
        self, size: float = 0.01, *, name: str = "Dummy", persistent: bool = False
    ) -> int:
        """A dummy at the world origin (CoppeliaSim creates it there), fixed in the world."""
        h = len(self._tree) + 1
        obj = Created(h, self._new_name(name), "dummy", None, IDENTITY, persistent, (size,))
        self._place(obj)
        return h

    def create_primitive(
        self,
        primitive: str,
        size: tuple[float, float, float],
        *,
        mass: float = 1.0,
        static: bool = False,
        respondable: bool = True,
        color: tuple[float, float, float] = (0.8, 0.8, 0.8),
        persistent: bool = False,
    ) -> int:
        """A primitive shape at the origin: a pybullet body (``static``: fixed, mass 0)."""
        if primitive not in PRIMITIVES:
            raise ValueError(f"unknown primitive shape {primitive!r}")
        h = len(self._tree) + 1
        name = self._new_name(primitive.capitalize())
        obj = Created(h, name, "shape", None, IDENTITY, persistent, tuple(size), primitive,
                      0.0 if static else max(mass, 1e-6), respondable, color)  # fmt: skip
        self._place(obj)
        return h

    def _place(self, obj: Created) -> None:
        """Put ``obj`` into the tables at its handle (append, the handle being the next)."""
        assert obj.handle == len(self._tree) + 1
        self._tree.append(TreeEntry(obj.handle, obj.name, obj.name, obj.parent, obj.kind))
        self._names.append(obj.name)
        self._handles[obj.name] = obj.handle
        self._created[obj.handle] = obj
        if obj.kind == "shape" and obj.primitive:
            obj.body = _primitive_body(self.client_id, obj)  # type: ignore[attr-defined]
            self._objects[obj.name] = ObjectRef(obj.name, obj.body, -1)
        else:
            body, link, frame = self._carrier(obj.parent)
            self._objects[obj.name] = ObjectRef(obj.name, body, link, *mul(inv(frame), obj.pose))
        self._changed()

    def _changed(self) -> None:
        self._tree_version += 1
        self._roots = None
        self.moved()  # type: ignore[attr-defined]

    def is_created(self, handle: int) -> bool:
        return handle in self._created

    def created(self, handle: int) -> Created | None:
        return self._created.get(handle)

    # -- removing ------------------------------------------------------------------------------
    def remove_object(self, handle: int) -> None:
        """Remove an object and what hangs on it. Created objects go; of the scene's objects,
        non-dynamic ones riding a link and free bodies (with everything on them) can go; a link
        of a chain cannot (ValueError)."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        sub = [h] + [e.handle for e in self._subtree(h)]
        bodies = {self._roots_map().get(x) for x in sub} - {None}
        for x in sub:
            ref = self._carried(x)
            if ref is not None and ref.body >= 0 and ref.link >= 0:
                owner = self._roots_map()
                if not any(owner.get(y) == ref.body for y in sub):
                    raise ValueError(
                        f"object {self._names[x - 1]!r} is a link of a chain: it cannot be removed"
                    )
        for body in bodies:
            p.removeBody(body, physicsClientId=self.client_id)  # type: ignore[attr-defined]
        for x in reversed(sub):
            name = self._names[x - 1]
            self._objects.pop(name, None)
            self._joints.pop(name, None)
            self._sensors.pop(name, None)
            self._handles.pop(name, None)
            self._tree[x - 1] = None
            self._names[x - 1] = None
            self._created.pop(x, None)
        self._changed()

    # -- the tree ------------------------------------------------------------------------------
    def object_tree(self) -> Tree:
        """The object tree as the resolver (``sims.scene.paths``) reads it, with model bases
        marked (for ``:`` in paths); cached until the tree changes."""
        cached = getattr(self, "_tree_cache", None)
        if cached is not None and cached[0] == self._tree_version:
            return cached[1]
        models = {
            o.name
            for o in getattr(getattr(self, "source", None), "objects", ()) or ()
            if getattr(o, "model_base", False)
        }
        tree = Tree(
            Entry(e.handle, e.name, e.alias, e.parent, e.kind, e.name in models)
            for e in self._tree
            if e is not None
        )
        self._tree_cache = (self._tree_version, tree)
        return tree

    def _subtree(self, handle: int) -> list[Any]:
        return self.object_tree().descendants(handle)

    def set_parent(self, handle: int, parent: int | None, keep_in_place: bool = True) -> None:
        """Hang ``handle`` under ``parent`` (None: the world). A non-dynamic object rides its new
        parent's link; ``keep_in_place`` False keeps its pose relative to the parent instead of
        its world pose. A body's root keeps its physics (its place in the tree changes)."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        if parent is not None:
            self.handle_of(parent)  # type: ignore[attr-defined]
            if parent == h or any(e.handle == parent for e in self._subtree(h)):
                raise ValueError("an object cannot be its own ancestor")
        old_parent = self.parent_of_object(h)
        world_pose = self.object_pose(h)  # type: ignore[attr-defined]
        if not keep_in_place:
            old_ref = IDENTITY if old_parent is None else self.object_pose(old_parent)  # type: ignore[attr-defined]
            local = mul(inv(old_ref), world_pose)
            new_ref = IDENTITY if parent is None else self.object_pose(parent)  # type: ignore[attr-defined]
            world_pose = mul(new_ref, local)
        self._tree[h - 1] = dataclasses.replace(self._tree[h - 1], parent=parent)
        if h in self._created:
            self._created[h].parent = parent
        if self._roots_map().get(h) is None and not self._is_link(h):
            # riding: follows the new parent's carrier from now on
            name = self._names[h - 1]
            body, link, frame = self._carrier(parent)
            sub = [h] + [e.handle for e in self._subtree(h)]
            old = self._carried(h)
            for x in sub:
                ref = self._carried(x)
                if ref is None or (x != h and (ref.body, ref.link) != (old.body, old.link)):
                    continue
                pose = world_pose if x == h else self.object_pose(x)  # type: ignore[attr-defined]
                self._set_carried(x, body, link, mul(inv(frame), pose))
            del name
        self._changed()
        if not keep_in_place or self._roots_map().get(h) is not None:
            self.set_object_pose(h, world_pose)

    def parent_of_object(self, handle: int) -> int | None:
        e = self._tree[handle - 1]
        return None if e is None else e.parent

    # -- moving --------------------------------------------------------------------------------
    def set_object_pose(self, handle: int, pose: Tf) -> None:
        """Move an object so that its frame is ``pose`` (world), with what hangs on it: see the
        module docstring. ValueError for a joint or a link in the middle of a chain."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        old = self.object_pose(h)  # type: ignore[attr-defined]
        delta = mul(pose, inv(old))
        roots = self._roots_map()
        sub = [h] + [e.handle for e in self._subtree(h)]
        if roots.get(h) is None and (self._is_link(h) or self._names[h - 1] in self._joints):
            raise ValueError(
                f"object {self._names[h - 1]!r} is part of a dynamic chain: "
                "only a model's base (or what rides on a link) can be moved"
            )
        moved_bodies: set[int] = set()
        mine = self._carried(h)
        for x in sub:
            body = roots.get(x)
            if body is not None and body not in moved_bodies:
                moved_bodies.add(body)
                self._move_body(body, delta)
        for x in sub:
            ref = self._carried(x)
            if ref is None or ref.body in moved_bodies:
                continue
            if mine is not None and (ref.body, ref.link) != (mine.body, mine.link) and x != h:
                continue  # rides another link (of a chain below): that chain stays
            frame = self._link_pose(ref.body, ref.link)  # type: ignore[attr-defined]
            world = mul(frame, (ref.offset_pos, ref.offset_orn))
            self._set_carried(x, ref.body, ref.link, mul(inv(frame), mul(delta, world)))
        for x in sub:
            if x in self._created:
                self._created[x].pose = self.object_pose(x)  # type: ignore[attr-defined]
        self.moved()  # type: ignore[attr-defined]

    def _move_body(self, body: int, delta: Tf) -> None:
        cid = self.client_id  # type: ignore[attr-defined]
        com = p.getBasePositionAndOrientation(body, physicsClientId=cid)
        new = mul(delta, (tuple(com[0]), tuple(com[1])))
        p.resetBasePositionAndOrientation(body, new[0], new[1], physicsClientId=cid)

    # -- helpers -------------------------------------------------------------------------------
    def _link_pose(self, body: int, link: int) -> Tf:
        """World frame of a pybullet link (World.link_frame; _link_frame before issue 34)."""
        get = getattr(self, "link_frame", None) or self._link_frame  # type: ignore[attr-defined]
        return get(body, link)

    def _carried(self, handle: int) -> ObjectRef | None:
        """The (body, link, offset) an object rides on (None for joints)."""
        name = self._names[handle - 1]
        if name in self._objects:
            return self._objects[name]
        s = self._sensors.get(name)
        if s is not None:
            return ObjectRef(name, s.body, s.link, s.offset_pos, s.offset_orn)
        return None

    def _set_carried(self, handle: int, body: int, link: int, offset: Tf) -> None:
        name = self._names[handle - 1]
        if name in self._objects:
            self._objects[name] = ObjectRef(name, body, link, *offset)
        elif name in self._sensors:
            s = self._sensors[name]
            self._sensors[name] = dataclasses.replace(
                s, body=body, link=link, offset_pos=offset[0], offset_orn=offset[1]
            )

    def _carrier(self, parent: int | None) -> tuple[int, int, Tf]:
        """The link a child of ``parent`` rides on, and that link's world frame."""
        if parent is None:
            return -1, -1, IDENTITY
        name = self._names[parent - 1]
        if name in self._joints:
            j = self._joints[name]
            body, link = j.body, j.index
        else:
            ref = self._carried(parent)
            body, link = (ref.body, ref.link) if ref is not None else (-1, -1)
        return body, link, self._link_pose(body, link)  # type: ignore[attr-defined]

    def _is_link(self, handle: int) -> bool:
        """A dynamic link of a chain (carried by a joint's link, not a body's base)."""
        ref = self._carried(handle)
        return ref is not None and ref.body >= 0 and ref.link >= 0

    def _roots_map(self) -> dict[int, int]:
        """Object handle -> pybullet body, for each body's root object: the shallowest object on
        the body's base (or the parent of a joint that starts a fixed body)."""
        if self._roots is not None:
            return self._roots
        tree = self.object_tree()
        depth: dict[int, int] = {}

        def depth_of(h: int) -> int:
            if h not in depth:
                up = tree.parent_of(h)
                depth[h] = 0 if up is None else depth_of(up) + 1
            return depth[h]

        best: dict[int, tuple[int, int]] = {}
        cid = self.client_id  # type: ignore[attr-defined]
        for e in tree.entries:
            ref = self._carried(e.handle)
            body = None
            if ref is not None and ref.body >= 0 and ref.link == -1:
                body = ref.body
            elif e.name in self._joints:
                j = self._joints[e.name]
                if p.getJointInfo(j.body, j.index, physicsClientId=cid)[16] == -1:
                    body = j.body
            if body is None:
                continue
            key = (depth_of(e.handle), e.handle)
            if body not in best or key < best[body]:
                best[body] = key
        roots = {h: body for body, (_, h) in best.items()}
        # a joint starting a fixed body under a world-fixed object: that object is the root
        for h, body in list(roots.items()):
            if self._names[h - 1] in self._joints:
                up = tree.parent_of(h)
                ref = self._carried(up) if up is not None else None
                if ref is not None and ref.body < 0:
                    del roots[h]
                    roots[up] = body
        self._roots = roots
        return roots


def _primitive_body(client: int, obj: Created) -> int:
    """A pybullet body for a primitive shape, centred on its frame (CoppeliaSim's convention)."""
    sx, sy, sz = (tuple(obj.size) + (0.1, 0.1, 0.1))[:3]
    kind = obj.primitive
    if kind in ("cuboid", "plane"):
        half = [sx / 2, sy / 2, max(sz, 0.001) / 2]
        col = p.createCollisionShape(p.GEOM_BOX, halfExtents=half, physicsClientId=client)
        vis = p.createVisualShape(p.GEOM_BOX, halfExtents=half, rgbaColor=[*obj.color, 1],
                                  physicsClientId=client)  # fmt: skip
    elif kind == "sphere":
        r = sx / 2
        col = p.createCollisionShape(p.GEOM_SPHERE, radius=r, physicsClientId=client)
        vis = p.createVisualShape(p.GEOM_SPHERE, radius=r, rgbaColor=[*obj.color, 1],
                                  physicsClientId=client)  # fmt: skip
    elif kind == "capsule":
        r, h = sx / 2, max(sz - sx, 0.001)
        col = p.createCollisionShape(p.GEOM_CAPSULE, radius=r, height=h, physicsClientId=client)
        vis = p.createVisualShape(p.GEOM_CAPSULE, radius=r, length=h, rgbaColor=[*obj.color, 1],
                                  physicsClientId=client)  # fmt: skip
    else:  # cylinder, disc, cone (a cone's hull is taken as its cylinder's)
        r, h = sx / 2, max(sz, 0.001)
        col = p.createCollisionShape(p.GEOM_CYLINDER, radius=r, height=h, physicsClientId=client)
        vis = p.createVisualShape(p.GEOM_CYLINDER, radius=r, length=h, rgbaColor=[*obj.color, 1],
                                  physicsClientId=client)  # fmt: skip
    fixed = obj.mass <= 0
    uid = p.createMultiBody(
        baseMass=0.0 if fixed else obj.mass,
        baseCollisionShapeIndex=col,
        baseVisualShapeIndex=vis,
        basePosition=obj.pose[0],
        baseOrientation=obj.pose[1],
        physicsClientId=client,
    )
    group, mask = collision_group(obj.respondable, fixed)
    p.setCollisionFilterGroupMask(uid, -1, group, mask, physicsClientId=client)
    return uid


def rotation_angle(q: tuple[float, float, float, float]) -> float:
    return 2.0 * math.acos(max(-1.0, min(1.0, abs(q[3]))))
