"""Moving non-convex meshes collide as convex parts (issue 28): the parts follow the mesh's
outline (a ring keeps its hole), they are cached by content, and a scene whose decomposition is
cached loads in under a second."""

from __future__ import annotations

import math
import time

import numpy as np

from sims.scene import convex_parts
from sims.world import World
from tests.shared_data import shared


def ring(segments: int = 48) -> tuple[np.ndarray, np.ndarray]:
    """A flat ring (10 cm outside, 6 cm inside, 2 cm thick) as a closed triangle mesh."""
    points, triangles = [], []
    for k in range(segments):
        a = 2 * math.pi * k / segments
        for r in (0.1, 0.06):
            for z in (-0.01, 0.01):
                points.append((r * math.cos(a), r * math.sin(a), z))

    def at(k: int, ri: int, zi: int) -> int:
        return 4 * (k % segments) + 2 * ri + zi

    for k in range(segments):
        for ri in (0, 1):
            triangles += [(at(k, ri, 0), at(k + 1, ri, 0), at(k + 1, ri, 1))]
            triangles += [(at(k, ri, 0), at(k + 1, ri, 1), at(k, ri, 1))]
        for zi in (0, 1):
            triangles += [(at(k, 0, zi), at(k + 1, 0, zi), at(k + 1, 1, zi))]
            triangles += [(at(k, 0, zi), at(k + 1, 1, zi), at(k, 1, zi))]
    return np.array(points), np.array(triangles)


def test_cells_of_a_ring_leave_its_hole_open():
    points, triangles = ring()
    assert not convex_parts.is_convex(points, triangles)
    cube = np.array([(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)], dtype=float)
    faces = [(0, 2, 3), (0, 3, 1), (4, 5, 7), (4, 7, 6), (0, 1, 5), (0, 5, 4)]
    faces += [(2, 6, 7), (2, 7, 3), (0, 4, 6), (0, 6, 2), (1, 3, 7), (1, 7, 5)]
    assert convex_parts.is_convex(cube, np.array(faces))
    parts = convex_parts.cells(points, triangles)
    assert len(parts) > 8
    for part in parts:  # every part stays in the ring's band: none reaches the hole
        radii = np.linalg.norm(part[:, :2], axis=1)
        assert radii.min() > 0.06 - 0.02 and radii.max() < 0.1 + 1e-9


def test_decomposition_is_cached_by_content(tmp_path, monkeypatch):
    monkeypatch.setenv("SITEGEN_SCENE_CACHE", str(tmp_path))
    points, triangles = ring()
    first = convex_parts.decomposition(points, triangles)
    started = time.perf_counter()
    again = convex_parts.decomposition(points.copy(), triangles.copy())
    assert again == first and time.perf_counter() - started < 0.1
    assert first.startswith(str(tmp_path / "convex"))
    moved = convex_parts.decomposition(points + 0.001, triangles)
    assert moved != first  # another mesh, another entry


def test_scene_with_convex_parts_loads_in_under_a_second_once_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("SITEGEN_SCENE_CACHE", str(tmp_path))
    path = shared("data", "scenes", "vrep_remoteapi_ex", "fourbar", "solvespace_fourbar.ttt")
    World(str(path)).close()  # decodes the file and decomposes its three links
    assert len(list((tmp_path / "convex").glob("*.obj"))) == 3
    started = time.perf_counter()
    world = World(str(path))
    elapsed = time.perf_counter() - started
    world.close()
    assert elapsed < 1.0, f"{elapsed:.2f} s"
