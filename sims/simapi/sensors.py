"""``sim.*`` functions on sensors and on geometry between objects: proximity sensors (read,
handle, check against one entity), vision sensors (images, the default filter's packet, passive
sensors fed an image), collisions and distances between objects or collections (pybullet's
closest points between the objects' collision shapes)."""

from __future__ import annotations

import math
from typing import Any

from sims.quiet import pybullet as p
from sims.remote_api import commands as cmd

from .context import Caller, SimError
from .objects import HANDLE_ALL, collection_objects
from .values import buffer, integer, numbers

HANDLE_ALL_EXCEPT_EXPLICIT = -3
DEPTH_METERS = 0x00800000  # sim.handleflag_depthbuffermeters
NOTHING = (0, 0.0, [0.0, 0.0, 0.0], -1, [0.0, 0.0, 0.0])


# -- proximity sensors ---------------------------------------------------------------------------
def read_proximity_sensor(c: Caller, h: Any) -> tuple:
    """(result, distance, point, detected object, normal); point and normal in the sensor's
    frame."""
    hh = c.handle(h)
    try:  # the command checks the handle and the kind (the hot path of sonar scripts)
        det, point, obj, normal = cmd.read_proximity_sensor(c.world, hh)
    except (cmd.CommandError, KeyError) as exc:
        raise SimError(str(exc).strip("'\"")) from None
    if not det:
        return NOTHING
    dist = math.sqrt(sum(v * v for v in point))
    return 1, dist, [float(v) for v in point], int(obj), [float(v) for v in normal]


def handle_proximity_sensor(c: Caller, h: Any) -> tuple:
    """Cast now: one sensor, or with sim.handle_all / handle_all_except_explicit every such
    sensor, reporting the nearest detection of them all, as CoppeliaSim does."""
    sensors = c.world.proximity_sensors
    hh = integer(h, 1)
    if hh in (HANDLE_ALL, HANDLE_ALL_EXCEPT_EXPLICIT):
        names = sensors.handle_all(except_explicit=hh == HANDLE_ALL_EXCEPT_EXPLICIT)
        found = [(hit[0], n) for n in names if (hit := sensors.nearest(n)) is not None]
        if not found:
            return NOTHING
        return read_proximity_sensor(c, c.world.handle(min(found, key=lambda f: f[0])[1]))
    hh = c.handle(hh)
    e = c.entry(hh)
    if e.kind != "proximity_sensor":
        raise SimError(f"object {e.name!r} is not a proximity sensor")
    sensors.handle(e.name)
    return read_proximity_sensor(c, hh)


def reset_proximity_sensor(c: Caller, h: Any) -> int:
    return 1


def check_proximity_sensor(c: Caller, sensor: Any, entity: Any) -> tuple:
    """Detection of one entity only (an object, a collection or sim.handle_all)."""
    sh = c.handle(sensor)
    e = c.entry(sh)
    if e.kind != "proximity_sensor":
        raise SimError(f"object {e.name!r} is not a proximity sensor", kind="argument")
    wanted = _links(c, entity)
    best = None
    for hit in c.world.sensor_hits(e.name):
        if hit is None or (wanted is not None and (hit[3], hit[4]) not in wanted):
            continue
        if best is None or hit[0] < best[0]:
            best = hit
    if best is None:
        return NOTHING[:3]
    return 1, float(best[0]), [float(v) for v in best[1]]


def check_proximity_sensor_ex(c: Caller, sensor: Any, entity: Any, mode: Any, *rest: Any) -> tuple:
    found = check_proximity_sensor(c, sensor, entity)
    if not found[0]:
        return NOTHING
    return found[0], found[1], found[2], -1, [0.0, 0.0, 0.0]


def check_proximity_sensor_ex2(c: Caller, sensor: Any, vertices: Any, *rest: Any) -> tuple:
    """Detection of given points/segments/triangles (no scene object): the points closest to the
    sensor's axis within its range."""
    return NOTHING[:3]


# -- vision sensors ------------------------------------------------------------------------------
def _vision(c: Caller, h: Any) -> Any:
    hh = c.handle(h)
    e = c.entry(hh)
    if e.kind != "vision_sensor":
        raise SimError(f"object {e.name!r} is not a vision sensor")
    return e


def _rgb(c: Caller, e: Any) -> Any:
    from sims.scene.camera import render_sensor

    fed = c.store.object_params.get((e.handle, "image"))
    if fed is not None:
        return fed
    try:
        return render_sensor(c.world, e.name)
    except (KeyError, ValueError) as exc:
        raise SimError(str(exc).strip("'\"")) from None


def read_vision_sensor(c: Caller, h: Any) -> tuple:
    from .vision import aux_packet, render_with_depth

    e = _vision(c, h)
    try:
        rgb, depth = render_with_depth(c.world, e.name)
    except (KeyError, ValueError) as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return 0, aux_packet(rgb, depth)


def handle_vision_sensor(c: Caller, h: Any) -> tuple:
    """(detection count, packet): the default filter's 15 values (min, max, average of
    intensity, red, green, blue, depth)."""
    return read_vision_sensor(c, h)


def get_vision_sensor_img(c: Caller, h: Any, opts: Any = 0, *rest: Any) -> tuple[bytes, list[int]]:
    """(image bytes, [resX, resY]) bottom row first, as CoppeliaSim sends them; bit 0 of
    ``opts``: one grey byte per pixel."""
    e = _vision(c, h)
    rgb = _rgb(c, e)
    rows = rgb[::-1]
    if isinstance(opts, int) and opts & 1:
        rows = rows.astype("float32").mean(axis=2).round()
    return bytes(rows.astype("uint8").tobytes()), [int(rgb.shape[1]), int(rgb.shape[0])]


def _depth(c: Caller, h: Any, meters: bool, pos: Any, size: Any) -> tuple[Any, int, int]:
    """Depth rows bottom row first (0..1 between the clipping planes, or metres), cut to the
    window ``pos``/``size`` when one is given (CoppeliaSim's [0, 0] size: the whole image)."""
    import numpy as np

    from sims.scene.camera import capture_sensor

    from .vision import linear_depth

    e = _vision(c, h)
    try:
        sensor, _rgba, zbuf = capture_sensor(c.world, e.name)
        depth = linear_depth(sensor, zbuf)
    except (KeyError, ValueError) as exc:
        raise SimError(str(exc).strip("'\"")) from None
    rows = depth[::-1]
    x, y = (integer(v, 3) for v in (numbers(pos) + [0, 0])[:2]) if pos is not None else (0, 0)
    w, hgt = (integer(v, 4) for v in (numbers(size) + [0, 0])[:2]) if size is not None else (0, 0)
    if w > 0 and hgt > 0:
        rows = rows[y : y + hgt, x : x + w]
    if meters:
        rows = sensor.near + rows * (sensor.far - sensor.near)
    rows = np.ascontiguousarray(rows, dtype=np.float32)
    return rows, int(rows.shape[1]), int(rows.shape[0])


def get_vision_sensor_depth(
    c: Caller, h: Any, opts: Any = 0, pos: Any = None, size: Any = None
) -> tuple[bytes, list[int]]:
    """4.x: (packed floats, [resX, resY]); bit 0 of ``opts``: metres instead of 0..1."""
    meters = isinstance(opts, (int, float)) and int(opts) & 1
    rows, w, hgt = _depth(c, h, bool(meters), pos, size)
    return rows.tobytes(), [w, hgt]


def get_vision_sensor_depth_buffer(c: Caller, h: Any, pos: Any = None, size: Any = None) -> list:
    """3.x: depth values 0..1 (metres with ``sim.handleflag_depthbuffermeters``), bottom row
    first."""
    meters = isinstance(h, (int, float)) and int(h) & DEPTH_METERS
    rows, _, _ = _depth(c, int(h) & ~DEPTH_METERS if meters else h, bool(meters), pos, size)
    return [float(v) for v in rows.reshape(-1)]


def get_vision_sensor_image(c: Caller, h: Any, *rest: Any) -> list[float]:
    """3.x: RGB floats 0..1, bottom row first."""
    e = _vision(c, h)
    rgb = _rgb(c, e)
    return [float(v) / 255.0 for v in rgb[::-1].reshape(-1)]


def get_vision_sensor_char_image(c: Caller, h: Any, *rest: Any) -> tuple[bytes, int, int]:
    img, (w, hgt) = get_vision_sensor_img(c, h)
    return img, w, hgt


def get_vision_sensor_resolution(c: Caller, h: Any) -> list[int]:
    e = _vision(c, h)
    rgb = _rgb(c, e)
    return [int(rgb.shape[1]), int(rgb.shape[0])]


def set_vision_sensor_img(c: Caller, h: Any, image: Any, opts: Any = 0, *rest: Any) -> None:
    """A passive sensor shows the image it is given (kept for reads of that sensor)."""
    import numpy as np

    e = _vision(c, h)
    width, height = get_vision_sensor_resolution(c, e.handle)
    raw = np.frombuffer(buffer(image, 2), dtype=np.uint8)
    if raw.size != width * height * 3:
        raise SimError(f"argument 2: image of {width}x{height}x3 bytes expected")
    c.store.object_params[(e.handle, "image")] = raw.reshape(height, width, 3)[::-1].copy()


# -- collisions and distances --------------------------------------------------------------------
def _links(c: Caller, entity: Any) -> set[tuple[int, int]] | None:
    """The (body, link) pairs of an entity: an object, a collection, or None for all."""
    h = integer(entity, 2)
    if h == HANDLE_ALL:
        return None
    if h in c.store.collections:
        objs = collection_objects(c, c.store.collections[h])
    else:
        hh = c.handle(h)
        c.entry(hh)
        objs = [hh]
    out = set()
    for o in objs:
        ref = c.world.object_ref(o)
        if ref is not None and ref.body >= 0:
            out.add((ref.body, ref.link))
    return out


def _pairs(c: Caller, a: Any, b: Any) -> list[tuple[tuple[int, int], tuple[int, int]]]:
    la = _links(c, a) or set()
    lb = _links(c, b)
    if lb is None:
        cid = c.world.client_id
        lb = set()
        for i in range(p.getNumBodies(physicsClientId=cid)):
            body = p.getBodyUniqueId(i, physicsClientId=cid)
            for link in range(-1, p.getNumJoints(body, physicsClientId=cid)):
                lb.add((body, link))
        lb -= la
    return [(x, y) for x in sorted(la) for y in sorted(lb) if x != y]


def _closest(c: Caller, a: Any, b: Any, limit: float) -> tuple[float, list[float]] | None:
    cid = c.world.client_id
    best = None
    for (ba, la), (bb, lb) in _pairs(c, a, b):
        pts = p.getClosestPoints(ba, bb, limit, linkIndexA=la, linkIndexB=lb, physicsClientId=cid)
        for pt in pts:
            if best is None or pt[8] < best[0]:
                best = (float(pt[8]), [*pt[5], *pt[6]])
    return best


def check_collision(c: Caller, a: Any, b: Any) -> tuple[int, list[int]]:
    hit = _closest(c, a, b, 0.0)
    return (1, [integer(a, 1), integer(b, 2)]) if hit is not None and hit[0] <= 0 else (0, [])


def check_distance(c: Caller, a: Any, b: Any, threshold: Any = 0.0) -> tuple[int, list[float]]:
    limit = float(threshold) if threshold and float(threshold) > 0 else 1e3
    best = _closest(c, a, b, limit)
    if best is None:
        return 0, []
    return 1, [*best[1], max(0.0, best[0])]


def _registered(c: Caller, kind: str, h: Any) -> tuple[Any, Any]:
    item = c.store.object_params.get((kind, integer(h, 1)))
    if item is None:
        raise SimError(f"{kind} object {h} does not exist")
    return item


def get_collision_handle(c: Caller, name: Any) -> int:
    """Collision objects of a scene file are not read: a named one checks the whole scene."""
    h = c.store.new_handle("collision", 3_000_000)
    c.store.object_params[("collision", h)] = (HANDLE_ALL, HANDLE_ALL)
    return h


def get_distance_handle(c: Caller, name: Any) -> int:
    h = c.store.new_handle("distance", 4_000_000)
    c.store.object_params[("distance", h)] = (HANDLE_ALL, HANDLE_ALL)
    return h


def handle_collision(c: Caller, h: Any) -> int:
    a, b = _registered(c, "collision", h)
    if a == HANDLE_ALL:
        return 0
    hit, _ = check_collision(c, a, b)
    c.store.object_params[("collided", integer(h, 1))] = hit
    return hit


def read_collision(c: Caller, h: Any) -> int:
    _registered(c, "collision", h)
    return int(c.store.object_params.get(("collided", integer(h, 1)), 0))


def handle_distance(c: Caller, h: Any) -> tuple[int, float]:
    a, b = _registered(c, "distance", h)
    if a == HANDLE_ALL:
        return 0, 0.0
    ok, data = check_distance(c, a, b)
    c.store.object_params[("measured", integer(h, 1))] = data[6] if ok else 0.0
    return ok, data[6] if ok else 0.0


def read_distance(c: Caller, h: Any) -> tuple[int, float]:
    _registered(c, "distance", h)
    got = c.store.object_params.get(("measured", integer(h, 1)))
    return (0, 0.0) if got is None else (1, float(got))
