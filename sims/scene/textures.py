"""Textures of a scene: the images a ``.ttt`` file holds and how each shape's mesh maps one.

What the file holds (from CoppeliaSim's texture-object and texture-property serializers):
- A top-level ``TEX`` chunk per texture object: ``Ipa`` (int32 id, int32 width, int32 height),
  ``Gon`` (its name), ``Bst`` (bit 0: the image was given with alpha) and ``Img``: width x height
  pixels of 3 (RGB) or 4 (RGBA) bytes, the first row at texture coordinate v = 0 (OpenGL's
  order: the bottom of the picture).
- A mesh's ``Toj`` part (inside ``Gst``/``Geo``): ``Bst``/``Bs2`` (bit 0 interpolate, bit 1 in
  ``Bst`` only: decal, bit 2 repeat u, bit 3 repeat v), ``Tob``/``_ob`` (the texture's id, the
  mapping mode 0 plane, 1 cylinder, 2 sphere, 3 cube, then the x and y scaling as float32 or
  float64), ``Trc``/``_rc`` (the texture's pose in the mesh frame: quaternion w, x, y, z then
  position), ``Ftc`` (fixed texture coordinates, float32, two per triangle corner; empty when
  CoppeliaSim computes them from the mapping) and ``Apm`` (int32 apply mode: 0 modulate, 1
  decal, 2 add).
- In a ``.simscene.xml``, a ``<texture>`` element of a mesh holds the same mapping and the
  texture objects hold their image in base64 (``data_base64Coded``) or a file beside the scene.

Texture coordinates are computed here as CoppeliaSim computes them (per triangle corner, from
the vertices expressed in the texture's frame); :func:`texture_file` writes the image where
pybullet's renderers can load it. Reading is bounded by :mod:`sims.scene.limits`.
"""

from __future__ import annotations

import math

import numpy as np

from sims.scene.content_files import content_file
from sims.scene.limits import TextureBudget
from sims.scene.model import Pose, TextureImage, TextureMapping
from sims.scene.ttt_chunks import Chunk, ChunkError, Fields, bit, chunk_list

MODES = {0: "plane", 1: "cylinder", 2: "sphere", 3: "cube"}
APPLY = {0: "modulate", 1: "decal", 2: "add"}


def read_texture_object(buf: bytes, chunk: Chunk, budget: TextureBudget) -> TextureImage:
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    tid, width, height, name, rgba_given = -1, 0, 0, "", False
    img: Chunk | None = None
    for c in parts:
        f = Fields(buf, c)
        if c.name == "Ipa":
            tid, width, height = f.i32(), f.i32(), f.i32()
        elif c.name == "Gon":
            name = f.string()
        elif c.name == "Bst":
            rgba_given = bit(f.u8(), 0)
        elif c.name == "Img":
            img = c
    label = name or f"texture {tid}"
    if width <= 0 or height <= 0:
        raise ChunkError(f"{label}: size {width}x{height} is not an image")
    budget.take(label, width, height)
    channels = 4 if rgba_given else 3
    if img is None or img.end - img.start != width * height * channels:
        got = 0 if img is None else img.end - img.start
        raise ChunkError(
            f"{label}: {width}x{height} pixels of {channels} bytes need "
            f"{width * height * channels} bytes, the file holds {got}"
        )
    return TextureImage(tid, name, width, height, rgba_bytes(buf[img.start : img.end], channels))


def rgba_bytes(raw: bytes, channels: int) -> bytes:
    pixels = np.frombuffer(raw, dtype=np.uint8).reshape(-1, channels)
    if channels == 4:
        return pixels.tobytes()
    alpha = np.full((len(pixels), 1), 255, dtype=np.uint8)
    return np.hstack([pixels, alpha]).tobytes()


def read_texture_property(buf: bytes, chunk: Chunk) -> TextureMapping:
    parts, _ = chunk_list(buf, chunk.start, chunk.end)
    values: dict = {"texture": -1}
    for c in parts:
        f = Fields(buf, c)
        if c.name in ("Bst", "Bs2"):
            flags = f.u8()
            values["interpolate"] = bit(flags, 0)
            values["repeat_u"], values["repeat_v"] = bit(flags, 2), bit(flags, 3)
            if c.name == "Bst":
                values["apply"] = "decal" if bit(flags, 1) else "modulate"
        elif c.name in ("Tob", "_ob"):
            values["texture"] = f.i32()
            mode = f.i32()
            if mode not in MODES:
                raise ChunkError(f"texture mapping mode {mode} is not one CoppeliaSim has")
            values["mode"] = MODES[mode]
            values["scaling"] = tuple(f.real(2))
        elif c.name in ("Trc", "_rc"):
            w, x, y, z, px, py, pz = f.real(7)
            norm = math.sqrt(w * w + x * x + y * y + z * z) or 1.0
            values["pose"] = Pose((px, py, pz), (x / norm, y / norm, z / norm, w / norm))
        elif c.name == "Ftc":
            n = (c.end - c.start) // 4
            values["coordinates"] = tuple(float(v) for v in f.f32(n)) if n else ()
        elif c.name == "Apm":
            values["apply"] = APPLY.get(f.i32(), "modulate")
    return TextureMapping(**values)


def quaternion_matrix(q: tuple[float, float, float, float]) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def texture_coordinates(
    mapping: TextureMapping, vertices: np.ndarray, indices: np.ndarray
) -> np.ndarray | None:
    """(u, v) per triangle corner, shape (3T, 2), as CoppeliaSim computes them; None when the
    mesh's fixed coordinates do not match its triangles (CoppeliaSim then drops the texture)."""
    if mapping.coordinates:
        if len(mapping.coordinates) != 2 * len(indices):
            return None
        return np.asarray(mapping.coordinates, dtype=np.float64).reshape(-1, 2)
    rot = quaternion_matrix(mapping.pose.quaternion)
    corners = (vertices.reshape(-1, 3)[indices] - np.asarray(mapping.pose.position)) @ rot
    xs = ys = 1.0
    if mapping.image is not None:
        w, h = mapping.image.width, mapping.image.height
        xs, ys = (1.0, h / w) if w >= h else (w / h, 1.0)
    sx = (mapping.scaling[0] or 1.0) * xs
    sy = (mapping.scaling[1] or 1.0) * ys
    if mapping.mode == "plane":
        return np.stack([corners[:, 0] / sx + 0.5, corners[:, 1] / sy + 0.5], axis=1)
    if mapping.mode == "cube":
        tri = corners.reshape(-1, 3, 3)
        normal = np.abs(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]))
        # the largest normal component picks the plane: x -> (y, z), y -> (z, x), z -> (x, y)
        axis = np.where(
            normal[:, 0] >= normal[:, 1],
            np.where(normal[:, 0] >= normal[:, 2], 0, 2),
            np.where(normal[:, 1] >= normal[:, 2], 1, 2),
        )
        first = np.array([1, 2, 0])[axis]
        second = np.array([2, 0, 1])[axis]
        rows = np.arange(len(tri))[:, None]
        u = tri[rows, np.arange(3)[None, :], first[:, None]] / sx + 0.5
        v = tri[rows, np.arange(3)[None, :], second[:, None]] / sy + 0.5
        return np.stack([u.reshape(-1), v.reshape(-1)], axis=1)
    return _round(mapping.mode, corners, sy)


def _round(mode: str, corners: np.ndarray, sy: float) -> np.ndarray:
    """Cylinder and sphere mappings: u is the angle around z; the seam is mended per triangle."""
    out = np.empty((len(corners), 2))
    for t in range(0, len(corners), 3):
        tri = corners[t : t + 3]
        u = (np.arctan2(tri[:, 1], tri[:, 0]) / math.pi + 1.0) / 2.0
        if mode == "cylinder":
            v = tri[:, 2] / sy + 0.5
        else:
            length = np.linalg.norm(tri, axis=1)
            cos = np.divide(tri[:, 2], length, out=np.ones(3), where=length > 0)
            v = 1.0 - np.arccos(np.clip(cos, -1.0, 1.0)) / math.pi
        centre = (np.abs(tri[:, 0]) < 1e-5) & (np.abs(tri[:, 1]) < 1e-5)
        if centre.sum() == 2:
            u[centre] = u[~centre][0]
        elif centre.sum() == 1:
            a, b = u[~centre]
            u[centre] = (a + b + (1.0 if abs(a - b) > 0.5 else 0.0)) * 0.5
        u = np.where(u.max() - u > 0.5, u + 1.0, u)
        out[t : t + 3, 0], out[t : t + 3, 1] = u, v
    return out


def texture_file(image: TextureImage, pad_u: bool = False, pad_v: bool = False) -> str:
    """The image as a PNG in a cache folder, named by its content, for pybullet's loadTexture.
    The file's top row is the texture's last row (v = 1), as image files and OBJ's ``vt`` have
    it. ``pad_u``/``pad_v``: one copy of the edge texels added on both sides (a clamped
    texture, see ``sims.scene.shapes.textured_mesh``). Written once, atomically; the same
    texture gives the same bytes."""
    import cv2  # opencv-python-headless: a kept PNG encoder, already a dependency

    pixels = np.frombuffer(image.rgba, dtype=np.uint8).reshape(image.height, image.width, 4)
    pad = ((1, 1) if pad_v else (0, 0), (1, 1) if pad_u else (0, 0), (0, 0))
    pixels = np.pad(pixels, pad, mode="edge")
    bgr = np.ascontiguousarray(pixels[::-1, :, [2, 1, 0]])
    ok, encoded = cv2.imencode(".png", bgr)
    if not ok:
        raise ValueError(f"texture {image.name!r} could not be encoded")
    return content_file("sitegen-scene-textures", ".png", encoded.tobytes())


def attach_images(objects: list, images: dict[int, TextureImage]) -> list[str]:
    """Give every textured mesh its texture object (in place of the id); returns the names of
    shapes whose texture the file does not hold (their meshes are drawn without it)."""
    from dataclasses import replace

    missing: list[str] = []
    for i, o in enumerate(objects):
        if o.shape is None or not any(m.texture is not None for m in o.shape.meshes):
            continue
        meshes = []
        for m in o.shape.meshes:
            if m.texture is not None:
                image = images.get(m.texture.texture)
                if image is None:
                    missing.append(o.name)
                    m = replace(m, texture=None)
                else:
                    m = replace(m, texture=replace(m.texture, image=image))
            meshes.append(m)
        objects[i] = replace(o, shape=replace(o.shape, meshes=tuple(meshes)))
    return missing
