"""Write a replay as glTF 2.0 binary (``.glb``) with pygltflib.

Layout of the file (what the page's viewer and the tests rely on):

- one scene whose single root node ``replay`` turns the simulation's z-up frame into glTF's
  y-up one (a rotation of -90° about x); everything else hangs below it, in metres, z up;
- one node per link (:class:`Node`): its meshes (one primitive per colour), its pose at the
  first sample, and children without meshes for the named objects it carries (their fixed
  offset), so ``getObjectByName`` finds any named object of the scene;
- an animation ``run`` whose channels move the nodes that move (translation and rotation,
  LINEAR), sampled at the kept keyframes (sims/replay/keyframes.py); rotations are stored as
  normalized 16-bit integers (allowed for animation outputs by core glTF 2.0);
- a perspective camera node ``camera`` (the replay's starting view; ``extras.target`` is the
  point it looks at, for orbit controls) and, for a clip with a trail, a LINE_STRIP mesh
  ``trail`` whose ``_TIME`` attribute (an application attribute) gives each point's time;
- ``extras.sitegen`` on the root: duration, fps, speed, the followed object, tolerances.

Every number is written from numpy arrays of fixed types in a fixed order and pygltflib
writes JSON with sorted-free, insertion-ordered keys, so identical inputs give identical bytes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pygltflib as G

from sims.replay.geometry import Surface

ROOT_ROTATION = [-math.sqrt(0.5), 0.0, 0.0, math.sqrt(0.5)]  # z up -> y up
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963
TRAIL_RGBA = (1.0, 0.376, 0.0, 1.0)


@dataclass
class Node:
    """One link: shapes in its frame, its pose per kept keyframe (None: it does not move)."""

    name: str
    surfaces: list[Surface]
    position: tuple[float, float, float]
    rotation: tuple[float, float, float, float]
    children: list[tuple[str, tuple, tuple]] = field(default_factory=list)  # (name, pos, quat)
    translation_keys: tuple[np.ndarray, np.ndarray] | None = None  # (times, N×3)
    rotation_keys: tuple[np.ndarray, np.ndarray] | None = None  # (times, N×4 xyzw)
    link: tuple[int, int] | None = None  # (pybullet body, link): ``extras.link``, for tools


@dataclass
class Camera:
    """The starting view: eye and target (world, z up), vertical field of view, aspect."""

    eye: tuple[float, float, float]
    target: tuple[float, float, float]
    yfov_deg: float
    aspect: float


@dataclass
class Trail:
    """The followed object's path: points (N×3) and the time of each (N)."""

    points: np.ndarray
    times: np.ndarray


def srgb_to_linear(c: float) -> float:
    """glTF colours are linear; scene colours are display (sRGB) values."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


class _Builder:
    def __init__(self) -> None:
        self.blob = bytearray()
        self.gltf = G.GLTF2(asset=G.Asset(generator="sitegen replay", version="2.0"))
        self.materials: dict[tuple, int] = {}
        self.inputs: dict[bytes, int] = {}

    def view(self, data: bytes, target: int | None = None) -> int:
        while len(self.blob) % 4:
            self.blob.append(0)
        self.gltf.bufferViews.append(
            G.BufferView(buffer=0, byteOffset=len(self.blob), byteLength=len(data), target=target)
        )
        self.blob += data
        return len(self.gltf.bufferViews) - 1

    def accessor(
        self,
        array: np.ndarray,
        kind: str,
        target: int | None = None,
        bounds: bool = False,
        normalized: bool = False,
    ) -> int:
        types = {np.float32: G.FLOAT, np.uint32: G.UNSIGNED_INT, np.uint16: G.UNSIGNED_SHORT}
        types[np.int16] = G.SHORT
        component = types[array.dtype.type]
        acc = G.Accessor(
            bufferView=self.view(np.ascontiguousarray(array).tobytes(), target),
            componentType=component,
            count=int(array.shape[0]),
            type=kind,
            normalized=True if normalized else None,
        )
        if bounds:
            flat = array.reshape(array.shape[0], -1)
            acc.min = [float(v) for v in flat.min(axis=0)]
            acc.max = [float(v) for v in flat.max(axis=0)]
        self.gltf.accessors.append(acc)
        return len(self.gltf.accessors) - 1

    def times(self, times: np.ndarray) -> int:
        """An animation input accessor, shared by samplers with the same key times."""
        data = np.asarray(times, dtype=np.float32)
        key = data.tobytes()
        if key not in self.inputs:
            self.inputs[key] = self.accessor(data, G.SCALAR, bounds=True)
        return self.inputs[key]

    def material(self, rgba: tuple) -> int:
        if rgba not in self.materials:
            factor = [*(round(srgb_to_linear(c), 6) for c in rgba[:3]), float(rgba[3])]
            self.gltf.materials.append(
                G.Material(
                    pbrMetallicRoughness=G.PbrMetallicRoughness(
                        baseColorFactor=factor, metallicFactor=0.0, roughnessFactor=0.85
                    ),
                    doubleSided=True,
                )
            )
            self.materials[rgba] = len(self.gltf.materials) - 1
        return self.materials[rgba]

    def mesh(self, name: str, surfaces: list[Surface]) -> int | None:
        prims = []
        for s in surfaces:
            index_type = np.uint16 if len(s.positions) < 65536 else np.uint32
            prims.append(
                G.Primitive(
                    attributes=G.Attributes(
                        POSITION=self.accessor(s.positions, G.VEC3, ARRAY_BUFFER, bounds=True),
                        NORMAL=self.accessor(s.normals, G.VEC3, ARRAY_BUFFER),
                    ),
                    indices=self.accessor(
                        s.indices.astype(index_type), G.SCALAR, ELEMENT_ARRAY_BUFFER
                    ),
                    material=self.material(s.rgba),
                    mode=G.TRIANGLES,
                )
            )
        if not prims:
            return None
        self.gltf.meshes.append(G.Mesh(name=name, primitives=prims))
        return len(self.gltf.meshes) - 1

    def add_node(self, node: G.Node) -> int:
        self.gltf.nodes.append(node)
        return len(self.gltf.nodes) - 1


def _f(values: Any) -> list[float]:
    return [float(v) for v in values]


def quantized_rotations(quats: np.ndarray) -> np.ndarray:
    """Unit quaternions as normalized signed 16-bit integers (glTF: c / 32767)."""
    return np.round(np.clip(quats, -1.0, 1.0) * 32767.0).astype(np.int16)


def look_at(eye: tuple, target: tuple) -> list[float]:
    """A glTF camera's rotation (x y z w) looking from ``eye`` at ``target``, z up."""
    forward = np.asarray(target, dtype=np.float64) - np.asarray(eye, dtype=np.float64)
    forward /= np.linalg.norm(forward) or 1.0
    right = np.cross(forward, (0.0, 0.0, 1.0))
    if np.linalg.norm(right) < 1e-9:
        right = np.array([1.0, 0.0, 0.0])
    right /= np.linalg.norm(right)
    up = np.cross(right, forward)
    m = np.stack([right, up, -forward], axis=1)  # camera x, y, z axes in world coordinates
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    if w > 1e-6:
        q = [(m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w)]
        q += [(m[1, 0] - m[0, 1]) / (4 * w), w]
    else:  # a half turn: take the largest diagonal term
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = math.sqrt(max(0.0, 1 + m[i, i] - m[j, j] - m[k, k])) * 2
        q = [0.0, 0.0, 0.0, (m[k, j] - m[j, k]) / s]
        q[i], q[j], q[k] = s / 4, (m[j, i] + m[i, j]) / s, (m[k, i] + m[i, k]) / s
    return _f(np.asarray(q) / np.linalg.norm(q))


def build_glb(
    nodes: list[Node],
    camera: Camera,
    info: dict[str, Any],
    duration: float | None,
    trail: Trail | None = None,
) -> bytes:
    """The replay as .glb bytes. ``duration``: the animation's end time (None: no animation)."""
    b = _Builder()
    children: list[int] = []
    channels: list[G.AnimationChannel] = []
    samplers: list[G.AnimationSampler] = []
    for node in nodes:
        kids = [
            b.add_node(G.Node(name=name, translation=_f(pos), rotation=_f(quat)))
            for name, pos, quat in node.children
        ]
        index = b.add_node(
            G.Node(
                name=node.name,
                mesh=b.mesh(node.name, node.surfaces),
                translation=_f(node.position),
                rotation=_f(node.rotation),
                children=kids,
                extras={"link": list(node.link)} if node.link is not None else None,
            )
        )
        children.append(index)
        for path, keys in (
            ("translation", node.translation_keys),
            ("rotation", node.rotation_keys),
        ):
            if keys is None:
                continue
            times, values = keys
            if path == "rotation":
                output = b.accessor(quantized_rotations(values), G.VEC4, normalized=True)
            else:
                output = b.accessor(np.asarray(values, dtype=np.float32), G.VEC3)
            samplers.append(G.AnimationSampler(input=b.times(times), output=output))
            channels.append(
                G.AnimationChannel(
                    sampler=len(samplers) - 1,
                    target=G.AnimationChannelTarget(node=index, path=path),
                )
            )
    if trail is not None and len(trail.points) >= 2:
        pts = np.asarray(trail.points, dtype=np.float32)
        prim = G.Primitive(
            attributes=G.Attributes(
                POSITION=b.accessor(pts, G.VEC3, ARRAY_BUFFER, bounds=True),
                _TIME=b.accessor(np.asarray(trail.times, dtype=np.float32), G.SCALAR, ARRAY_BUFFER),
            ),
            material=b.material(TRAIL_RGBA),
            mode=G.LINE_STRIP,
        )
        b.gltf.meshes.append(G.Mesh(name="trail", primitives=[prim]))
        children.append(b.add_node(G.Node(name="trail", mesh=len(b.gltf.meshes) - 1)))
    b.gltf.cameras.append(
        G.Camera(
            type="perspective",
            perspective=G.Perspective(
                yfov=math.radians(camera.yfov_deg),
                znear=0.01,
                zfar=100.0,
                aspectRatio=camera.aspect,
            ),
        )
    )
    children.append(
        b.add_node(
            G.Node(
                name="camera",
                camera=0,
                translation=_f(camera.eye),
                rotation=look_at(camera.eye, camera.target),
                extras={"target": _f(camera.target)},
            )
        )
    )
    root = b.add_node(
        G.Node(name="replay", rotation=ROOT_ROTATION, children=children, extras={"sitegen": info})
    )
    b.gltf.scenes.append(G.Scene(name="sitegen-replay", nodes=[root]))
    b.gltf.scene = 0
    if channels and duration is not None:
        b.gltf.animations.append(G.Animation(name="run", channels=channels, samplers=samplers))
    while len(b.blob) % 4:
        b.blob.append(0)
    b.gltf.buffers.append(G.Buffer(byteLength=len(b.blob)))
    b.gltf.set_binary_blob(bytes(b.blob))
    return b"".join(b.gltf.save_to_bytes())
