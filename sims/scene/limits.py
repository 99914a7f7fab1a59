"""How much a scene file may hold: the bounds every scene reader keeps (docs/security.md).

Why bounds: a scene file is input from anyone (a student's upload, a gallery clip), and a few
kilobytes can claim gigabytes: a ``.ttt`` header claims its uncompressed size, a mesh array in
the file's pool can be referred to by any number of shapes, objects and compounds nest as deep
as the file likes. Each bound below is far above what any course scene needs (the figures are
the largest over every scene in ``../shared``) and low enough that reading and showing the
worst file that passes them stays under 512 MB and a few seconds. Passing a bound is a
:class:`LimitError`, which the readers turn into the one-line :class:`SceneError`.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from sims.scene.model import SceneObject

#: bytes read from a scene file (the largest course scene: 1.06 MB)
MAX_FILE_BYTES = 32 * 1024 * 1024
#: a ``.ttt`` body's uncompressed size (the largest course scene: 1.59 MB)
MAX_BODY = 32 * 1024 * 1024
#: a ``.ttt`` body's uncompressed size over its compressed size: course scenes stay under 1.6,
#: Huffman coding cannot shrink real data more than 8 times; only an attack needs more
MAX_RATIO = 4
#: numbers in all the scene's meshes together, vertices and indices, counted once per mesh
#: that uses them (the largest course scene: 239,313)
MAX_MESH_VALUES = 2_000_000
#: objects in one scene (the largest course scene: 244)
MAX_OBJECTS = 100_000
#: objects inside objects (the deepest course scene: 24 levels)
MAX_DEPTH = 256
#: XML elements and attributes in a ``.simscene.xml`` (the course's XML scene: 2,267); each
#: costs about 85 bytes in the parsed tree, so a file of empty elements cannot fill memory
MAX_XML_ITEMS = 1_000_000
#: a texture's width or height in pixels (course scenes: 256)
MAX_TEXTURE_SIDE = 4096
#: pixels in all the scene's textures together (course scenes: 131,072): each costs 4 bytes
#: read and more drawn, for every World that renders the scene
MAX_TEXTURE_PIXELS = 16 * 1024 * 1024
#: compound shapes inside compound shapes (CoppeliaSim's own scenes: 2 or 3)
MAX_COMPOUND_DEPTH = 64


class LimitError(ValueError):
    """A scene file passes one of the bounds above; ``str()`` says which, with the figures."""


class MeshBudget:
    """Counts the numbers the meshes of one scene hold, against :data:`MAX_MESH_VALUES`."""

    def __init__(self, limit: int = MAX_MESH_VALUES):
        self.limit = limit
        self.used = 0

    def take(self, values: int) -> None:
        self.used += values
        if self.used > self.limit:
            raise LimitError(
                f"the scene's meshes hold more than {self.limit:,} numbers in all (vertices "
                f"and indices, once per mesh that uses them); course scenes hold under 250,000"
            )


class TextureBudget:
    """Counts the pixels of one scene's textures against :data:`MAX_TEXTURE_SIDE` and
    :data:`MAX_TEXTURE_PIXELS`."""

    def __init__(self, limit: int = MAX_TEXTURE_PIXELS):
        self.limit = limit
        self.used = 0

    def take(self, name: str, width: int, height: int) -> None:
        if width > MAX_TEXTURE_SIDE or height > MAX_TEXTURE_SIDE:
            raise LimitError(
                f"texture {name!r} is {width}x{height} pixels, more than {MAX_TEXTURE_SIDE} "
                f"on a side (course scenes use 256x256)"
            )
        self.used += width * height
        if self.used > self.limit:
            raise LimitError(
                f"the scene's textures hold more than {self.limit:,} pixels in all "
                f"(course scenes hold under 140,000)"
            )


def check_object_count(count: int) -> None:
    if count > MAX_OBJECTS:
        raise LimitError(
            f"more than {MAX_OBJECTS:,} objects in one scene (course scenes hold a few hundred)"
        )


def check_depth(objects: Sequence[SceneObject]) -> set[int]:
    """Raise :class:`LimitError` when objects nest deeper than :data:`MAX_DEPTH`; return the
    handles that sit on a parent loop (only a broken file has one). Linear in the objects."""
    parent = {o.handle: o.parent for o in objects}
    depth: dict[int, int] = {}
    in_loop: set[int] = set()
    for o in objects:
        chain: list[int] = []
        on_chain: set[int] = set()
        h: int | None = o.handle
        while h is not None and h in parent and h not in depth and h not in on_chain:
            chain.append(h)
            on_chain.add(h)
            h = parent[h]
        base = 0
        if h is not None and h in on_chain:  # the walk came round: a loop from h on
            at = chain.index(h)
            for x in chain[at:]:
                in_loop.add(x)
                depth[x] = 0
            chain = chain[:at]
            base = 1
        elif h is not None and h in depth:
            base = depth[h] + 1
        for x in reversed(chain):
            depth[x] = base
            if base > MAX_DEPTH:
                raise LimitError(
                    f"objects nested more than {MAX_DEPTH} deep (course scenes nest 24 at most)"
                )
            base += 1
    return in_loop
