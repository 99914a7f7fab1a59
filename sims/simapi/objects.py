"""``sim.*`` functions on scene objects: handles, names and paths, the tree, creating, removing,
re-parenting and copying objects, their properties. Paths go through the one resolver
(``sims.scene.paths``); the scene's changes through ``World`` (``sims/world_objects.py``)."""

from __future__ import annotations

from typing import Any

from sims.remote_api import commands as cmd
from sims.remote_api.object_commands import OBJECT_TYPES
from sims.scene import paths

from .context import Caller, SimError
from .values import flag, integer, numbers, options, table, text

HANDLE_ALL, HANDLE_SCENE = -2, -12
#: sim.getObjectType numbers by the tree entries' kind (the legacy API's table)
KIND_TYPES = OBJECT_TYPES
#: sim.primitiveshape_* (4.x) / sim.pure_primitive_* (3.x) numbers
PRIMITIVES = {
    1: "plane",
    2: "disc",
    3: "cuboid",
    4: "sphere",
    5: "cylinder",
    6: "cone",
    7: "capsule",
}


def object_type(c: Caller, h: int) -> int:
    return KIND_TYPES.get(c.entry(h).kind, 0)


# -- handles, names, paths -----------------------------------------------------------------------
def get_object(c: Caller, path: Any, opts: Any = None, proxy: Any = None, flags: Any = None) -> int:
    """sim.getObject(path, {index=, proxy=, noError=}) (4.3+), or (path, index, proxy, options)
    as the C API takes them."""
    query = text(path)
    o = options(opts)
    index = integer(o.get("index", opts if isinstance(opts, int) else -1), 2)
    base = o.get("proxy", proxy if isinstance(proxy, int) else -1)
    silent = bool(o.get("noError", False)) or (isinstance(flags, int) and flags & 1)
    tree = c.world.object_tree()
    at = c.handle(base) if isinstance(base, int) and base != -1 else c.object
    try:
        found = paths.resolve(tree, query, index=index, base=at)
    except paths.PathError as exc:
        if silent:
            return -1
        raise SimError(str(exc), "path", query) from None
    if found is None:
        if silent:
            return -1
        return c.not_found(f"object does not exist: {query!r}", query)
    return int(found)


def get_object_handle(c: Caller, name: Any, *rest: Any) -> int:
    """The 3.x/4.1 lookup: an old-style name with the calling script's suffix rule, or a path
    (4.2+); ``sim.handle_self`` gives the script's object (the 4.2 rewrite of
    getObjectAssociatedWithScript)."""
    if isinstance(name, (int, float)) and not isinstance(name, bool):
        return c.handle(name)
    query = text(name)
    silent = query.endswith("@silentError")
    query = query.removesuffix("@silentError")
    if paths.is_path(query):
        return get_object(c, query, {"noError": silent})
    found = paths.resolve_name(c.world.object_tree(), query, getattr(c, "suffix", None))
    if found is None:
        if silent:
            return -1
        return c.not_found(f"object {query!r} does not exist", query)
    return int(found)


def is_handle(c: Caller, h: Any) -> bool:
    return isinstance(h, int) and h in c.world.object_tree().by_handle


def get_object_alias(c: Caller, h: Any, opts: Any = -1) -> str:
    """Options -1/0: the alias; 1 and up: the full path ``/a/b/c``."""
    e = c.entry(c.handle(h))
    if isinstance(opts, int) and opts >= 1:
        return paths.full_path(c.world.object_tree(), e.handle)
    return paths.alias_of(e)


def get_object_name(c: Caller, h: Any) -> str:
    return c.entry(c.handle(h)).name


def set_object_name(c: Caller, h: Any, name: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    try:
        c.world.rename_object(h, text(name, 2))
    except ValueError as exc:
        raise SimError(str(exc)) from None
    return c.done


def set_object_alias(c: Caller, h: Any, alias: Any, opts: Any = 0) -> None:
    h = c.handle(h)
    c.entry(h)
    c.world.set_alias(h, text(alias, 2))


def get_object_type(c: Caller, h: Any) -> int:
    return object_type(c, c.handle(h))


def get_object_parent(c: Caller, h: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    up = c.world.parent_of_object(h)
    return -1 if up is None else int(up)


def get_object_child(c: Caller, h: Any, index: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    kids = c.world.object_tree().children.get(h, [])
    i = integer(index, 2)
    return int(kids[i].handle) if 0 <= i < len(kids) else -1


def _walk(tree: paths.Tree, root: int | None) -> list[Any]:
    return tree.descendants(root)


def get_objects_in_tree(c: Caller, base: Any, kind: Any = HANDLE_ALL, opts: Any = 0) -> list[int]:
    """Bit 0 of ``opts``: leave the base out; bit 1: only its direct children."""
    kind, opts = integer(kind, 2, HANDLE_ALL), integer(opts, 3, 0)
    tree = c.world.object_tree()
    b = integer(base, 1)
    if b in (HANDLE_SCENE, -1):
        found = _walk(tree, None)
    else:
        root = c.entry(c.handle(b))
        below = tree.children.get(root.handle, []) if opts & 2 else _walk(tree, root.handle)
        found = ([] if opts & 1 else [root]) + list(below)
    return [int(e.handle) for e in found if kind == HANDLE_ALL or KIND_TYPES.get(e.kind, 0) == kind]


def get_objects(c: Caller, index: Any, kind: Any = HANDLE_ALL) -> int:
    """The ``index``-th object of a type, or -1 past the last."""
    found = get_objects_in_tree(c, HANDLE_SCENE, kind)
    i = integer(index, 1)
    return found[i] if 0 <= i < len(found) else -1


def get_object_associated_with_script(c: Caller, h: Any = -4) -> int:
    if integer(h, 1) == -4:
        return -1 if c.object is None else c.object
    run = c.lua.script_by_handle(int(h)) if c.lua is not None else None
    return -1 if run is None else run.object


def get_object_selection(c: Caller) -> Any:
    sel = list(c.store.selection)
    return sel or None  # headless: nothing is selected unless a script selected it


def set_object_selection(c: Caller, handles: Any) -> None:
    c.store.selection = [c.handle(h) for h in table(handles)]


def add_object_to_selection(c: Caller, what: Any, h: Any = None) -> None:
    if h is not None:
        c.store.selection.append(c.handle(h))


def remove_object_from_selection(c: Caller, what: Any, h: Any = None) -> None:
    if integer(what, 1) == HANDLE_ALL or h is None:
        c.store.selection.clear()
    else:
        c.store.selection = [x for x in c.store.selection if x != c.handle(h)]


def get_object_size_factor(c: Caller, h: Any) -> float:
    h = c.handle(h)
    c.entry(h)
    return float(c.store.object_params.get((h, 17), 1.0))  # objfloatparam_size_factor


def get_special(c: Caller, h: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    return c.store.special.get(h, 0x01F0 | 0x0001 | 0x0002 | 0x0200)


def set_special(c: Caller, h: Any, value: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    c.store.special[h] = integer(value, 2)
    return c.done


def get_model_property(c: Caller, h: Any) -> int:
    h = c.handle(h)
    e = c.entry(h)
    tree = c.world.object_tree()
    default = 0 if getattr(tree.by_handle[e.handle], "model", False) else 0xF000  # not_model
    return int(c.store.object_params.get((h, "model"), default))


def set_model_property(c: Caller, h: Any, value: Any) -> int:
    h = c.handle(h)
    c.entry(h)
    c.store.object_params[(h, "model")] = integer(value, 2)
    return c.done


# -- creating, removing, parenting ---------------------------------------------------------------
def create_dummy(c: Caller, size: Any = 0.01, colors: Any = None) -> int:
    return c.world.create_dummy(float(size or 0.01), persistent=c.persistent)


def create_primitive_shape(c: Caller, kind: Any, sizes: Any, opts: Any = 0) -> int:
    """sim.createPrimitiveShape(type, sizes, options): options bit 0 backface culling, bit 1
    visible edges, bit 2 smooth, bit 3 respondable, bit 4 static, bit 5 open (4.x)."""
    o = integer(opts, 3, 0)
    return _primitive(c, integer(kind, 1), numbers(sizes), 1.0, bool(o & 16), bool(o & 8))


def create_pure_shape(
    c: Caller, kind: Any, opts: Any, sizes: Any, mass: Any = 1.0, precision: Any = None
) -> int:
    """sim.createPureShape (3.x): options bit 3 respondable, bit 4 static."""
    o = integer(opts, 2, 0)
    return _primitive(c, integer(kind, 1), numbers(sizes), float(mass), bool(o & 16), bool(o & 8))


def _primitive(
    c: Caller, kind: int, sizes: list[float], mass: float, static: bool, respondable: bool
) -> int:
    name = PRIMITIVES.get(kind)
    if name is None:
        raise SimError(f"unknown primitive shape type {kind}")
    size = (sizes + [0.1, 0.1, 0.1])[:3]
    return c.world.create_primitive(
        name,
        tuple(size),
        mass=mass,
        static=static,
        respondable=respondable,
        persistent=c.persistent,
    )


def remove_object(c: Caller, h: Any, model: bool = False) -> int:
    h = c.handle(h)
    c.entry(h)
    try:
        c.world.remove_object(h, model=model)
    except ValueError as exc:
        raise SimError(str(exc)) from None
    for key in [k for k in c.store.custom if k[0] == h]:
        del c.store.custom[key]
    return 1


def remove_objects(c: Caller, handles: Any, *rest: Any) -> None:
    for h in table(handles):
        if is_handle(c, c.handle(h)):
            remove_object(c, h)


def _remove_object(c: Caller, h: Any) -> int:
    return remove_object(c, h)


def remove_model(c: Caller, h: Any, *rest: Any) -> int:
    return remove_object(c, h, model=True)


def set_object_parent(c: Caller, h: Any, parent: Any, keep_in_place: Any = True) -> int:
    h = c.handle(h)
    c.entry(h)
    up = integer(parent, 2)
    if up != -1:
        up = c.handle(up)
        c.entry(up)
    try:
        c.world.set_parent(h, None if up == -1 else up, flag(keep_in_place, True))
    except ValueError as exc:
        raise SimError(str(exc)) from None
    attach_dynamic(c, h, up)
    return c.done


def attach_dynamic(c: Caller, h: int, up: int) -> None:
    """CoppeliaSim links two dynamic bodies only through a joint or a force sensor: a free
    dynamic shape hung on an unbroken force sensor (a gripper's attach point) is held there
    rigidly (``World.hold``) and comes loose when re-parented elsewhere or when the sensor
    breaks; hung on anything else it stays a free body, as it does in CoppeliaSim. A shape a
    script made static (``sim.shapeintparam_static``) rides its parent (the world: stays put),
    the other fake-grasp pattern."""
    world = c.world
    if not world.can_hold(h):
        return
    world.release(h)
    parent = None if up == -1 else up
    try:
        if c.store.object_params.get((h, 3003)) == 1:
            world.hold(h, parent)
        elif parent is not None and world.kind(parent) == "force_sensor":
            if not world.force_sensor_broken(parent):
                world.hold(h, parent)
    except ValueError as exc:
        raise SimError(str(exc)) from None


#: sim.dummy_linktype_* (CoppeliaSim's numbers) -> the scene model's names
LINK_TYPES = {
    0: "dynamics_loop_closure",
    1: "dynamics_force_constraint",
    2: "gcs_loop_closure",
    3: "gcs_tip",
    4: "gcs_target",
    5: "ik_tip_target",
}
LINK_TYPE_NUMBERS = {v: k for k, v in LINK_TYPES.items()}


def dummy_link_type(c: Caller, h: int) -> int:
    """A dummy's sim.dummyintparam_link_type: what a script set, else the scene's, else
    CoppeliaSim's default for a new dummy (IK tip-target)."""
    got = c.store.object_params.get((h, 10000))
    if got is not None:
        return int(got)
    data = getattr(c.world.model.data.get(c.world.name_of(h) or ""), "dummy", None)
    return LINK_TYPE_NUMBERS.get(getattr(data, "link_type", ""), 5)


def _dummy(c: Caller, h: Any, position: int) -> int:
    hh = c.handle(h, position)
    e = c.entry(hh)
    if e.kind != "dummy":
        raise SimError(f"argument {position}: object {e.name!r} is not a dummy")
    return hh


def set_link_dummy(c: Caller, h: Any, other: Any) -> int | None:
    """Link two dummies (-1: undo the link); a dynamics link type (of either dummy) holds
    them together through their bodies (``World.link_dummies``)."""
    a = _dummy(c, h, 1)
    o = integer(other, 2)
    b = None if o == -1 else _dummy(c, o, 2)
    dynamic = any(dummy_link_type(c, x) in (0, 1) for x in (a, b) if x is not None)
    try:
        c.world.link_dummies(a, b, dynamic)
    except ValueError as exc:
        raise SimError(str(exc)) from None
    return c.done


def get_link_dummy(c: Caller, h: Any) -> int:
    found = c.world.linked_dummy(_dummy(c, h, 1))
    return -1 if found is None else int(found)


def copy_paste_objects(c: Caller, handles: Any, opts: Any = 0) -> list[int]:
    """Copies of the objects (with what hangs on them); dynamics kept (World.copy_objects)."""
    hs = [c.handle(h) for h in table(handles)]
    for h in hs:
        c.entry(h)
    try:
        return [int(h) for h in c.world.copy_objects(hs, persistent=c.persistent)]
    except ValueError as exc:
        raise SimError(str(exc)) from None


def scale_object(c: Caller, h: Any, x: Any, y: Any, z: Any, opts: Any = 0) -> None:
    h = c.handle(h)
    c.entry(h)
    try:
        c.world.scale_object(h, (float(x), float(y), float(z)))
    except ValueError as exc:
        raise SimError(str(exc)) from None


def scale_objects(c: Caller, handles: Any, factor: Any, positions_too: Any = True) -> None:
    for h in table(handles):
        scale_object(c, h, factor, factor, factor)


def reset_dynamic_object(c: Caller, h: Any) -> int:
    """The dynamic body restarts from its current pose (and, for the 3.x conveyor trick, with
    the initial velocity its shape float parameters give; ``World.reset_dynamic_object``)."""
    h = c.handle(h)
    c.entry(h)
    reset = getattr(c.world, "reset_dynamic_object", None)
    keys = [(h, k) for k in (3000, 3001, 3002, 3020, 3021, 3022)]
    lin = [c.store.object_params.get(k, 0.0) for k in keys[:3]]
    ang = [c.store.object_params.get(k, 0.0) for k in keys[3:]]
    if reset is not None:
        reset(h)
    setter = getattr(c.world, "set_initial_velocity", None)
    if setter is not None and any(k in c.store.object_params for k in keys):
        setter(h, tuple(lin), tuple(ang))  # zero too: a stopped belt stops
    return c.done


def get_name_suffix(c: Caller, name: Any = None) -> Any:
    if name is None:
        s = getattr(c, "suffix", None)
        return -1 if s is None else s
    n = text(name)
    base, sep, num = n.rpartition("#")
    if sep and num.isdigit():
        return (int(num), base)
    return (-1, n)


def set_name_suffix(c: Caller, suffix: Any) -> int:
    c.suffix = None if integer(suffix, 1) < 0 else integer(suffix, 1)  # type: ignore[attr-defined]
    return c.done


# -- collections (4.x) ---------------------------------------------------------------------------
def create_collection(c: Caller, opts: Any = 0) -> int:
    h = c.store.new_handle("collection", 2_000_000)
    c.store.collections[h] = []
    return h


def add_item_to_collection(c: Caller, coll: Any, what: Any, h: Any, opts: Any = 0) -> None:
    items = c.store.collections.get(integer(coll, 1))
    if items is None:
        raise SimError(f"collection {coll} does not exist")
    obj = -1 if integer(what, 2) == HANDLE_ALL else c.handle(h, 3)
    items.append((integer(what, 2), obj, integer(opts, 4, 0)))


def get_collection_objects(c: Caller, coll: Any) -> list[int]:
    items = c.store.collections.get(integer(coll, 1))
    if items is None:
        raise SimError(f"collection {coll} does not exist")
    return collection_objects(c, items)


def collection_objects(c: Caller, items: list[tuple[int, int, int]]) -> list[int]:
    """The objects of a collection's items: all, one object (sim.handle_single), a tree (base
    included or not), a chain up from a tip; bit 0 of an item's options removes."""
    tree = c.world.object_tree()
    out: list[int] = []
    for what, h, o in items:
        if what == HANDLE_ALL:
            got = [e.handle for e in tree.entries]
        elif what in (-6, -7):  # sim.handle_tree, sim.handle_chain
            got = [h] + [e.handle for e in tree.descendants(h)]
            if what == -7:
                got, up = [], h
                while up is not None:
                    got.append(up)
                    up = tree.parent_of(up)
            if o & 2:
                got = got[1:]
        else:
            got = [h]
        if o & 1:
            out = [x for x in out if x not in got]
        else:
            out += [x for x in got if x not in out]
    return out


def get_collection_handle(c: Caller, name: Any) -> int:
    """Collections of a scene file are not read (the readers skip them): a named collection
    stands for the whole scene, so that collision and distance checks still see every object."""
    key = text(name)
    for h in c.store.collections:
        if c.store.object_params.get((h, "name")) == key:
            return h
    h = create_collection(c)
    c.store.object_params[(h, "name")] = key
    c.store.collections[h] = [(HANDLE_ALL, -1, 0)]
    return h


def get_configuration_tree(c: Caller, h: Any) -> bytes:
    import struct

    from .poses import object_frame

    h = c.handle(h)
    out: list[float] = []
    for o in get_objects_in_tree(c, h if h != -12 else HANDLE_SCENE):
        pos, q = object_frame(c, o)
        jp = c.world.joint_position(o) if c.world.is_joint(o) else 0.0
        out += [o, *pos, *q, jp]
    return struct.pack(f"<{len(out)}d", *out)


def set_configuration_tree(c: Caller, data: Any) -> int:
    import struct

    raw = bytes(data) if not isinstance(data, str) else data.encode("latin-1")
    vals = struct.unpack(f"<{len(raw) // 8}d", raw[: len(raw) // 8 * 8])
    for i in range(0, len(vals) - 8, 9):
        h = int(vals[i])
        if c.world.is_joint(h):
            c.world.set_joint_position(h, vals[i + 8])
    for i in range(0, len(vals) - 8, 9):  # the base last: its children follow it
        h = int(vals[i])
        if c.world.parent_of_object(h) is None and not c.world.is_joint(h):
            try:
                cmd.set_frame(c.world, h, -1, vals[i + 1 : i + 4], vals[i + 4 : i + 8])
            except cmd.CommandError:
                pass
    return c.done


def _scene_file(c: Caller, name: str, kinds: tuple[str, ...]) -> str:
    """A model or scene file a script names: relative to the scene's folder, and only inside
    it or inside CoppeliaSim's scenes folder (``sim.stringparam_scenedefaultdir``: the package's
    bundled scenes); scripts never reach other files (the same rule as ``require``). A missing
    ``X.ttt`` with ``X.simscene.xml`` beside it loads that (the XML form of the same scene)."""
    from pathlib import Path

    from sims.scene.resolve import BUNDLED_SCENES

    source = str(getattr(getattr(c.world, "source", None), "source", "") or "")
    folders = [BUNDLED_SCENES.resolve()]
    if source and Path(source).exists():
        folders.insert(0, Path(source).resolve().parent)
    base = folders[0]
    path = (base / name).resolve()
    if not any(path.is_relative_to(f) for f in folders):
        raise SimError(f"{name!r}: only files beside the scene file can be loaded")
    if not path.is_file() and path.suffix in (".ttt", ".ttm"):
        xml = path.with_suffix(".simscene.xml" if path.suffix == ".ttt" else ".simmodel.xml")
        path = xml if xml.is_file() else path
    if not path.is_file() or not path.name.endswith(kinds):
        raise SimError(f"{name!r}: no such model or scene file beside the scene")
    return str(path)


def load_model(c: Caller, name: Any, *rest: Any) -> int:
    """A model file beside the scene, added to it (its scripts do not run: see docs/lua.md)."""
    path = _scene_file(c, text(name), (".ttm", ".ttt", ".simscene.xml", ".simmodel.xml"))
    try:
        return int(c.world.load_model(path, persistent=c.persistent))
    except (ValueError, OSError) as exc:
        raise SimError(str(exc)) from None


def load_scene(c: Caller, name: Any, *rest: Any) -> int | None:
    """Replace the scene (the simulation must be stopped), as sim.loadScene: only scene files
    beside the current one (sim.stringparam_scenedefaultdir is that folder)."""
    path = _scene_file(c, text(name), (".ttt", ".simscene.xml"))
    if c.state_code() != 0:
        raise SimError("a scene can only be loaded while the simulation is stopped")
    c.replace_scene(path)
    return c.done
