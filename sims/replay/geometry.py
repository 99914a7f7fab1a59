"""What a World looks like, as coloured triangle meshes per link: the shapes of a replay.

Two sources hold a World's looks, and the renderer draws both:

- pybullet's own visual shapes (``getVisualShapeData``): the models built in Python
  (cart), the arena, obstacles and sitegen's checker floor. A frame given there is
  relative to the link's own (URDF) frame, which for a base is its centre of mass moved back
  by the inertial offset (measured; ``World.link_frame`` computes the same frame);
- a scene file's looks (``model.data["looks"]``, sims/scene/bodies.py): every visible mesh
  of the scene with its pose in its link's frame. The physics links of a scene file carry a
  hidden, transparent sphere only, which is skipped here (alpha 0).

Primitives are tessellated by trimesh (``trimesh.creation``), and normals are split where
faces meet at more than ``SHADING_ANGLE`` (``trimesh.graph.smooth_shade``), so a box has
sharp edges and a wheel a smooth rim. Parts of one colour on one link are merged into one
:class:`Surface`, one draw call in the viewer.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from sims.quiet import pybullet as p

SHADING_ANGLE = math.radians(30.0)
SECTIONS = 24  # around a cylinder, capsule or cone
SPHERE_SUBDIVISIONS = 2  # icosphere: 162 vertices
SLAB = 0.02  # a box thinner than this share of its next side (a tile, a plane): two faces
LinkKey = tuple[int, int]  # (pybullet body id, link index; -1 = base)
Arrays = tuple[np.ndarray, np.ndarray, np.ndarray]  # positions, normals, triangle indices


@dataclass
class Surface:
    """Triangles of one colour on one link, in the link's frame (metres, z up)."""

    rgba: tuple[float, float, float, float]
    positions: np.ndarray  # N×3 float32
    normals: np.ndarray  # N×3 float32, unit length
    indices: np.ndarray  # 3M uint32


class LooksError(RuntimeError):
    """The World was drawn before: its visual-only bodies would be counted twice."""


def _shade(mesh: Any) -> Arrays:
    import trimesh

    smooth = trimesh.graph.smooth_shade(mesh, angle=SHADING_ANGLE)
    positions = np.asarray(smooth.vertices, dtype=np.float64)
    normals = np.asarray(smooth.vertex_normals, dtype=np.float64)
    faces = np.asarray(smooth.faces, dtype=np.int64).reshape(-1)
    return positions, normals, faces


@lru_cache(maxsize=256)
def primitive(kind: str, dims: tuple[float, ...]) -> Arrays:
    """A tessellated primitive centred on its frame, pybullet's axes (cylinders along z)."""
    from trimesh import creation

    if kind == "box" and min(dims) < SLAB * sorted(dims)[1]:
        return _slab(dims)
    if kind == "box":
        mesh = creation.box(extents=dims)
    elif kind == "sphere":
        mesh = creation.icosphere(subdivisions=SPHERE_SUBDIVISIONS, radius=dims[0])
    elif kind == "cylinder":  # (radius, length)
        mesh = creation.cylinder(radius=dims[0], height=dims[1], sections=SECTIONS)
    elif kind == "capsule":  # (radius, length between the centres of the caps)
        mesh = creation.capsule(height=dims[1], radius=dims[0], count=[SECTIONS, SECTIONS // 2])
    else:
        raise ValueError(f"unknown primitive {kind!r}")
    return _shade(mesh)


def _slab(dims: tuple[float, ...]) -> Arrays:
    """A very thin box as its two large faces: its sides are under 2% as wide as the faces
    and draw as a hairline at most, and a checker floor of such tiles shrinks threefold."""
    axis = int(np.argmin(dims))
    u, v = [a for a in range(3) if a != axis]
    pts, normals, faces = [], [], []
    for side in (1.0, -1.0):
        base = len(pts)
        for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
            p = [0.0, 0.0, 0.0]
            p[axis], p[u], p[v] = side * dims[axis] / 2, a * dims[u] / 2, b * dims[v] / 2
            pts.append(p)
            n = [0.0, 0.0, 0.0]
            n[axis] = side
            normals.append(n)
        faces += [base + i for i in (0, 1, 2, 0, 2, 3)]
    pts_a, faces_a = np.asarray(pts), np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    normals_a = np.asarray(normals)
    for tri in faces_a:  # wind each triangle counter-clockwise about its normal
        a, b, c = pts_a[tri]
        if np.dot(np.cross(b - a, c - a), normals_a[tri[0]]) < 0:
            tri[1], tri[2] = tri[2], tri[1]
    return pts_a, normals_a, faces_a.reshape(-1)


def triangles(points: list | np.ndarray, indices: list | np.ndarray) -> Arrays:
    """A triangle mesh (points N×3, flat triangle indices) with split normals."""
    import trimesh

    pts = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    faces = np.asarray(indices, dtype=np.int64).reshape(-1, 3)
    faces = faces[(faces >= 0).all(axis=1) & (faces < len(pts)).all(axis=1)]
    mesh = trimesh.Trimesh(pts, faces, process=False)
    return _shade(mesh)


def rotation(q: tuple[float, ...]) -> np.ndarray:
    """3×3 rotation matrix of a quaternion (x, y, z, w)."""
    x, y, z, w = (float(v) for v in q)
    n = math.sqrt(x * x + y * y + z * z + w * w) or 1.0
    x, y, z, w = x / n, y / n, z / n, w / n
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def placed(arrays: Arrays, position: tuple, quaternion: tuple) -> Arrays:
    """``arrays`` moved by a frame (position, quaternion) into its parent's frame."""
    pts, normals, faces = arrays
    r = rotation(quaternion)
    return pts @ r.T + np.asarray(position, dtype=np.float64), normals @ r.T, faces


def _visual_shape(entry: tuple) -> Arrays | None:
    """pybullet's visual shape data entry as triangles in its link frame (None: not drawn)."""
    kind, dims, file_name, position, quaternion, rgba = (
        entry[2],
        entry[3],
        entry[4],
        entry[5],
        entry[6],
        entry[7],
    )
    if rgba[3] <= 0:
        return None  # the hidden sphere of a scene file's physics link
    if kind == p.GEOM_BOX:
        arrays = primitive("box", tuple(float(d) for d in dims[:3]))
    elif kind == p.GEOM_SPHERE:
        arrays = primitive("sphere", (float(dims[0]),))
    elif kind == p.GEOM_CYLINDER:  # dims: length, radius
        arrays = primitive("cylinder", (float(dims[1]), float(dims[0])))
    elif kind == p.GEOM_CAPSULE:
        arrays = primitive("capsule", (float(dims[1]), float(dims[0])))
    elif kind == p.GEOM_MESH and file_name:
        import trimesh

        mesh = trimesh.load(file_name.decode(), force="mesh", process=False)
        pts = np.asarray(mesh.vertices, dtype=np.float64) * np.asarray(dims[:3], dtype=np.float64)
        arrays = triangles(pts, np.asarray(mesh.faces).reshape(-1))
    else:
        return None
    return placed(arrays, position, quaternion)


def _part_arrays(part: Any) -> Arrays | None:
    """A scene file's part (sims.scene.shapes.Part) as triangles in its link frame."""
    from sims.scene import shapes as S

    if not (part.visible and part.mesh.visible) or part.mesh.wireframe:
        return None
    g = S.geometry(part)
    if g is None:
        return None
    vis = g[1]
    kind = vis["shapeType"]
    if kind == p.GEOM_BOX:
        arrays = primitive("box", tuple(2 * float(h) for h in vis["halfExtents"]))
    elif kind == p.GEOM_SPHERE:
        arrays = primitive("sphere", (float(vis["radius"]),))
    elif kind == p.GEOM_CYLINDER:
        arrays = primitive("cylinder", (float(vis["radius"]), float(vis["length"])))
    else:
        arrays = triangles(vis["vertices"], vis["indices"])
    return placed(arrays, part.pose.position, part.pose.quaternion)


def _colour(rgb: tuple[float, ...]) -> tuple[float, float, float, float]:
    r, g, b = (round(min(1.0, max(0.0, float(v))), 4) for v in rgb[:3])
    return (r, g, b, 1.0)


def world_looks(world: Any) -> dict[LinkKey, list[Surface]]:
    """Every drawn shape of ``world``, grouped by the link that carries it and by colour.

    Call it on a World that has not been drawn (``render``/``sync_visuals`` add a scene file's
    visual-only bodies, whose shapes the looks below already hold)."""
    c = world.client_id
    data = world.model.data
    if "visuals" in data:
        raise LooksError("the World was drawn before: build a fresh one for its looks")
    pieces: dict[LinkKey, dict[tuple, list[Arrays]]] = {}

    def add(key: LinkKey, rgba: tuple, arrays: Arrays | None) -> None:
        if arrays is not None and len(arrays[2]):
            pieces.setdefault(key, {}).setdefault(rgba, []).append(arrays)

    for i in range(p.getNumBodies(physicsClientId=c)):
        body = p.getBodyUniqueId(i, physicsClientId=c)
        for entry in p.getVisualShapeData(body, physicsClientId=c):
            add((body, entry[1]), _colour(entry[7]), _visual_shape(entry))
    for uid, row, _moving, _frame, part in data.get("looks", ()):
        add((uid, row), _colour(part.mesh.color), _part_arrays(part))
    out: dict[LinkKey, list[Surface]] = {}
    for key in sorted(pieces):
        out[key] = [_merge(rgba, parts) for rgba, parts in pieces[key].items()]
    return out


def _merge(rgba: tuple, parts: list[Arrays]) -> Surface:
    offset, pts, normals, faces = 0, [], [], []
    for a, n, f in parts:
        pts.append(a)
        normals.append(n)
        faces.append(f + offset)
        offset += len(a)
    nrm = np.concatenate(normals)
    length = np.linalg.norm(nrm, axis=1, keepdims=True)
    nrm = np.where(length > 1e-12, nrm / np.maximum(length, 1e-12), (0.0, 0.0, 1.0))
    return Surface(
        rgba,
        np.concatenate(pts).astype(np.float32),
        nrm.astype(np.float32),
        np.concatenate(faces).astype(np.uint32),
    )
