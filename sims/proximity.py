"""Proximity sensors of one World: rays cast into the scene in pybullet batches, results kept.

Kept apart from the stepping core in sims/world.py because scripts poll their sonars every pass
(bench/lua_bench.py), so this is the code a speed change touches. A sensor is a frame whose z is
its sensing axis and a tuple of (start, end) rays in that frame; a bundled scene's ray fan
(sims.models.common.RaySensor) is turned into that form here.

Two ways to decide when a sensor is cast (the World's ``sensors`` option), both giving the
readings a cast at that moment gives:

- ``"lazy"`` (default): a sensor is cast at its first read after the world last changed (a
  physics step, or something put somewhere between steps: ``forget()``), and that result is
  served to every later read until the world changes again. A read therefore always reports the
  world as it is at the read.
- ``"main-script"``: what CoppeliaSim's main script does. In the sensing phase of every pass
  (after the pass's last physics step, before the child scripts' sensing) it calls
  ``sim.handleProximitySensor(sim.handle_all_except_explicit)``: every sensor whose
  explicit-handling flag is off is cast, all in one batch, whether a script reads it or not. A
  read (``sim.readProximitySensor``, ``simxReadProximitySensor``) only returns the last handled
  result; a sensor never handled detects nothing; ``handle()`` casts one sensor now.

The two differ only when (1) a sensor is read before the first pass ends (lazy: the world at
time 0; main-script: nothing detected), (2) an object is moved between steps (a script's or
client's setObjectPosition, setJointPosition) and a sensor is read afterwards in the same pass
(lazy: after the move; main-script: as handled before it), (3) a sensor has its explicit-handling
flag on and no script handles it (lazy: read as any other; main-script: nothing detected), or
(4) a read happens between two passes' physics steps (lazy: that physics step; main-script: the
last pass end) — the script host and the remote API server only read at pass ends.

Speed (bench/lua_bench.py): the sensor's pose comes from one query of its link's frame per cast
(the same pybullet calls ``World.object_pose`` makes, so the same numbers), the rays of all the
sensors of a cast go into the world in one stacked matrix product and into pybullet in one
``rayTestBatch``; the numbers are bit-identical to casting each sensor alone
(tests/test_proximity_cache.py checks this over a run of the Pioneer scene).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from sims.models.common import ProxSensor, RaySensor, SceneModel
from sims.quiet import pybullet as p


class World(Protocol):
    """What the sensors read of ``sims.world.World`` (which creates them: a Protocol, so that
    this module does not import the world back)."""

    client_id: int
    steps: int
    timestep: float

    def link_frame(self, body: int, link: int) -> tuple: ...

    def object_name(self, handle: int | str) -> str: ...


#: (distance from the sensor origin, point and normal in the sensor frame, body, link)
Hit = tuple[float, tuple, tuple, int, int]
#: A bundled ray fan looks along its link's +x; its CoppeliaSim frame has z there (x_s = y_link,
#: y_s = z_link, z_s = x_link).
LEGACY_SENSOR_ORN = (0.5, 0.5, 0.5, 0.5)
MODES = ("lazy", "main-script")
#: pybullet refuses batches above 16384 rays; a cast of more is sent in pieces.
BATCH = 8192


@dataclass
class Cast:
    """One sensor cast: its origin and row-major rotation (world frame) at the cast and the raw
    pybullet hits of its rays; ``stamp`` says which state of the world it saw (lazy mode)."""

    origin: tuple
    rot: tuple
    hits: list
    stamp: tuple[int, int] = (-1, -1)
    best: Hit | None = None
    best_done: bool = False


class ProximitySensors:
    """The proximity sensors of one built scene, by name; rebuilt with the scene."""

    def __init__(self, world: World, model: SceneModel, mode: str = "lazy"):
        if mode not in MODES:
            raise ValueError(f"sensors={mode!r} not understood: use one of {', '.join(MODES)}")
        self.world = world
        self.mode = mode
        self.by_name: dict[str, ProxSensor] = {s.name: s for s in model.prox}
        for legacy in model.sensors:
            self.by_name[legacy.name] = _from_fan(legacy)
        #: sensors CoppeliaSim's main script leaves to the scripts (explicit handling)
        self.explicit = frozenset(n for n, s in self.by_name.items() if s.explicit)
        source = getattr(world, "source", None)
        dt = getattr(source, "time_step", 0.05) or 0.05
        #: physics steps per simulation pass (the scene's time step); a ScriptHost with its own
        #: pass length sets it
        self.pass_steps = max(1, round(dt / world.timestep))
        self.handled = 0  # passes handled in main-script mode
        self._ends: dict[str, np.ndarray] = {}  # a sensor's ray starts then ends (sensor frame)
        self._casts: dict[str, Cast] = {}
        self._generation = 0  # bumped by forget(): something moved between steps
        #: lazy mode: the world state of the latest read, the sensors read in it (in order) and
        #: those read in the state before
        self._stamp = (-1, -1)
        self._reads: dict[str, None] = {}
        self._previous: dict[str, None] = {}

    # -- reading ------------------------------------------------------------------------------
    def hits(self, name: str) -> list[Hit | None]:
        """Each ray of a sensor: None, or its hit in the sensor frame."""
        cast = self._reading(name)
        if cast is None:
            return [None] * len(self.by_name[self.world.object_name(name)].rays)
        return [None if h[0] < 0 else _hit_in_frame(h, cast.origin, cast.rot) for h in cast.hits]

    def nearest(self, name: str) -> Hit | None:
        """The nearest of ``hits`` (the first of equals), what a proximity sensor reports,
        without bringing every other ray's hit into the sensor frame."""
        cast = self._reading(name)
        if cast is None:
            return None
        if not cast.best_done:
            cast.best, cast.best_done = _nearest(cast), True
        return cast.best

    def handle(self, name: str) -> Hit | None:
        """Cast one sensor now (``sim.handleProximitySensor(handle)``): its nearest hit."""
        name = self.world.object_name(name)
        self._cast([name])
        return self.nearest(name)

    def handle_all(self, except_explicit: bool) -> list[str]:
        """Cast every sensor (but those with explicit handling when ``except_explicit``), in
        one batch; returns their names."""
        names = [n for n in self.by_name if not (except_explicit and n in self.explicit)]
        for cast in self._cast(names):  # the detection is part of handling, as in CoppeliaSim
            cast.best, cast.best_done = _nearest(cast), True
        return names

    def stepped(self) -> None:
        """Called by the World after every physics step: the main script's sensing at the end
        of a pass, in main-script mode."""
        if self.mode == "main-script" and self.world.steps % self.pass_steps == 0:
            self.handle_all(except_explicit=True)
            self.handled += 1

    def forget(self) -> None:
        """Something was put somewhere between steps: lazy readings are cast again. (Handled
        results stay, as in CoppeliaSim: a read returns what the last handling saw.)"""
        self._generation += 1

    def _reading(self, name: str) -> Cast | None:
        name = self.world.object_name(name)
        cast = self._casts.get(name)
        if self.mode == "main-script":
            return cast
        stamp = (self.world.steps, self._generation)
        if stamp != self._stamp:  # the world changed: this state's reads start afresh
            self._stamp, self._previous, self._reads = stamp, self._reads, {}
        self._reads[name] = None
        if cast is None or cast.stamp != stamp:
            # The sensors read in the previous state are likely read again in this one: cast
            # them with this one, in one batch (nothing moves until the next change, so each
            # reads what its own cast at its read would give).
            batch = [name]
            if name in self._previous:
                batch += [n for n in self._previous if n != name and self._stale(n, stamp)]
            cast = self._cast(batch)[0]
        return cast

    def _stale(self, name: str, stamp: tuple[int, int]) -> bool:
        cast = self._casts.get(name)
        return cast is None or cast.stamp != stamp

    # -- casting ------------------------------------------------------------------------------
    def _cast(self, names: list[str]) -> list[Cast]:
        """Cast the rays of ``names`` in one pybullet batch; store and return the casts.

        The rays go into the world with one stacked matrix product per ray count rather than two
        pybullet transforms per ray (also more exact: pybullet's multiplyTransforms returns
        single-precision results); the sensor poses are those ``World.object_pose`` gives.
        """
        if not names:
            return []
        w = self.world
        stamp = (w.steps, self._generation)
        frames: dict[tuple[int, int], tuple] = {}
        poses = []
        groups: dict[int, list[int]] = {}  # ray count -> indices into names
        for i, name in enumerate(names):
            s = self.by_name[name]
            key = (s.body, s.link)
            frame = frames.get(key)
            if frame is None:
                frame = frames[key] = w.link_frame(s.body, s.link)
            pos, orn = p.multiplyTransforms(frame[0], frame[1], s.offset_pos, s.offset_orn)
            poses.append((tuple(pos), p.getMatrixFromQuaternion(orn)))  # rotation: row-major
            groups.setdefault(len(s.rays), []).append(i)
        if len(names) == 1:  # a single read: the plain product (the same numbers)
            ends = self._ray_ends(names[0])
            m = np.array(poses[0][1], float).reshape(3, 3).T
            points = (ends @ m + np.array(poses[0][0], float)).tolist()
            half = len(points) // 2
            frm, to, order = points[:half], points[half:], [0]
        else:
            starts, tips, order = [], [], []
            for count, members in groups.items():
                ends = np.stack([self._ray_ends(names[i]) for i in members])
                rot = np.array([poses[i][1] for i in members], float).reshape(-1, 3, 3)
                origin = np.array([poses[i][0] for i in members], float)[:, None, :]
                points = ends @ rot.transpose(0, 2, 1) + origin  # (sensor, starts + tips, xyz)
                starts.append(points[:, :count].reshape(-1, 3))
                tips.append(points[:, count:].reshape(-1, 3))
                order += members
            frm = np.concatenate(starts).tolist()
            to = np.concatenate(tips).tolist()
        raw: list = []
        for at in range(0, len(frm), BATCH):
            raw += p.rayTestBatch(
                frm[at : at + BATCH], to[at : at + BATCH], physicsClientId=w.client_id
            )
        out: list[Cast] = [None] * len(names)  # type: ignore[list-item]
        at = 0
        for i in order:  # the batch holds the sensors in group order
            origin, rot = poses[i]
            count = len(self.by_name[names[i]].rays)
            out[i] = self._casts[names[i]] = Cast(origin, rot, raw[at : at + count], stamp)
            at += count
        return out

    def _ray_ends(self, name: str) -> np.ndarray:
        ends = self._ends.get(name)
        if ends is None:
            rays = self.by_name[name].rays
            ends = self._ends[name] = np.array([a for a, _ in rays] + [b for _, b in rays], float)
        return ends


def _nearest(cast: Cast) -> Hit | None:
    ox, oy, oz = cast.origin
    best = None
    best_d2 = math.inf
    for h in cast.hits:
        if h[0] < 0:
            continue
        x, y, z = h[3]
        d2 = (x - ox) * (x - ox) + (y - oy) * (y - oy) + (z - oz) * (z - oz)
        if d2 < best_d2:
            best, best_d2 = h, d2
    return None if best is None else _hit_in_frame(best, cast.origin, cast.rot)


def _hit_in_frame(h: Any, origin: tuple, rot: tuple) -> Hit:
    """A pybullet ray hit as (distance from the sensor origin, point and normal in the sensor
    frame, body, link); ``rot`` is the sensor's row-major rotation (its transpose maps back)."""
    r0, r1, r2, r3, r4, r5, r6, r7, r8 = rot
    dx, dy, dz = h[3][0] - origin[0], h[3][1] - origin[1], h[3][2] - origin[2]
    nx, ny, nz = h[4]
    point = (r0 * dx + r3 * dy + r6 * dz, r1 * dx + r4 * dy + r7 * dz, r2 * dx + r5 * dy + r8 * dz)
    normal = (r0 * nx + r3 * ny + r6 * nz, r1 * nx + r4 * ny + r7 * nz, r2 * nx + r5 * ny + r8 * nz)
    return math.sqrt(dx * dx + dy * dy + dz * dz), point, normal, h[0], h[1]


def _from_fan(s: RaySensor) -> ProxSensor:
    """A bundled ray fan as a sensor frame with z along the link's +x, rays in that frame."""
    rays = []
    for d in s.rays():  # link frame (x forward) -> sensor frame (z forward)
        tip = (d[1] * s.max_range, d[2] * s.max_range, d[0] * s.max_range)
        rays.append(((0.0, 0.0, 0.0), tip))
    return ProxSensor(s.name, s.body, s.link, s.origin, LEGACY_SENSOR_ORN, tuple(rays))
