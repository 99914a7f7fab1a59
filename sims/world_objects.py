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
        obj = Created(
            h,
            name,
            "shape",
            None,
            IDENTITY,
            persistent,
            tuple(size),
            primitive,
            0.0 if static else max(mass, 1e-6),
            respondable,
            color,
        )
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
            body, link, frame = self._carrier_frame(obj.parent)
            self._objects[obj.name] = ObjectRef(obj.name, body, link, *mul(inv(frame), obj.pose))
        self._changed()

    def _changed(self) -> None:
        self._tree_version += 1
        self._roots = None
        self.moved()  # type: ignore[attr-defined]

    def created(self, handle: int) -> Created | None:
        return self._created.get(handle)

    # -- names ---------------------------------------------------------------------------------
    def rename_object(self, handle: int, name: str) -> None:
        """A new old-style name (sim.setObjectName); ValueError when taken or for a joint."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        old = self._names[h - 1]
        if name == old:
            return
        if not name or name in self._handles:
            raise ValueError(f"an object named {name!r} exists already")
        if old in self._joints:
            raise ValueError(f"joint {old!r} keeps its name in this emulation")
        for table in (self._objects, self._sensors):
            if old in table:
                table[name] = dataclasses.replace(table.pop(old), name=name)
        self._tree[h - 1] = dataclasses.replace(self._tree[h - 1], name=name)
        self._names[h - 1] = name
        del self._handles[old]
        self._handles[name] = h
        if h in self._created:
            self._created[h].name = name
        self._changed()

    def set_alias(self, handle: int, alias: str) -> None:
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        self._tree[h - 1] = dataclasses.replace(self._tree[h - 1], alias=alias)
        self._changed()

    # -- copying and scaling ---------------------------------------------------------------------
    def copy_objects(self, handles: list[int], *, persistent: bool = False) -> list[int]:
        """Copies of objects with what hangs on them (CoppeliaSim's copy-paste): a scene
        object's subtree is built again by the scene builder, so a copy has the original's
        bodies, masses, joints and motors; names get CoppeliaSim's ``#n`` suffixes."""
        out = []
        for h in handles:
            h = self.handle_of(h)  # type: ignore[attr-defined]
            if h in self._created:
                out.append(self._copy_created(self._created[h], persistent))
            else:
                out.append(self._copy_scene(h, persistent))
        return out

    def _copy_name(self, name: str) -> str:
        base = name.rpartition("#")[0] if name_has_suffix(name) else name
        i = 0
        while f"{base}#{i}" in self._handles:
            i += 1
        return f"{base}#{i}"

    def _copy_created(self, obj: Created, persistent: bool) -> int:
        h = len(self._tree) + 1
        twin = dataclasses.replace(
            obj,
            handle=h,
            name=self._copy_name(obj.name),
            persistent=persistent,
            body=-1,
            pose=self.object_pose(obj.handle),  # type: ignore[attr-defined]
            extra=dict(obj.extra),
        )
        self._place(twin)
        return h

    def _copy_scene(self, handle: int, persistent: bool) -> int:
        from sims.scene.model import Pose, Scene

        source = getattr(self, "source", None)
        if not isinstance(source, Scene):
            raise ValueError("objects of a bundled scene cannot be copied")
        by_name = {o.name: o for o in source.objects}
        sub = [handle] + [e.handle for e in self._subtree(handle)]
        top = self._names[handle - 1]
        if top not in by_name:
            raise ValueError(f"object {top!r} cannot be copied")
        renamed: dict[str, str] = {}
        objs = []
        for x in sub:
            name = self._names[x - 1]
            o = by_name.get(name)
            if o is None:
                continue
            renamed[name] = self._copy_name(name) if name not in renamed else renamed[name]
            while (
                renamed[name] in renamed.values()
                and list(renamed.values()).count(renamed[name]) > 1
            ):
                renamed[name] += "0"
            if x == handle:
                pos, quat = self.object_pose(x)  # type: ignore[attr-defined]
                o = dataclasses.replace(o, parent=None, pose=Pose(tuple(pos), tuple(quat)))
            objs.append(dataclasses.replace(o, name=renamed[name]))
        return self._merge_scene(objs, source, persistent)

    def load_model(self, path: str, *, persistent: bool = False) -> int:
        """A model file (``.ttm``, or a scene file) added to the scene, its objects renamed
        where their names are taken; the handle of its base (the first top object)."""
        from sims.scene.load import load_scene

        model = load_scene(path)
        objs = []
        for o in model.objects:
            name = o.name if o.name not in self._handles else self._copy_name(o.name)
            objs.append(dataclasses.replace(o, name=name))
        if not objs:
            raise ValueError(f"{path}: the model has no objects")
        return self._merge_scene(objs, model, persistent)

    def _merge_scene(self, objs: list[Any], source: Any, persistent: bool) -> int:
        """Build ``objs`` (scene objects with unique names) into this World's client with the
        scene builder and add them to the tables; the first new handle."""
        from sims.scene.bodies import create_visuals
        from sims.scene.build import build
        from sims.scene.model import Scene

        more = getattr(self, "_dynamic_more", set())
        more |= {o.name for o in objs if o.shape is not None and not o.shape.dynamics.static}
        self._dynamic_more = more
        cid = self.client_id  # type: ignore[attr-defined]
        model = build(
            Scene(tuple(objs), source=source.source, time_step=source.time_step), cid, floor=False
        )
        first = len(self._tree) + 1
        index = {n.name: first + i for i, n in enumerate(model.tree)}
        for i, node in enumerate(model.tree):
            h = first + i
            parent = index.get(node.parent or "")
            entry = TreeEntry(h, node.name, node.alias, parent, node.kind)
            self._tree.append(entry)
            self._names.append(node.name)
            self._handles[node.name] = h
            self._created[h] = Created(
                h, node.name, node.kind, parent, IDENTITY, persistent, extra={"copy": True}
            )
        for ref in model.objects:
            self._objects[ref.name] = ref
        for sensor in model.prox:
            self._sensors[sensor.name] = sensor
        for j in model.joints:
            self._joints[j.name] = j
            self.model.joints.append(j)  # type: ignore[attr-defined]
            self._init_motor(j)  # type: ignore[attr-defined]
        data = self.model.data  # type: ignore[attr-defined]
        for key, value in model.data.items():
            if key != "looks":
                data.setdefault(key, value)
        if "visuals" in data:
            data["visuals"].extend(create_visuals(cid, model.data.get("looks", [])))
        else:
            data.setdefault("looks", []).extend(model.data.get("looks", []))
        self._changed()
        return first

    def scale_object(self, handle: int, factors: tuple[float, float, float]) -> None:
        """sim.scaleObject: a created primitive shape gets its new size (its body is made
        again at its pose); a dummy its size. ValueError for objects loaded with the scene."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        obj = self._created.get(h)
        if obj is None or obj.extra.get("copy"):
            raise ValueError("only objects a script created can be scaled in this emulation")
        obj.size = tuple(v * f for v, f in zip(obj.size, factors + (1.0,) * 3, strict=False))
        if obj.kind == "shape" and obj.body >= 0:
            obj.pose = self.object_pose(h)  # type: ignore[attr-defined]
            p.removeBody(obj.body, physicsClientId=self.client_id)  # type: ignore[attr-defined]
            obj.body = _primitive_body(self.client_id, obj)  # type: ignore[attr-defined]
            self._objects[obj.name] = ObjectRef(obj.name, obj.body, -1)
        self._changed()

    # -- removing ------------------------------------------------------------------------------
    def remove_object(self, handle: int, *, model: bool = False) -> None:
        """Remove an object (``model``: with everything below it, sim.removeModel). Without
        ``model`` its children move up to its parent, keeping their pose (CoppeliaSim's
        sim.removeObject). A body's root takes its body along; what rode on that body stays
        where it is, fixed in the world. ValueError for a link or joint of a chain, or a root
        that carries one."""
        h = self.handle_of(handle)  # type: ignore[attr-defined]
        sub = [h] + [e.handle for e in self._subtree(h)] if model else [h]
        roots = self._roots_map()
        bodies = {roots[x] for x in sub if x in roots}
        for x in sub:
            name = self._names[x - 1]
            ref = self._carried(x)
            in_chain = name in self._joints or self._is_link(x)
            body = self._joints[name].body if name in self._joints else (ref.body if ref else -1)
            if in_chain and not (body in bodies and model):
                raise ValueError(f"object {name!r} is part of a chain: it cannot be removed")
        up = self.parent_of_object(h)
        for e in self.object_tree().entries:
            if e.handle in sub:
                continue
            ref = self._carried(e.handle)
            on_removed = (ref is not None and ref.body in bodies) or (
                e.name in self._joints and self._joints[e.name].body in bodies
            )
            if on_removed:
                if e.name in self._joints or self._is_link(e.handle):
                    raise ValueError(
                        f"object {self._names[h - 1]!r} carries the chain of {e.name!r}: "
                        "it cannot be removed"
                    )
                pose = self.object_pose(e.handle)  # type: ignore[attr-defined]
                self._set_carried(e.handle, -1, -1, pose)
            if e.parent in sub:
                self._tree[e.handle - 1] = dataclasses.replace(self._tree[e.handle - 1], parent=up)
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
            body, link, frame = self._carrier_frame(parent)
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

    def _carrier_frame(self, parent: int | None) -> tuple[int, int, Tf]:
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
        """A dynamic shape that is a link of a chain (what rides on a link is not)."""
        ref = self._carried(handle)
        if ref is None or ref.body < 0 or ref.link < 0:
            return False
        name = self._names[handle - 1]
        from sims.scene.model import Scene

        if not isinstance(getattr(self, "source", None), Scene):  # a bundled scene's links
            return self._tree[handle - 1].kind == "shape"
        return name in self._dynamic_shapes() or name in getattr(self, "_dynamic_more", ())

    def _dynamic_shapes(self) -> frozenset[str]:
        cached = getattr(self, "_dynamic_cache", None)
        if cached is None:
            cached = frozenset(
                o.name
                for o in getattr(getattr(self, "source", None), "objects", ()) or ()
                if getattr(o, "shape", None) is not None and not o.shape.dynamics.static
            )
            self._dynamic_cache = cached
        return cached

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
        vis = p.createVisualShape(
            p.GEOM_BOX, halfExtents=half, rgbaColor=[*obj.color, 1], physicsClientId=client
        )
    elif kind == "sphere":
        r = sx / 2
        col = p.createCollisionShape(p.GEOM_SPHERE, radius=r, physicsClientId=client)
        vis = p.createVisualShape(
            p.GEOM_SPHERE, radius=r, rgbaColor=[*obj.color, 1], physicsClientId=client
        )
    elif kind == "capsule":
        r, h = sx / 2, max(sz - sx, 0.001)
        col = p.createCollisionShape(p.GEOM_CAPSULE, radius=r, height=h, physicsClientId=client)
        vis = p.createVisualShape(
            p.GEOM_CAPSULE, radius=r, length=h, rgbaColor=[*obj.color, 1], physicsClientId=client
        )
    else:  # cylinder, disc, cone (a cone's hull is taken as its cylinder's)
        r, h = sx / 2, max(sz, 0.001)
        col = p.createCollisionShape(p.GEOM_CYLINDER, radius=r, height=h, physicsClientId=client)
        vis = p.createVisualShape(
            p.GEOM_CYLINDER, radius=r, length=h, rgbaColor=[*obj.color, 1], physicsClientId=client
        )
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


def name_has_suffix(name: str) -> bool:
    base, sep, num = name.rpartition("#")
    return bool(sep) and num.isdigit()
