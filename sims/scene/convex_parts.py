"""Convex parts of a moving, non-convex mesh, so that it collides as its shape, not its hull.

CoppeliaSim's Bullet engine collides a dynamic mesh it calls convex (a flag saved with the mesh)
as its convex hull and any other as its triangles (GImpact). pybullet moves only convex shapes,
so a non-convex mesh becomes a compound of convex parts: the example pack's four-bar links are
bars with round bosses, and their hulls fill the necks the crank passes through, which jammed
the linkage a third of a turn in.

The parts come from V-HACD (shipped with pybullet, ``pybullet.vhacd``), run on the mesh scaled to
a unit box (a thin plate otherwise leaves V-HACD's voxel error above the concavity it would
split at). V-HACD splits a part only when its concavity exceeds its own voxel error, which for
a mildly concave plate with holes takes a grid of millions of voxels (26 s for one 68-vertex
link here). When it returns a single part for a mesh that is not convex, the mesh is cut into
cells instead (``cells``: slabs across an elongated mesh, an 8 x 8 grid over a compact one),
each cell's part the hull of the triangles clipped to it: written here because no library at
hand does it, and it follows an outline to within a cell's width.

Parts are kept as a Wavefront OBJ file, one object per part (pybullet loads such a file as a
compound of hulls), each eroded by the 1 mm pybullet pads a hull with, named by the content
(mesh, method and this module's code as :func:`located.code_keys.code_key` keys it), in the
scene cache's folder (``sims.scene.scene_cache.cache_dir()/convex``; a temporary folder when the
cache is off).
"""

from __future__ import annotations

import hashlib
import math
import os
import tempfile
from pathlib import Path

import numpy as np

from sims.quiet import pybullet as p
from sims.quiet import quiet_fd
from sims.scene.scene_cache import cache_dir

METHOD = "convex-parts/4 vhacd(resolution=100000,unit-box) cells(slabs width/4|grid 8) eroded 1mm"
HULL_MARGIN = 0.001  # m: pybullet pads every convex hull by this much; parts are eroded by it
CONVEX_TOLERANCE = 1e-4  # relative: a vertex this far outside a face plane is a concavity
MAX_SLABS = 32
GRID = 8  # cells a side over a compact mesh


def is_convex(points: np.ndarray, triangles: np.ndarray) -> bool:
    """Every vertex on the inner side of (or on) every face's plane."""
    if len(points) < 4 or len(triangles) < 4:
        return True
    a, b, c = (points[triangles[:, k]] for k in range(3))
    normals = np.cross(b - a, c - a)
    lengths = np.linalg.norm(normals, axis=1)
    keep = lengths > 1e-12
    normals, a = normals[keep] / lengths[keep, None], a[keep]
    size = float(np.ptp(points, axis=0).max()) or 1.0
    outward = np.sign(np.mean(np.einsum("ij,ij->i", normals, a - points.mean(axis=0))))
    worst = 0.0
    for start in range(0, len(normals), 128):  # bounded memory for large meshes
        n = normals[start : start + 128] * (outward or 1.0)
        d = np.einsum("fj,fvj->fv", n, points[None, :, :] - a[start : start + 128, None, :])
        worst = max(worst, float(d.max()))
    return worst <= CONVEX_TOLERANCE * size


def decomposition(points: np.ndarray, triangles: np.ndarray) -> str:
    """The OBJ file of the mesh's convex parts (made once per content, then read back)."""
    points = np.ascontiguousarray(points, dtype=np.float64)
    triangles = np.ascontiguousarray(triangles, dtype=np.int64)
    from located.code_keys import code_key

    h = hashlib.sha256(f"{METHOD}\0{code_key(__name__)}\0".encode())
    h.update(points.tobytes() + b"|" + triangles.tobytes())
    folder = _folder()
    target = folder / f"{h.hexdigest()[:40]}.obj"
    if target.is_file():
        return str(target)
    parts = _vhacd(points, triangles, folder)
    if len(parts) < 2:
        parts = cells(points, triangles)
    _write(target, [_eroded(part) for part in parts])
    return str(target)


def _folder() -> Path:
    base = cache_dir()
    folder = (
        (base / "convex") if base is not None else Path(tempfile.gettempdir()) / "sitegen-convex"
    )
    folder.mkdir(parents=True, exist_ok=True)
    return folder


def _vhacd(points: np.ndarray, triangles: np.ndarray, folder: Path) -> list[np.ndarray]:
    lo = points.min(axis=0)
    scale = np.where(np.ptp(points, axis=0) > 1e-9, np.ptp(points, axis=0), 1.0)
    unit = (points - lo) / scale
    with tempfile.TemporaryDirectory(dir=folder) as tmp:
        src, out, log = (Path(tmp) / n for n in ("in.obj", "out.obj", "log.txt"))
        _write(src, [unit], triangles)
        with quiet_fd(1):
            p.vhacd(str(src), str(out), str(log), resolution=100000)
        if not out.is_file():
            return []
        return [part * scale + lo for part in _read(out)]


def cells(points: np.ndarray, triangles: np.ndarray) -> list[np.ndarray]:
    """The mesh cut by a grid on its two widest principal axes, each cell's part the hull of
    the mesh's triangles clipped to the cell: slabs across an elongated mesh (a bar), an 8 x 8
    grid over a compact one (a wheel with scoops round its rim)."""
    centre = points.mean(axis=0)
    axes = np.linalg.svd(points - centre, full_matrices=False)[2]
    coords = (points - centre) @ axes.T
    extent = np.maximum(np.ptp(coords, axis=0), 1e-6)
    if extent[0] > 2 * extent[1]:
        counts = (int(min(MAX_SLABS, max(2, math.ceil(extent[0] / (extent[1] / 4))))), 1)
    else:
        counts = (GRID, GRID)
    lows = coords.min(axis=0)
    cuts = [np.linspace(lows[k], lows[k] + extent[k], counts[k] + 1) for k in (0, 1)]
    tris = coords[triangles]
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    parts = []
    for i in range(counts[0]):
        for j in range(counts[1]):
            box = ((cuts[0][i], cuts[0][i + 1]), (cuts[1][j], cuts[1][j + 1]))
            sel = (
                (hi[:, 0] >= box[0][0]) & (lo[:, 0] <= box[0][1])
                & (hi[:, 1] >= box[1][0]) & (lo[:, 1] <= box[1][1])
            )  # fmt: skip
            pts = [q for tri in tris[sel] for q in _clip_to(tri, box)]
            if len(pts) >= 4:
                parts.append(np.array(pts) @ axes + centre)
    return parts


def _clip_to(tri: np.ndarray, box: tuple) -> list[np.ndarray]:
    """A triangle clipped to a cell (Sutherland-Hodgman on the cell's four planes)."""
    poly = list(tri)
    for axis, (low, high) in enumerate(box):
        for value, keep_above in ((low, True), (high, False)):
            out: list[np.ndarray] = []
            for k, cur in enumerate(poly):
                prev = poly[k - 1]
                cur_in = cur[axis] >= value if keep_above else cur[axis] <= value
                prev_in = prev[axis] >= value if keep_above else prev[axis] <= value
                if cur_in != prev_in:
                    t = (value - prev[axis]) / (cur[axis] - prev[axis])
                    out.append(prev + (cur - prev) * t)
                if cur_in:
                    out.append(cur)
            poly = out
            if not poly:
                return []
    return poly


def _eroded(part: np.ndarray) -> np.ndarray:
    """The part's points moved in by pybullet's hull margin, so that the padded hull covers
    what the mesh covers (CoppeliaSim's Bullet plugin corrects its hulls the same way)."""
    centre = part.mean(axis=0)
    offset = part - centre
    length = np.linalg.norm(offset, axis=1, keepdims=True)
    step = np.minimum(HULL_MARGIN, length * 0.5)
    return part - offset / np.maximum(length, 1e-12) * step


def _write(path: Path, parts: list[np.ndarray], triangles: np.ndarray | None = None) -> None:
    """One OBJ object per part (vertices only, or the triangles of a single part); written
    to a temporary name and renamed, so a reader never sees half a file."""
    lines: list[str] = []
    first = 1
    for i, part in enumerate(parts):
        lines.append(f"o part_{i}\n")
        lines += [f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in part]
        if triangles is None:  # pybullet takes a part's points from its faces: a fan over all
            n = len(part)
            lines += [f"f {first} {first + k} {first + k + 1}\n" for k in range(1, n - 1)]
        first += len(part)
    if triangles is not None:
        lines += [f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in triangles.tolist()]
    fd, tmp = tempfile.mkstemp(dir=path.parent, suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.writelines(lines)
    os.replace(tmp, path)


def _read(path: Path) -> list[np.ndarray]:
    parts: list[list[list[float]]] = []
    for line in path.read_text().splitlines():
        if line.startswith("o "):
            parts.append([])
        elif line.startswith("v ") and parts:
            parts[-1].append([float(x) for x in line.split()[1:4]])
    return [np.array(part) for part in parts if len(part) >= 4]
