"""Shapes of a ``.simscene.xml`` file: primitives, inline meshes, heightfields, compounds, and the
shape's dynamics (see :mod:`sims.scene.xml` for what the file holds)."""

from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET

import numpy as np

from sims.scene.limits import MAX_COMPOUND_DEPTH, LimitError
from sims.scene.model import Dynamics, Mesh, Physics, Pose
from sims.scene.rotations import principal_axes
from sims.scene.xml_values import flag, floats, frame, number, text

PRIMITIVES = {"cuboid", "sphere", "cylinder", "cone", "plane", "disc"}
PARTS = ("primitive", "mesh", "heightfield")


def _color(el: ET.Element) -> tuple[float, float, float]:
    rgb = floats(el, "color/ambientDiffuse", 3)
    if rgb is None:
        return (0.8, 0.8, 0.8)
    return tuple(min(1.0, max(0.0, c / 255.0)) for c in rgb)  # type: ignore[return-value]


def _part(el: ET.Element, notes: list[str]) -> Mesh | None:
    mesh = _geometry(el, notes)
    if mesh is not None and flag(el, "wireframe", False):
        mesh = dataclasses.replace(mesh, wireframe=True)
    return mesh


def _geometry(el: ET.Element, notes: list[str]) -> Mesh | None:
    local = frame(el.find("localFrame"))
    if el.tag == "primitive":
        kind = text(el, "type", "cuboid") or "cuboid"
        if kind not in PRIMITIVES:
            notes.append(f"primitive type {kind!r} not understood, skipped")
            return None
        sx, sy, sz = floats(el, "size", 3) or (0.1, 0.1, 0.1)
        if kind == "sphere":
            sy = sz = sx
        elif kind in ("cylinder", "cone"):
            sy = sx
        return Mesh(primitive=kind, size=(sx, sy, sz), local=local, color=_color(el))
    if el.tag == "mesh":
        if text(el, "fileName") is not None and el.find("vertices") is None:
            notes.append(f"mesh kept in external file {text(el, 'fileName')!r}: not read")
            return None
        vertices = floats(el, "vertices") or ()
        indices = tuple(int(i) for i in floats(el, "indices") or ())
        if len(vertices) % 3 or len(indices) % 3:
            raise ValueError("mesh vertex or index count is not a multiple of 3")
        if indices and (min(indices) < 0 or max(indices) >= len(vertices) // 3):
            raise ValueError("mesh triangle refers to a vertex it does not have")
        return Mesh(vertices=vertices, indices=indices, local=local, color=_color(el))
    # heightfield: a grid of heights, centred on the shape frame
    nx, ny = (int(v) for v in (floats(el, "size", 2) or (2, 2)))
    step = number(el, "gridStep", 0.1)
    heights = floats(el, "data") or ()
    if len(heights) != nx * ny or nx < 2 or ny < 2:
        raise ValueError(f"heightfield holds {len(heights)} heights for a {nx}x{ny} grid")
    ix, iy = np.meshgrid(np.arange(nx), np.arange(ny))
    verts = np.stack(
        [(ix - (nx - 1) / 2) * step, (iy - (ny - 1) / 2) * step, np.array(heights).reshape(ny, nx)],
        axis=-1,
    ).reshape(-1)
    tris = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            a = j * nx + i
            tris += [a, a + 1, a + nx + 1, a, a + nx + 1, a + nx]
    return Mesh(vertices=tuple(verts.tolist()), indices=tuple(tris), local=local, color=_color(el))


def read_geometry(el: ET.Element, notes: list[str]) -> tuple[list[Mesh], bool]:
    """The shape's meshes (in the shape frame) and whether it is a compound."""
    compound = el.find("compound")
    meshes: list[Mesh] = []
    if compound is not None:
        _collect(compound, meshes, notes)
        return meshes, True
    for child in el:
        if child.tag in PARTS:
            mesh = _part(child, notes)
            if mesh is not None:
                meshes.append(mesh)
            break
    return meshes, False


def _collect(el: ET.Element, meshes: list[Mesh], notes: list[str]) -> None:
    """The parts of a compound and of the compounds inside it, in document order, without
    recursion; compounds nested more than ``MAX_COMPOUND_DEPTH`` deep are an error."""
    stack = [(iter(el), 0)]
    while stack:
        children, depth = stack[-1]
        child = next(children, None)
        if child is None:
            stack.pop()
        elif child.tag in PARTS:
            mesh = _part(child, notes)
            if mesh is not None:
                meshes.append(mesh)
        elif child.tag == "compound":
            if depth + 1 > MAX_COMPOUND_DEPTH:
                raise LimitError(f"compound shapes nested more than {MAX_COMPOUND_DEPTH} deep")
            stack.append((iter(child), depth + 1))


def read_dynamics(dyn: ET.Element | None, program: int) -> Dynamics:
    if dyn is None:
        return Dynamics()
    mass = max(number(dyn, "mass", 1.0), 1e-7)
    moments = floats(dyn, "principalMomentOfInertia", 3)
    inertia_frame = frame(dyn.find("localInertiaFrame"))
    matrix = floats(dyn, "inertiaMatrix", 9)
    if moments is not None:
        inertia = tuple(m * mass for m in moments)
    elif matrix is not None:
        com = floats(dyn, "centerOfMass", 3) or (0.0, 0.0, 0.0)
        inertia, axes = principal_axes(matrix)
        inertia_frame = Pose(com, axes)  # type: ignore[arg-type]
    else:
        inertia = (1e-3 * mass,) * 3
    bullet = dyn.find("material/engines/bullet")
    friction = None
    if bullet is not None:
        raw = text(bullet, "oldfriction") or text(bullet, "friction")
        friction = float(raw) if raw is not None else None
    return Dynamics(
        static=flag(dyn, "switches/static", True),
        respondable=flag(dyn, "switches/respondable", False),
        mass=mass,
        inertia=inertia,  # type: ignore[arg-type]
        inertia_frame=inertia_frame,
        friction=friction,
        respondable_mask=int(number(dyn, "respondableMask", 0xFFFF)),
    )


def read_physics(el: ET.Element | None) -> Physics:
    """The scene's ``<dynamics>``: engine, its step and constraint solving iterations."""
    if el is None:
        return Physics()
    engine = text(el, "engine", "bullet") or "bullet"
    node = el.find(f"engines/{engine}")
    step = number(node, "stepsize", 0.005) if node is not None else 0.005
    iterations = int(number(node, "constraintsolvingiterations", 100)) if node is not None else 100
    enabled = flag(el, "switches/dynamicsEnabled", True)
    return Physics(engine, step if step > 0 else 0.005, max(1, iterations), enabled)
