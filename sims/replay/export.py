"""A run of a World becomes a replay: link frames sampled while it runs, then one ``.glb``.

:class:`ReplayTape` is handed every data sample of a recording (``Recorder(on_sample=)``,
``fps`` per simulated second, plus the state at the clip's end time, so the animation lasts as
long as the run). At its first sample it takes the World's looks (sims/replay/geometry.py)
and from then on stores, per sample, the world frame of every link that has shapes or carries
the followed object. :meth:`ReplayTape.glb` turns that into nodes: a link that moves (beyond
the tolerances of sims/replay/keyframes.py) or carries a named object gets its own node and,
when it moves, animation channels; every other link's shapes are merged, by colour, into one
static node ``scene`` (the floor, walls, obstacles: one draw call per colour).

:func:`scene_glb` exports a scene without a run (``sitegen scene export``).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from sims.replay import keyframes as K
from sims.replay.geometry import LinkKey, Surface, placed, world_looks
from sims.replay.gltf import Camera, Node, Trail, build_glb

PITCH = -40.0  # the starting view looks down at 40°
FOV_DEG = 50.0  # as the clips' renderer (sims/render.py)
TRAIL_Z = 0.002  # just above the floor (as sims/camera.py draws it)


class ReplayError(RuntimeError):
    """The World's links changed during the run (a body added or removed)."""


def _identity(pos: tuple, orn: tuple) -> bool:
    return max(abs(v) for v in pos) < 1e-9 and abs(abs(orn[3]) - 1.0) < 1e-9


class ReplayTape:
    """Link frames of a running World, one row per sample (see the module docstring)."""

    def __init__(self, follow: str | None = None):
        self.follow = follow
        self.keys: list[LinkKey] = []
        self.looks: dict[LinkKey, list[Surface]] = {}
        self.named: dict[LinkKey, list[tuple[str, tuple, tuple]]] = {}
        self.rows: list[np.ndarray] = []
        self.path: list[tuple[float, float, float]] = []
        self.camera_yaw = 35.0
        self.follow_key: LinkKey | None = None
        self._started = False

    def _start(self, world: Any) -> None:
        self.follow = self.follow or world.model.robot
        self.looks = world_looks(world)
        for obj in world.model.objects:
            if obj.body >= 0:
                self.named.setdefault((obj.body, obj.link), []).append(
                    (obj.name, tuple(obj.offset_pos), tuple(obj.offset_orn))
                )
        ref = next((o for o in world.model.objects if o.name == self.follow), None)
        self.follow_key = (ref.body, ref.link) if ref is not None else None
        keys = set(self.looks)
        if self.follow_key is not None and self.follow_key[0] >= 0:
            keys.add(self.follow_key)
        self.keys = sorted(keys)
        self.camera_yaw = float(world.model.camera.yaw)

    def sample(self, world: Any) -> None:
        """Store the frame of every tracked link now (called once per data sample)."""
        if not self._started:
            self._start(world)
            self._started = True
        row = np.empty((len(self.keys), 7), dtype=np.float64)
        try:
            for k, (body, link) in enumerate(self.keys):
                pos, orn = world.link_frame(body, link)
                row[k, :3], row[k, 3:] = pos, orn
        except Exception as exc:  # pybullet says "getLinkState failed" for a lost body
            raise ReplayError(f"the scene's bodies changed at sample {len(self.rows)}") from exc
        self.rows.append(row)
        self.path.append(tuple(world.object_pose(self.follow)[0]))

    # -- writing -------------------------------------------------------------------------------
    def glb(
        self,
        fps: float,
        speed: float = 1.0,
        aspect: float = 4 / 3,
        trail: bool = False,
        extra: dict[str, Any] | None = None,
    ) -> bytes:
        """The replay's bytes: sample ``k`` is at ``k / fps`` simulated seconds."""
        if not self.rows:
            raise ReplayError("no samples were recorded")
        frames = np.stack(self.rows)  # S × K × 7
        times = np.arange(len(frames), dtype=np.float64) / fps
        duration = (len(frames) - 1) / fps
        nodes, static = [], []
        names: dict[str, int] = {}
        for k, key in enumerate(self.keys):
            pos = frames[:, k, :3]
            quat = K.continuous(frames[:, k, 3:])
            still_pos = K.is_still(pos, K.POSITION_TOLERANCE)
            still_rot = K.is_still(quat, K.ROTATION_TOLERANCE, rotation=True)
            named = self.named.get(key, [])
            clock = key == self.follow_key  # keeps the animation as long as the run
            if still_pos and still_rot and not named and not clock:
                static += [_moved(s, pos[0], quat[0]) for s in self.looks.get(key, [])]
                continue
            name, kids = _node_names(key, named, names)
            node = Node(name, self.looks.get(key, []), _t(pos[0]), _t(quat[0]), kids, link=key)
            if not still_pos or clock:
                idx = K.reduce_track(pos, K.POSITION_TOLERANCE)
                node.translation_keys = (times[idx], pos[idx])
            if not still_rot:
                idx = K.reduce_track(quat, K.ROTATION_TOLERANCE, rotation=True)
                node.rotation_keys = (times[idx], quat[idx])
            nodes.append(node)
        if static:
            nodes.insert(0, Node("scene", _by_colour(static), (0.0, 0.0, 0.0), (0, 0, 0, 1.0)))
        path = np.asarray(self.path, dtype=np.float64)
        info = {
            "duration": round(duration, 6),
            "fps": fps,
            "speed": speed,
            "follow": self.follow,
            "samples": len(frames),
            "tolerance": {
                "position_m": K.POSITION_TOLERANCE,
                "rotation_deg": round(math.degrees(K.ROTATION_TOLERANCE), 6),
            },
            **(extra or {}),
        }
        track = None
        if trail:
            idx = K.reduce_track(path, K.POSITION_TOLERANCE)
            points = path[idx].copy()
            points[:, 2] = TRAIL_Z
            track = Trail(points, times[idx])
        cam = self.camera(aspect)
        return build_glb(nodes, cam, info, duration if len(frames) > 1 else None, track)

    def camera(self, aspect: float) -> Camera:
        """The replay's starting view (:func:`start_camera` on the followed object's path)."""
        return start_camera(np.asarray(self.path, dtype=np.float64), self.camera_yaw, aspect)

    def write(self, path: str | Path, **kwargs: Any) -> None:
        Path(path).write_bytes(self.glb(**kwargs))


def _t(values: Any) -> tuple:
    return tuple(float(v) for v in values)


def _node_names(key: LinkKey, named: list, taken: dict[str, int]) -> tuple[str, list]:
    """The link node's name (the object whose frame it is, else ``<first object>-link``,
    else ``link-<body>.<link>``) and the named objects left as its children."""
    own = next((n for n in named if _identity(n[1], n[2])), None)
    kids = [n for n in named if n is not own]
    name = own[0] if own else (f"{named[0][0]}-link" if named else f"link-{key[0]}.{key[1]}")
    if name in taken:
        taken[name] += 1
        name = f"{name}#{taken[name]}"
    else:
        taken[name] = 0
    return name, kids


def _moved(surface: Surface, pos: np.ndarray, quat: np.ndarray) -> Surface:
    pts, normals, faces = placed(
        (surface.positions.astype(np.float64), surface.normals.astype(np.float64), surface.indices),
        tuple(pos),
        tuple(quat),
    )
    return Surface(surface.rgba, pts.astype(np.float32), normals.astype(np.float32), faces)


def _by_colour(surfaces: list[Surface]) -> list[Surface]:
    groups: dict[tuple, list[Surface]] = {}
    for s in surfaces:
        groups.setdefault(s.rgba, []).append(s)
    out = []
    for rgba, group in groups.items():
        offset, faces = 0, []
        for s in group:
            faces.append(s.indices + offset)
            offset += len(s.positions)
        out.append(
            Surface(
                rgba,
                np.concatenate([s.positions for s in group]),
                np.concatenate([s.normals for s in group]),
                np.concatenate(faces).astype(np.uint32),
            )
        )
    return out


def start_camera(path: np.ndarray, yaw: float, aspect: float) -> Camera:
    """The replay's starting view: the fixed overview framing the followed object's whole
    path (sims/camera.py), looking down at ``PITCH``."""
    from sims.camera import matrices, overview_for

    ov = overview_for(path, yaw, FOV_DEG, aspect, pitch=PITCH, margin=0.15, min_radius=0.25)
    view, _proj = matrices(ov, FOV_DEG, aspect)
    inverse = np.linalg.inv(np.asarray(view, dtype=np.float64).reshape(4, 4).T)
    eye = tuple(float(v) for v in inverse[:3, 3])
    return Camera(eye, tuple(float(v) for v in ov.target), FOV_DEG, aspect)


def scene_glb(scene: Any, seed: int = 0, aspect: float = 4 / 3, **options: Any) -> bytes:
    """A scene without a run: its shapes at their saved pose, no animation."""
    from sims.world import World

    with World(scene, seed=seed, **options) as world:
        tape = ReplayTape()
        tape.sample(world)
        return tape.glb(fps=1.0, aspect=aspect, extra={"scene_only": True})
