"""``sim.*`` functions on shapes and their physics (colours, mass, contacts), joint matrices,
and graphs (their streams kept as data for the clip, as drawing objects are)."""

from __future__ import annotations

from typing import Any

from sims.quiet import pybullet as p
from sims.remote_api import commands as cmd

from .context import Caller, SimError
from .values import integer, number, numbers, text


def _body(c: Caller, h: int) -> tuple[int, int]:
    ref = c.world.object_ref(h)
    if ref is None or ref.body < 0:
        raise SimError(f"object {c.world.name_of(h)!r} has no body")
    return ref.body, ref.link


def set_shape_color(c: Caller, h: Any, name: Any, component: Any, rgb: Any) -> int | None:
    """Kept per shape and component (sim.colorcomponent_ambient_diffuse...); a shape that is
    its own pybullet body (a created primitive) is drawn in it."""
    hh = c.handle(h)
    e = c.entry(hh) if hh >= 0 else None
    color = numbers(rgb)[:3]
    if e is None or len(color) < 3:
        return c.done
    c.store.object_params[(hh, "color", integer(component, 3, 0))] = color
    created = c.world.created(hh) if hasattr(c.world, "created") else None
    if created is not None and created.body >= 0:
        p.changeVisualShape(created.body, -1, rgbaColor=(*color, 1.0),
                            physicsClientId=c.world.client_id)  # fmt: skip
    return c.done


def get_shape_color(c: Caller, h: Any, name: Any, component: Any) -> tuple[int, list[float]]:
    hh = c.handle(h)
    c.entry(hh)
    color = c.store.object_params.get((hh, "color", integer(component, 3, 0)))
    if color is None:
        obj = c.world.model.data.get(c.world.name_of(hh)) if hasattr(c.world, "model") else None
        meshes = getattr(getattr(obj, "shape", None), "meshes", None) or ()
        color = list(meshes[0].color) if meshes else [0.8, 0.8, 0.8]
    return 1, [float(v) for v in color]


def get_shape_mass(c: Caller, h: Any) -> float:
    hh = c.handle(h)
    c.entry(hh)
    body, link = _body(c, hh)
    return float(p.getDynamicsInfo(body, link, physicsClientId=c.world.client_id)[0])


def set_shape_mass(c: Caller, h: Any, mass: Any) -> int | None:
    hh = c.handle(h)
    c.entry(hh)
    body, link = _body(c, hh)
    p.changeDynamics(body, link, mass=max(0.0, number(mass, 2)), physicsClientId=c.world.client_id)
    return c.done


def get_contact_info(c: Caller, dynamic_pass: Any, h: Any, index: Any) -> Any:
    """The ``index``-th contact of an object (sim.handle_all: of any object) in the last physics
    step: (objects, point, force and normal); nothing past the last."""
    hh = integer(h, 2)
    i = integer(index, 3) & 0x3FFFF
    cid = c.world.client_id
    if hh == -2:
        points = p.getContactPoints(physicsClientId=cid)
    else:
        hh = c.handle(hh)
        c.entry(hh)
        body, link = _body(c, hh)
        points = [pt for pt in p.getContactPoints(bodyA=body, physicsClientId=cid)
                  if pt[3] == link]  # fmt: skip
    if not 0 <= i < len(points):
        return None
    pt = points[i]
    a = _handle_of(c, pt[1], pt[3])
    b = _handle_of(c, pt[2], pt[4])
    normal = [float(v) for v in pt[7]]
    force = [float(v) * pt[9] for v in pt[7]]
    return [a, b], [float(v) for v in pt[5]], force + normal


def _handle_of(c: Caller, body: int, link: int) -> int:
    for ref in c.world.object_refs():
        if ref.body == body and ref.link == link and c.world.kind(ref.name) == "shape":
            return int(c.world.handle(ref.name))
    return -1


def get_object_uid(c: Caller, h: Any) -> int:
    hh = c.handle(h)
    c.entry(hh)
    return hh


def get_joint_matrix(c: Caller, h: Any) -> list[float]:
    try:
        return [float(v) for v in cmd.joint_matrix(c.world, c.handle(h))]
    except (cmd.CommandError, KeyError) as exc:
        raise SimError(str(exc).strip("'\"")) from None


def set_spherical_joint_matrix(c: Caller, h: Any, m: Any) -> int | None:
    try:
        cmd.set_spherical_matrix(c.world, c.handle(h), numbers(m)[:12])
    except (cmd.CommandError, KeyError) as exc:
        raise SimError(str(exc).strip("'\"")) from None
    return c.done


# -- graphs: their streams kept as data ----------------------------------------------------------
def _graph(c: Caller, h: Any) -> dict[str, list[tuple[float, float]]]:
    hh = c.handle(h)
    c.entry(hh)
    return c.store.object_params.setdefault((hh, "graph"), {})


def set_graph_user_data(c: Caller, h: Any, stream: Any, value: Any) -> int | None:
    _graph(c, h).setdefault(text(stream, 2), []).append((c.time, number(value, 3)))
    return c.done


def handle_graph(c: Caller, h: Any, time: Any = None) -> int:
    if integer(h, 1) != -2:  # sim.handle_all
        _graph(c, h)
    return 1


def reset_graph(c: Caller, h: Any) -> int | None:
    _graph(c, h).clear()
    return c.done


def add_graph_stream(c: Caller, h: Any, name: Any, unit: Any = "", *rest: Any) -> int:
    streams = _graph(c, h)
    key = text(name, 2)
    streams.setdefault(key, [])
    return list(streams).index(key) + 1


def set_graph_stream_value(c: Caller, h: Any, stream: Any, value: Any) -> None:
    streams = _graph(c, h)
    names = list(streams)
    i = integer(stream, 2) - 1
    if not 0 <= i < len(names):
        raise SimError(f"graph stream {stream} does not exist")
    streams[names[i]].append((c.time, number(value, 3)))
