"""Shapes in a ``.ttt`` file: meshes, primitives, compounds, colours, mass and inertia, material.

What the file holds (from CoppeliaSim's shape, mesh, mesh-wrapper, colour and dynamic-material
serializers):
- A top-level ``VIN`` chunk pools the heavy arrays once for the whole file: ``Ver`` (float32
  vertices), ``Ind`` (int32 indices) or ``In2`` (indices packed as deltas: the top two bits of
  the first byte say how many more bytes follow), plus normals and edges we do not need. A mesh
  refers to them by position in the pool (``Vev``, ``Inv``); older meshes may hold ``Ver``/``Ind``
  inline.
- A shape's ``Ge2`` part holds one mesh (``Gst``) or a compound (``Gsg``) whose parts are meshes
  (``Geo``) and sub-compounds (``Wrp``). Every part starts with the compound fields (name, mass
  ``Mas``, inertia ``Ine``: a frame and the principal moments *divided by the mass*, its frame in
  the shape frame; ``Vtb``: the part's frame) and a mesh adds colour ``Cl0``, the pure primitive
  ``Ppr`` (type, then x size or diameter, y size, z size or height) and ``Ppf``: the frame the
  vertices (and the primitive) are expressed in, relative to the shape frame.
- Frames inside a shape are 7 values: position (x, y, z) then quaternion (w, x, y, z) (an
  object's own pose, ``Cfq``, stores the quaternion first).
- The shape's own part: ``Sss`` (bit 7 set: dynamic, i.e. not static), ``Ss3``/``Ss2`` (bit 0:
  respondable), ``Dc2`` (respondable mask), ``Mat`` (the material inline; older files refer to a
  top-level ``DMA`` material by the id in ``Dmi``).
CoppeliaSim 4.5+ replaced ``Ine``/``Vtb``/``Ppf`` with ``Ifr``/``Com``/``Imx``; those are read
too (the inertia matrix taken as mass-less like the older moments, an assumption no course file
can check).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from sims.scene.limits import MAX_COMPOUND_DEPTH, LimitError, MeshBudget
from sims.scene.model import Dynamics, Mesh, Pose, ShapeData
from sims.scene.rotations import principal_axes
from sims.scene.textures import read_texture_property
from sims.scene.ttt_chunks import Chunk, ChunkError, Fields, bit, chunk_list

PRIMITIVES = {1: "plane", 2: "disc", 3: "cuboid", 4: "sphere", 5: "cylinder", 6: "cone"}
OTHER_PRIMITIVES = {7: "heightfield", 8: "capsule"}


def pose7(vals: tuple[float, ...]) -> Pose:
    """A pose stored quaternion first: (w, x, y, z), then position (an object's ``Cfq``)."""
    return _pose(vals[4:7], vals[0:4])


def pose7x(vals: tuple[float, ...]) -> Pose:
    """A pose stored position first, then quaternion (w, x, y, z): CoppeliaSim's 7-vector
    order, used by the mesh and inertia frames (``Ppf``, ``Ine``, ``Vtb``, ``Ifr``)."""
    return _pose(vals[0:3], vals[3:7])


def _pose(pos: tuple[float, ...], wxyz: tuple[float, ...]) -> Pose:
    w, x, y, z = wxyz
    norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
    return Pose(tuple(pos), (x / norm, y / norm, z / norm, w / norm))  # type: ignore[arg-type]


@dataclass
class Pool:
    """The file's shared vertex and index arrays (``VIN``). Meshes that refer to the same array
    share one tuple of it (``tuples``); every mesh's numbers count against the scene's
    ``budget`` (sims/scene/limits.py), since a file may refer to one array from any number of
    shapes."""

    vertices: list[np.ndarray] = field(default_factory=list)
    indices: list[np.ndarray] = field(default_factory=list)
    budget: MeshBudget = field(default_factory=MeshBudget)
    tuples: dict[tuple[str, int], tuple] = field(default_factory=dict)


def read_pool(buf: bytes, chunk: Chunk, budget: MeshBudget | None = None) -> Pool:
    pool = Pool(budget=budget or MeshBudget())
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    for c in parts:
        if c.name == "Ver":
            pool.vertices.append(np.frombuffer(buf, "<f4", (c.end - c.start) // 4, c.start))
        elif c.name == "Ind":
            pool.indices.append(np.frombuffer(buf, "<i4", (c.end - c.start) // 4, c.start))
        elif c.name == "In2":
            pool.indices.append(unpack_indices(buf, c))
    return pool


def unpack_indices(buf: bytes, chunk: Chunk) -> np.ndarray:
    """Indices stored as deltas in 1 to 4 bytes each (``In2``): the top two bits of an item's
    first byte say how many bytes follow; the item is ``first & 63`` plus the following bytes
    shifted by 6, 14 and 22 bits, minus 31, 8191, 2097151 or 536870911. Vectorised: the item
    starts are the orbit of byte 0 under "skip this item", found by pointer doubling."""
    f = Fields(buf, chunk)
    count = f.i32()
    data = np.frombuffer(buf, np.uint8, chunk.end - f.pos, f.pos)
    n = len(data)
    if count < 0 or count > n:
        raise ChunkError("packed index list is longer than its chunk")
    if count == 0:
        return np.zeros(0, dtype=np.int64)
    extra = (data >> 6).astype(np.int64)
    jump = np.minimum(np.arange(n, dtype=np.int64) + 1 + extra, n)
    jump = np.append(jump, n)  # position n: past the end, stays there
    starts = np.zeros(1, dtype=np.int64)
    while len(starts) < count:
        starts = np.concatenate([starts, jump[starts]])
        jump = jump[jump]
    starts = starts[:count]
    if starts[-1] >= n or starts[-1] + extra[starts[-1]] >= n:
        raise ChunkError("packed index list is truncated")
    padded = np.append(data, np.zeros(3, dtype=np.uint8)).astype(np.int64)
    k = extra[starts]
    value = padded[starts] & 0x3F
    for i in range(1, 4):
        value += np.where(k >= i, padded[starts + i] << (6 + 8 * (i - 1)), 0)
    bias = np.array([31, 8191, 2097151, 536870911], dtype=np.int64)
    return np.cumsum(value - bias[k])


def read_color(buf: bytes, chunk: Chunk) -> tuple[float, float, float] | None:
    """The ambient/diffuse colour of a colour object (``Cl3``: 15 floats, the first three)."""
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    for c in parts:
        if c.name == "Cl3":
            return _clamp3(Fields(buf, c).f32(3))
        if c.name in ("Cl2", "Cls"):  # before V-REP 3.1.3: ambient + half the diffuse part
            v = Fields(buf, c).f32(6)
            avg = (v[3] + v[4] + v[5]) / 3.0
            rgb = [(v[i] + avg * 0.5) / 0.85 for i in range(3)]
            top = max(rgb)
            return _clamp3(tuple(x / top for x in rgb) if top > 1.0 else tuple(rgb))
    return None


def read_opacity(buf: bytes, chunk: Chunk) -> float:
    """A colour object's opacity: ``Trf`` (float32) when ``Var`` bit 2 is clear (translucent)."""
    opacity, translucent = 1.0, False
    for c in chunk_list(buf, chunk.start, chunk.end)[0]:
        if c.name == "Trf":
            opacity = min(1.0, max(0.0, Fields(buf, c).f32()[0]))
        elif c.name == "Var":
            translucent = not bit(Fields(buf, c).u8(), 2)
    return opacity if translucent else 1.0


def read_colors(buf: bytes, chunk: Chunk) -> tuple[float, ...] | None:
    """All 15 floats of a colour object: ambient/diffuse, diffuse, specular, emission, aux."""
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    for c in parts:
        if c.name == "Cl3":
            return Fields(buf, c).f32(15)
    return None


def _clamp3(v: tuple[float, ...]) -> tuple[float, float, float]:
    return tuple(min(1.0, max(0.0, float(x))) for x in v[:3])  # type: ignore[return-value]


def read_friction(buf: bytes, chunk: Chunk) -> float | None:
    """Bullet friction of a dynamic material (``BuN``: float params, index 1 is the friction of
    Bullet 2.78, the engine the course scenes were saved with; ``Bul`` before 2016)."""
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    friction = None
    for c in parts:
        f = Fields(buf, c)
        if c.name == "Bul":
            friction = f.f32(2)[1]
        elif c.name in ("BuN", "_uN"):
            nfloat = f.i32()
            f.i32()
            if nfloat >= 2:
                friction = f.real(2)[1]
    return friction


def material_id(buf: bytes, chunk: Chunk) -> int | None:
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    for c in parts:
        if c.name == "Ipa":
            return Fields(buf, c).i32()
    return None


@dataclass
class _Part:
    """What one compound level says about itself (all optional)."""

    mass: float | None = None
    inertia_frame: Pose | None = None
    moments: tuple[float, float, float] | None = None
    frame: Pose | None = None  # 4.5+: the part's frame in its parent part
    com: tuple[float, float, float] | None = None
    matrix: tuple[float, ...] | None = None
    material: int | None = None
    convex: bool | None = None  # before 4.5: the wrapper's convex flag


def _part_field(buf: bytes, c: Chunk, part: _Part) -> bool:
    f = Fields(buf, c)
    if c.name in ("Mas", "_as"):
        part.mass = f.real()[0] or 0.001
    elif c.name in ("Ine", "_ne"):
        part.inertia_frame = pose7x(f.real(7))
        part.moments = tuple(f.real(3))  # type: ignore[assignment]
    elif c.name == "Ifr":
        part.frame = pose7x(f.f64(7))
    elif c.name == "Com":
        part.com = tuple(f.f64(3))  # type: ignore[assignment]
    elif c.name == "Imx":
        part.matrix = f.f64(9)
    elif c.name == "Dmi":
        part.material = f.i32()
    elif c.name == "Var":
        part.convex = bit(f.u8(), 2)
    else:
        return c.name in ("Nme", "Vtb", "_tb", "Bbf", "Bbs")
    return True


class ShapeReader:
    """Turns one shape's ``Ge2`` part into meshes and the root part's mass and inertia."""

    def __init__(self, buf: bytes, pool: Pool, unknown: set[str]):
        self.buf = buf
        self.pool = pool
        self.unknown = unknown  # chunk names met and not understood (for the notes)
        self.meshes: list[Mesh] = []
        self.root = _Part()
        self.compound = False

    def read_geometry(self, chunk: Chunk) -> None:
        for c in chunk_list(self.buf, chunk.start, chunk.end)[0]:
            if c.name == "Gst":
                self._mesh(c, self.root)
            elif c.name == "Gsg":
                self.compound = True
                self._wrapper(c, self.root)
            elif c.name != "Coj":
                self.unknown.add(f"shape geometry {c.name}")

    def _wrapper(self, chunk: Chunk, part: _Part, depth: int = 0) -> int:
        if depth > MAX_COMPOUND_DEPTH:
            raise LimitError(f"compound shapes nested more than {MAX_COMPOUND_DEPTH} deep")
        parts, pos = chunk_list(self.buf, chunk.start, chunk.end)
        for c in parts:
            if _part_field(self.buf, c, part):
                continue
            if c.name == "Geo":
                self._mesh(c, _Part(), depth + 1)
            elif c.name == "Wrp":
                self._wrapper(c, _Part(), depth + 1)
            else:
                self.unknown.add(f"compound {c.name}")
        return pos

    def _mesh(self, chunk: Chunk, part: _Part, depth: int = 0) -> None:
        pos = self._wrapper(chunk, part, depth)
        parts, _ = chunk_list(self.buf, pos, chunk.end)
        vertices: np.ndarray | None = None
        indices: np.ndarray | None = None
        pooled: dict[str, int] = {}  # "v"/"i" -> the pool array used
        primitive: str | None = None
        size = (0.0, 0.0, 0.0)
        local = part.frame or Pose()
        color = (0.8, 0.8, 0.8)
        wireframe = False
        convex = part.convex
        texture = None
        opacity = 1.0
        for c in parts:
            f = Fields(self.buf, c)
            if c.name == "Cl0":
                color = read_color(self.buf, c) or color
                opacity = read_opacity(self.buf, c)
            elif c.name == "Vev":
                pooled["v"] = f.i32()
                vertices = self._pooled(self.pool.vertices, pooled["v"], "vertex")
            elif c.name == "Inv":
                pooled["i"] = f.i32()
                indices = self._pooled(self.pool.indices, pooled["i"], "index")
            elif c.name == "Ver":
                vertices = np.frombuffer(self.buf, "<f4", (c.end - c.start) // 4, c.start)
                pooled.pop("v", None)
            elif c.name == "Ind":
                indices = np.frombuffer(self.buf, "<i4", (c.end - c.start) // 4, c.start)
                pooled.pop("i", None)
            elif c.name == "In2":
                indices = unpack_indices(self.buf, c)
                pooled.pop("i", None)
            elif c.name in ("Ppr", "_pr"):
                kind = f.i32()
                primitive = PRIMITIVES.get(kind)
                if primitive is not None:
                    size = tuple(abs(x) for x in f.real(3))  # type: ignore[assignment]
                if kind in OTHER_PRIMITIVES:
                    self.unknown.add(f"{OTHER_PRIMITIVES[kind]} primitive (kept as a mesh)")
            elif c.name in ("Ppf", "_pf"):
                local = pose7x(f.real(7))
            elif c.name == "Var":  # bits: 0 visible edges, 1 culling, 2 wireframe
                wireframe = bit(f.u8(), 2)
            elif c.name == "Va2":  # 4.5+: bit 0 convex
                convex = bit(f.u8(), 0)
            elif c.name == "Toj":
                texture = read_texture_property(self.buf, c)
            elif c.name not in _MESH_IGNORED:
                self.unknown.add(f"mesh {c.name}")
        if vertices is None or indices is None:
            vertices = np.zeros(0, dtype=np.float32)
            indices = np.zeros(0, dtype=np.int64)
            pooled.clear()
        if len(vertices) % 3 or len(indices) % 3:
            raise ChunkError("a mesh's vertex or index count is not a multiple of 3")
        if len(indices) and (indices.min() < 0 or indices.max() >= len(vertices) // 3):
            raise ChunkError("a mesh's triangle refers to a vertex it does not have")
        self.pool.budget.take(len(vertices) + len(indices))
        self.meshes.append(
            Mesh(
                vertices=self._tuple("v", pooled, vertices, float),
                indices=self._tuple("i", pooled, indices, int),
                primitive=primitive,
                size=size,
                local=local,
                color=color,
                wireframe=wireframe,
                convex=convex,
                texture=texture,
                opacity=opacity,
            )
        )

    def _tuple(self, kind: str, pooled: dict[str, int], array: np.ndarray, of: type) -> tuple:
        """The array as a tuple of Python numbers, shared by every mesh using the same pool
        array (a file may refer to one array from thousands of shapes)."""
        key = (kind, pooled[kind]) if kind in pooled else None
        found = self.pool.tuples.get(key) if key is not None else None
        if found is None:
            found = tuple((array.astype(np.float64) if of is float else array).tolist())
            if key is not None:
                self.pool.tuples[key] = found
        return found

    def _pooled(self, arrays: list[np.ndarray], index: int, what: str) -> np.ndarray:
        if not 0 <= index < len(arrays):
            raise ChunkError(f"a mesh refers to {what} array {index}, the file has {len(arrays)}")
        return arrays[index]

    def dynamics(self, static: bool, respondable: bool, mask: int, friction: float | None):
        root = self.root
        mass = root.mass if root.mass is not None else 1.0
        frame = root.inertia_frame or Pose()
        moments = root.moments or (1e-3, 1e-3, 1e-3)
        if root.matrix is not None:  # 4.5+: full matrix about the centre of mass
            moments, axes = principal_axes(root.matrix)
            frame = Pose(root.com or (0.0, 0.0, 0.0), axes)
        return Dynamics(
            static=static,
            respondable=respondable,
            mass=mass,
            inertia=tuple(m * mass for m in moments),  # type: ignore[arg-type]
            inertia_frame=frame,
            friction=friction,
            respondable_mask=mask,
        )

    def shape(self, dynamics: Dynamics) -> ShapeData:
        return ShapeData(meshes=tuple(self.meshes), compound=self.compound, dynamics=dynamics)


_MESH_IGNORED = {
    "Cl2", "Ecl", "Nov", "Vvd", "Nor", "No2", "Ved", "Pp2", "_p2", "Gsa", "_sa", "Gs2", "_s2",
    "Hfd", "_fd",
}  # fmt: skip


def shape_flags(buf: bytes, chunks: list[Chunk]) -> tuple[bool, bool, int]:
    """(static, respondable, respondable mask) from a shape's own part."""
    static, respondable, mask = True, False, 0xFFFF
    for c in chunks:
        f = Fields(buf, c)
        if c.name == "Sss":
            static = not bit(f.u8(), 7)
        elif c.name in ("Ss3", "Ss2"):
            respondable = bit(f.u8(), 0)
        elif c.name == "Dc2":
            mask = f.u16()
    return static, respondable, mask
