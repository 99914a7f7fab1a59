"""Collision and visual shapes for one part of a scene shape, and collision filter groups.

A CoppeliaSim shape is one mesh or a compound of meshes; each mesh is a primitive (cuboid,
cylinder, sphere, disc, cone, plane) or a triangle mesh. Primitives become pybullet primitives
(exact and fast to collide); a cone, an ellipsoid or a plain mesh becomes a pybullet mesh built
from the saved vertices. pybullet can only collide a *dynamic* body with convex shapes: a
dynamic mesh CoppeliaSim calls convex collides as its convex hull (as there), any other as
convex parts (sims/scene/convex_parts.py; CoppeliaSim collides it as its triangles); a static
mesh keeps its triangles.

Collision filters: respondable shapes are in group ``RESPONDABLE`` and collide with each other;
non-respondable shapes keep a collision shape in group ``DETECTABLE`` that collides with nothing
but is still hit by ray tests, so proximity sensors see it as CoppeliaSim's do.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from sims.quiet import pybullet as p
from sims.scene import convex_parts
from sims.scene.content_files import content_file
from sims.scene.model import Mesh, Pose
from sims.scene.textures import quaternion_matrix, texture_coordinates

RAY = 1  # the group pybullet's ray tests belong to
RESPONDABLE = 2
DETECTABLE = 4
THIN = 0.0005  # m: half thickness given to discs and planes


@dataclass(frozen=True)
class Part:
    """One mesh placed in a link's frame (``pose``), with what it does."""

    mesh: Mesh
    pose: Pose
    respondable: bool
    static: bool
    visible: bool
    owner: str  # the scene shape it comes from (for messages)


def _mesh_points(mesh: Mesh) -> list[tuple[float, float, float]]:
    v = mesh.vertices
    return [(v[i], v[i + 1], v[i + 2]) for i in range(0, len(v) - 2, 3)]


def _cone_mesh(radius: float, height: float, sides: int = 24) -> tuple[list, list]:
    """A cone along z centred on its bounding box (CoppeliaSim's cone primitive frame)."""
    pts = [(0.0, 0.0, height / 2), (0.0, 0.0, -height / 2)]
    for k in range(sides):
        a = 2 * math.pi * k / sides
        pts.append((radius * math.cos(a), radius * math.sin(a), -height / 2))
    tris: list[int] = []
    for k in range(sides):
        a, b = 2 + k, 2 + (k + 1) % sides
        tris += [0, a, b, 1, b, a]
    return pts, tris


def geometry(part: Part) -> tuple[dict, dict] | None:
    """Keyword arguments for createCollisionShape and createVisualShape, or None if empty."""
    m = part.mesh
    sx, sy, sz = m.size
    kind = m.primitive
    if kind == "sphere" and not (math.isclose(sx, sy) and math.isclose(sy, sz)) and m.vertices:
        kind = None  # an ellipsoid: use its mesh
    if kind == "cuboid" or kind == "plane":
        half = (max(sx, 2 * THIN) / 2, max(sy, 2 * THIN) / 2, max(sz, 2 * THIN) / 2)
        return {"shapeType": p.GEOM_BOX, "halfExtents": half}, {
            "shapeType": p.GEOM_BOX,
            "halfExtents": half,
        }
    if kind == "sphere":
        r = max(sx, sy, sz) / 2
        return {"shapeType": p.GEOM_SPHERE, "radius": r}, {"shapeType": p.GEOM_SPHERE, "radius": r}
    if kind in ("cylinder", "disc"):
        r = max(sx, sy) / 2
        h = max(sz, 2 * THIN)
        return {"shapeType": p.GEOM_CYLINDER, "radius": r, "height": h}, {
            "shapeType": p.GEOM_CYLINDER,
            "radius": r,
            "length": h,
        }
    if kind == "cone" and not m.vertices:
        pts, tris = _cone_mesh(max(sx, sy) / 2, sz)
    else:
        pts, tris = _mesh_points(m), list(m.indices)
    if len(pts) < 3 or len(tris) < 3:
        return None
    col = {"shapeType": p.GEOM_MESH, "vertices": pts, "indices": tris}
    vis = {"shapeType": p.GEOM_MESH, "vertices": pts, "indices": tris}
    return col, vis


def create_collision(client: int, part: Part, fixed: bool) -> int:
    """A collision shape for one part (-1 if it has no geometry). A mesh on a moving link
    collides as its convex hull; fixed geometry keeps its triangles."""
    g = geometry(part)
    if g is None:
        return -1
    col = dict(g[0])
    if col["shapeType"] == p.GEOM_MESH and not fixed:
        del col["indices"]
        if _concave(part.mesh, col["vertices"], g[0]["indices"]):
            points = np.asarray(col.pop("vertices"), dtype=np.float64)
            triangles = np.asarray(g[0]["indices"], dtype=np.int64).reshape(-1, 3)
            col["fileName"] = convex_parts.decomposition(points, triangles)
    return p.createCollisionShape(
        **col,
        collisionFramePosition=part.pose.position,
        collisionFrameOrientation=part.pose.quaternion,
        physicsClientId=client,
    )


def _concave(mesh: Mesh, vertices: list, indices: list) -> bool:
    """CoppeliaSim's own convexity flag, else the mesh's shape: a mesh that is not convex
    collides as convex parts (sims/scene/convex_parts.py), as CoppeliaSim collides it as its
    triangles."""
    if mesh.convex is not None:
        return not mesh.convex
    points = np.asarray(vertices, dtype=np.float64)
    triangles = np.asarray(indices, dtype=np.int64).reshape(-1, 3)
    return not convex_parts.is_convex(points, triangles)


def mesh_file(points: list, triangles: list, uvs: np.ndarray | None = None) -> str:
    """The mesh as a Wavefront OBJ file in a cache folder, named by its content (pybullet's EGL
    renderer draws meshes from files only, not from vertex arrays). Written once, atomically.
    ``uvs``: texture coordinates per triangle corner (CoppeliaSim's own layout), as ``vt``."""
    text = "".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in points)
    if uvs is None:
        text += "".join(
            f"f {triangles[i] + 1} {triangles[i + 1] + 1} {triangles[i + 2] + 1}\n"
            for i in range(0, len(triangles) - 2, 3)
        )
    else:
        text += "".join(f"vt {u!r} {v!r}\n" for u, v in uvs.tolist())
        text += "".join(
            f"f {triangles[i] + 1}/{i + 1} {triangles[i + 1] + 1}/{i + 2} "
            f"{triangles[i + 2] + 1}/{i + 3}\n"
            for i in range(0, len(triangles) - 2, 3)
        )
    return content_file("sitegen-scene-meshes", ".obj", text.encode())


def textured_mesh(part: Part) -> str | None:
    """The OBJ file of a textured mesh, with CoppeliaSim's texture coordinates (a textured
    primitive is drawn from its triangles, so that the texture lies as CoppeliaSim lays it);
    None when the mesh has no texture, no triangles, or coordinates CoppeliaSim would drop."""
    m = part.mesh
    mapping = m.texture
    if mapping is None or mapping.image is None or len(m.indices) < 3 or len(m.vertices) < 9:
        return None
    points = np.asarray(m.vertices, dtype=np.float64).reshape(-1, 3)
    indices = np.asarray(m.indices, dtype=np.int64)
    # the texture's pose is in the shape frame, as the mesh's own frame (Ppf) is
    shaped = points @ quaternion_matrix(m.local.quaternion).T + np.asarray(m.local.position)
    uvs = texture_coordinates(mapping, shaped, indices)
    if uvs is None:
        return None
    # pybullet's renderers repeat textures (and TinyRenderer blends the last column with the
    # first near u = 1, measured); a texture CoppeliaSim clamps is drawn from an image with a
    # copied edge texel on each side (texture_file(pad_u, pad_v)), its coordinates moved in.
    image = mapping.image
    sides = ((0, mapping.repeat_u, image.width), (1, mapping.repeat_v, image.height))
    for axis, repeat, size in sides:
        if not repeat:
            uvs[:, axis] = (np.clip(uvs[:, axis], 0.0, 1.0) * size + 1.0) / (size + 2.0)
    return mesh_file(_mesh_points(m), list(m.indices), uvs)


def look_color(mesh: Mesh) -> tuple[float, float, float, float]:
    """The colour a mesh is drawn in: its own, or white under a decal texture (CoppeliaSim's
    decal mode shows the texture's colours, not the mesh's; pybullet modulates)."""
    texture = mesh.texture
    if texture is not None and texture.image is not None and texture.apply == "decal":
        return (1.0, 1.0, 1.0, mesh.opacity)
    return (*mesh.color, mesh.opacity)


def create_visual(client: int, part: Part) -> int:
    """A visual shape for one visible part in its colour (-1 if invisible or empty)."""
    if not (part.visible and part.mesh.visible) or part.mesh.wireframe:
        return -1
    textured = textured_mesh(part)
    if textured is not None:
        return p.createVisualShape(
            shapeType=p.GEOM_MESH,
            fileName=textured,
            meshScale=(1.0, 1.0, 1.0),
            visualFramePosition=part.pose.position,
            visualFrameOrientation=part.pose.quaternion,
            rgbaColor=look_color(part.mesh),
            specularColor=(0.1, 0.1, 0.1),
            physicsClientId=client,
        )
    g = geometry(part)
    if g is None:
        return -1
    vis = dict(g[1])
    if vis["shapeType"] == p.GEOM_MESH:
        vis = {
            "shapeType": p.GEOM_MESH,
            "fileName": mesh_file(vis["vertices"], vis["indices"]),
            "meshScale": (1.0, 1.0, 1.0),
        }
    return p.createVisualShape(
        **vis,
        visualFramePosition=part.pose.position,
        visualFrameOrientation=part.pose.quaternion,
        rgbaColor=look_color(part.mesh),
        specularColor=(0.1, 0.1, 0.1),
        physicsClientId=client,
    )


def mask_allows(mask_a: int, mask_b: int, same_model: bool) -> bool:
    """CoppeliaSim's respondable masks: the low byte between shapes of one tree (the same
    topmost ancestor), the high byte between shapes of different trees."""
    bits = 0x00FF if same_model else 0xFF00
    return bool(mask_a & mask_b & bits)
