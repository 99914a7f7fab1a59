"""Path objects of a World (CoppeliaSim 3.x / 4.0-4.2 paths): the curve through their control
points and a position along it that moves the dummies following the path (``world.paths``).

The curve is CoppeliaSim's (read off coppeliaSimLib's ``pathCont_old.cpp``): each control
point with a Bézier point count above 1 rounds its corner by a quadratic Bézier between the
points a fraction (its Bézier factors) of the way to its neighbours; elsewhere the curve is
straight; between two of these points position is interpolated linearly and orientation by
slerp. A segment's length is its distance (or its angle times a factor, as the path's length
method says); a closed path wraps. Written here because it must match CoppeliaSim's own curve
exactly (a conveyor's pads are spaced by it), not any spline library's.

``set_position`` places every direct child dummy that follows the path (3.x dummies'
"follow parent path" flag) at the path's position plus its own offset, as CoppeliaSim does
when a script calls sim.setPathPosition (the conveyor belt's pads); ``main_script_pass``
advances paths that have a nominal velocity, as the 3.x main script's sim.handlePath did.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from sims.scene.model import PathData, Scene

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]


def _slerp(a: np.ndarray, b: np.ndarray, t: float) -> np.ndarray:
    dot = float(a @ b)
    if dot < 0:
        b, dot = -b, -dot
    if dot > 0.9995:
        q = a + (b - a) * t
        return q / np.linalg.norm(q)
    theta = math.acos(dot)
    return (math.sin((1 - t) * theta) * a + math.sin(t * theta) * b) / math.sin(theta)


def _mix(a: tuple[np.ndarray, np.ndarray], b: tuple[np.ndarray, np.ndarray], t: float):
    return a[0] + (b[0] - a[0]) * t, _slerp(a[1], b[1], t)


def _angle(a: np.ndarray, b: np.ndarray) -> float:
    return 2 * math.acos(min(1.0, abs(float(a @ b))))


@dataclass
class Curve:
    """The Bézier points of a path (position, quaternion x y z w, in the path's frame) and
    their cumulative lengths."""

    points: list[tuple[np.ndarray, np.ndarray]]
    closed: bool
    cumulative: np.ndarray = field(default_factory=lambda: np.zeros(0))

    @classmethod
    def of(cls, data: PathData) -> Curve:
        ctrl = [(np.array(pt.position), np.array(pt.quaternion)) for pt in data.points]
        out: list[tuple[np.ndarray, np.ndarray]] = []
        n = len(ctrl)
        if n <= 2:
            out = list(ctrl)
        for i in range(n if n > 2 else 0):
            before = ctrl[i - 1] if i > 0 else (ctrl[-1] if data.closed else None)
            after = ctrl[i + 1] if i < n - 1 else (ctrl[0] if data.closed else None)
            here, spec = ctrl[i], data.points[i]
            if before is None or after is None or spec.bezier_points == 1:
                out.append(here)
                continue
            da, db = here[0] - before[0], after[0] - here[0]
            lin = (
                np.linalg.norm(da) > 0
                and np.linalg.norm(db) > 0
                and float(da @ db) / (np.linalg.norm(da) * np.linalg.norm(db)) < 0.99999
            )
            ang = _angle(before[1], here[1]) > math.radians(1) and _angle(
                here[1], after[1]
            ) > math.radians(1)
            if not (lin or ang):
                out.append(here)
                continue
            m, k = _mix(before, here, 0.5), _mix(here, after, 0.5)
            first = _mix(m, here, 1 - spec.bezier[0])
            last = _mix(k, here, 1 - spec.bezier[1])
            out.append(first)
            count = spec.bezier_points - 1
            for step in range(1, count):
                t = step / count
                out.append(_mix(_mix(first, here, t), _mix(here, last, t), t))
            out.append(last)
        curve = cls(out, data.closed)
        curve.cumulative = curve._lengths(data)
        return curve

    def _lengths(self, data: PathData) -> np.ndarray:
        """Cumulative length at each Bézier point (a closed path's last entry is the length
        back to the first point)."""
        pts = self.points
        n = len(pts)
        out = np.zeros(n + 1)
        for i in range(n):
            a, b = pts[i], pts[(i + 1) % n]
            dl = float(np.linalg.norm(b[0] - a[0]))
            da = _angle(a[1], b[1]) * data.angle_to_distance
            method = data.length_method
            v = {1: da, 2: max(dl, da), 3: dl + da, 4: math.hypot(dl, da)}.get(method, dl)
            if method == 5:
                v = dl if dl >= 0.00005 else da
            elif method == 6:
                v = da if da >= math.radians(0.01) else dl
            out[i + 1] = out[i] + v
        return out if self.closed else out[:n]

    @property
    def length(self) -> float:
        return float(self.cumulative[-1]) if len(self.cumulative) else 0.0

    def pose_at(self, s: float) -> Pose:
        """Position and quaternion at length ``s`` along the path (in the path's frame)."""
        pts = self.points
        if not pts:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
        total = self.length
        if len(pts) == 1 or total <= 0:
            pos, quat = pts[0]
        else:
            s = s % total if self.closed else min(max(s, 0.0), total)
            i = int(np.searchsorted(self.cumulative, s, side="right")) - 1
            i = min(max(i, 0), len(self.cumulative) - 2)
            seg = self.cumulative[i + 1] - self.cumulative[i]
            t = (s - self.cumulative[i]) / seg if seg > 0 else 0.0
            pos, quat = _mix(pts[i], pts[(i + 1) % len(pts)], t)
        return tuple(pos.tolist()), tuple(quat.tolist())  # type: ignore[return-value]


@dataclass
class PathState:
    name: str
    curve: Curve
    position: float
    velocity: float
    target_velocity: float
    acceleration: float
    followers: list[tuple[str, float]]  # dummies on the path: (name, offset along it)


class PathObjects:
    """The path objects of one World (``world.paths``), by World handle."""

    def __init__(self, world: Any, scene: Scene | Any):
        self.world = world
        self.paths: dict[int, PathState] = {}
        objects = getattr(scene, "objects", ())
        kids: dict[int | None, list[Any]] = {}
        for o in objects:
            kids.setdefault(o.parent, []).append(o)
        for o in objects:
            data = getattr(o, "path", None)
            handle = world.handle(o.name)
            if data is None or handle is None:
                continue
            followers = [
                (k.name, k.dummy.path_offset)
                for k in kids.get(o.handle, [])
                if k.dummy is not None and k.dummy.follows_path and not k.dummy.free_on_path
            ]
            self.paths[handle] = PathState(
                o.name,
                Curve.of(data),
                data.position,
                data.nominal_velocity,
                data.target_velocity,
                data.max_acceleration,
                followers,
            )

    def _state(self, handle: int | str) -> PathState:
        h = self.world.handle_of(handle)
        if h not in self.paths:
            raise KeyError(f"{self.world.object_name(h)!r} is not a path")
        return self.paths[h]

    def length(self, handle: int | str) -> float:
        return self._state(handle).curve.length

    def position(self, handle: int | str) -> float:
        """sim.getPathPosition: the path's position along itself (m)."""
        return self._state(handle).position

    def set_position(self, handle: int | str, s: float) -> None:
        """sim.setPathPosition: the position (wrapped on a closed path, else clamped); the
        dummies that follow the path are put there."""
        state = self._state(handle)
        total = state.curve.length
        if state.curve.closed and total > 0:
            s = s % total
        else:
            s = min(max(s, 0.0), total)
        state.position = s
        for name, offset in state.followers:
            self.world.place_on_path(name, state.name, state.curve.pose_at(s + offset))

    def set_target_velocity(self, handle: int | str, v: float) -> None:
        """sim.setPathTargetNominalVelocity."""
        self._state(handle).target_velocity = v

    def pose_at(self, handle: int | str, s: float) -> Pose:
        """The world pose of the point at length ``s`` along the path."""
        from sims.quiet import pybullet as p

        state = self._state(handle)
        frame = self.world.object_pose(state.name)
        local = state.curve.pose_at(s)
        pos, orn = p.multiplyTransforms(*frame, *local)
        return tuple(pos), tuple(orn)  # type: ignore[return-value]

    def main_script_pass(self, dt: float) -> None:
        """Paths with a (target) nominal velocity advance by it, within their acceleration."""
        for handle, state in self.paths.items():
            v, target = state.velocity, state.target_velocity
            if state.acceleration > 0:
                dv = state.acceleration * dt
                v = min(max(target, v - dv), v + dv)
            else:
                v = target
            state.velocity = v
            if v != 0.0:
                self.set_position(handle, state.position + v * dt)
