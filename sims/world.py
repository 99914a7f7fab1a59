"""One headless pybullet world holding one course scene, addressed CoppeliaSim-style by name.

Contract used by the scenarios, the clip renderer and the remote API (see docs/DESIGN.md):
everything goes through names and stable integer handles, never raw pybullet ids, and every
pybullet call passes ``physicsClientId`` so several Worlds in one process stay independent.
Joint angles are reported and commanded in CoppeliaSim's convention for that joint (the model's
``JointRef`` holds the mapping). ``reset()`` rebuilds the scene like CoppeliaSim's stop/start.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from sims.models import build_scene
from sims.models.common import JointRef, ObjectRef, RaySensor, SceneModel
from sims.quiet import pybullet as p

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]
StepHook = Callable[["World"], None]
GRAVITY = -9.81


class World:
    """One pybullet physics client in DIRECT mode holding one scene ("2w1a" or "cart")."""

    def __init__(
        self,
        scene: str,
        seed: int = 0,
        timestep: float = 0.005,
        *,
        render_with: str | None = None,
        **scene_options: Any,
    ):
        """``render_with``: "egl" or "auto" loads pybullet's EGL renderer plugin *before* the
        scene is built (the plugin only sees shapes created after it loads), falling back to
        TinyRenderer if it fails; None/"tinyrenderer" uses TinyRenderer."""
        self.scene = scene
        self.seed = seed
        self.timestep = timestep
        self.scene_options = dict(scene_options)
        self.time = 0.0
        self.steps = 0  # physics steps since (re)start
        self._hooks: list[StepHook] = []
        self._client: int | None = p.connect(p.DIRECT)
        self._renderer: Any = None  # sims.render.Renderer, created on first render()
        if render_with not in (None, "tinyrenderer", "tiny"):
            from sims.render import Renderer

            self._renderer = Renderer(self, prefer=render_with)
        try:
            self._build()
            if self._renderer is not None:
                self._renderer.verify()
        except BaseException:
            self.close()  # an unknown scene or bad option must not leak the pybullet client
            raise

    # -- lifecycle ---------------------------------------------------------------------------
    def _build(self) -> None:
        c = self._cid
        p.resetSimulation(physicsClientId=c)
        p.setGravity(0, 0, GRAVITY, physicsClientId=c)
        p.setTimeStep(self.timestep, physicsClientId=c)
        p.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
        self.model: SceneModel = build_scene(self.scene, c, self.seed, **self.scene_options)
        names = [o.name for o in self.model.objects] + [j.name for j in self.model.joints]
        names += [s.name for s in self.model.sensors]
        self._names = names
        self._handles = {name: i + 1 for i, name in enumerate(names)}  # 0 means "not found"
        self._objects: dict[str, ObjectRef] = {o.name: o for o in self.model.objects}
        self._joints: dict[str, JointRef] = {j.name: j for j in self.model.joints}
        self._sensors: dict[str, RaySensor] = {s.name: s for s in self.model.sensors}
        self._inertial: dict[int, Pose] = {}
        for j in self.model.joints:
            self._init_motor(j)
        self.time = 0.0
        self.steps = 0

    def reset(self) -> None:
        """Rebuild the initial scene (CoppeliaSim's stop resets it); time = 0. Hooks stay."""
        self._build()
        if self._renderer is not None:
            self._renderer.scene_rebuilt()

    def close(self) -> None:
        if self._client is not None:
            if self._renderer is not None:
                self._renderer.close()
                self._renderer = None
            p.disconnect(physicsClientId=self._client)
            self._client = None

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:  # best effort; close() is the real API
        try:
            self.close()
        except Exception:
            pass

    @property
    def _cid(self) -> int:
        if self._client is None:
            raise RuntimeError("World is closed")
        return self._client

    @property
    def client_id(self) -> int:
        """The pybullet client id, for code that needs raw pybullet calls (contact checks)."""
        return self._cid

    # -- time --------------------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        for _ in range(n):
            p.stepSimulation(physicsClientId=self._cid)
            self.steps += 1
            self.time = self.steps * self.timestep
            for hook in list(self._hooks):
                hook(self)

    def advance(self, seconds: float) -> None:
        self.step(max(0, round(seconds / self.timestep)))

    def add_step_hook(self, hook: StepHook) -> Callable[[], None]:
        """Call ``hook(world)`` after every physics step (recording, limits); returns a remover."""
        self._hooks.append(hook)
        return lambda: self._hooks.remove(hook) if hook in self._hooks else None

    # -- names -------------------------------------------------------------------------------
    def names(self) -> list[str]:
        return list(self._names)

    def handle(self, name: str) -> int | None:
        return self._handles.get(name)

    def name_of(self, handle: int) -> str | None:
        return self._names[handle - 1] if 1 <= handle <= len(self._names) else None

    def is_joint(self, handle: int) -> bool:
        return self.name_of(handle) in self._joints

    def _lookup(self, handle: int | str) -> str:
        name = handle if isinstance(handle, str) else self.name_of(handle)
        if name is None or name not in self._handles:
            raise KeyError(f"no object with handle {handle!r} in scene {self.scene!r}")
        return name

    def _joint(self, handle: int | str) -> JointRef:
        name = self._lookup(handle)
        if name not in self._joints:
            raise KeyError(f"{name!r} is not a joint")
        return self._joints[name]

    # -- poses -------------------------------------------------------------------------------
    def object_pose(self, handle: int | str) -> Pose:
        """World position and quaternion (xyzw) of the object's CoppeliaSim frame."""
        name = self._lookup(handle)
        if name in self._joints:
            j = self._joints[name]
            ref = ObjectRef(name, j.body, j.index)
        elif name in self._sensors:
            s = self._sensors[name]
            ref = ObjectRef(name, s.body, s.link, offset_pos=s.origin)
        else:
            ref = self._objects[name]
        pos, orn = self._link_frame(ref.body, ref.link)
        pos, orn = p.multiplyTransforms(pos, orn, ref.offset_pos, ref.offset_orn)
        return tuple(pos), tuple(orn)  # type: ignore[return-value]

    def _link_frame(self, body: int, link: int) -> Pose:
        c = self._cid
        if link >= 0:
            state = p.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=c)
            return state[4], state[5]
        if body not in self._inertial:
            info = p.getDynamicsInfo(body, -1, physicsClientId=c)
            self._inertial[body] = p.invertTransform(info[3], info[4])
        com_pos, com_orn = p.getBasePositionAndOrientation(body, physicsClientId=c)
        inv_pos, inv_orn = self._inertial[body]
        return p.multiplyTransforms(com_pos, com_orn, inv_pos, inv_orn)

    def object_orientation(self, handle: int | str) -> tuple[float, float, float]:
        """CoppeliaSim Euler angles (alpha, beta, gamma) in rad: R = Rx(alpha)·Ry(beta)·Rz(gamma)."""
        m = p.getMatrixFromQuaternion(self.object_pose(handle)[1])  # row-major 3x3
        beta = math.asin(max(-1.0, min(1.0, m[2])))
        return math.atan2(-m[5], m[8]), beta, math.atan2(-m[1], m[0])

    def heading(self, handle: int | str | None = None) -> float:
        """Yaw (rad, about world z) of the robot's forward axis; for trajectories and plots."""
        pos, orn = self.object_pose(self.model.robot if handle is None else handle)
        m = p.getMatrixFromQuaternion(orn)
        ax = self.model.forward_axis
        fx = m[0] * ax[0] + m[1] * ax[1] + m[2] * ax[2]
        fy = m[3] * ax[0] + m[4] * ax[1] + m[5] * ax[2]
        return math.atan2(fy, fx)

    # -- joints ------------------------------------------------------------------------------
    def joint_position(self, handle: int | str) -> float:
        j = self._joint(handle)
        q = p.getJointState(j.body, j.index, physicsClientId=self._cid)[0]
        return j.zero + j.sign * q

    def joint_velocity(self, handle: int | str) -> float:
        j = self._joint(handle)
        return j.sign * p.getJointState(j.body, j.index, physicsClientId=self._cid)[1]

    def set_joint_target_position(self, handle: int | str, rad: float) -> None:
        """Position control, clamped to the joint's CoppeliaSim range."""
        j = self._joint(handle)
        if j.lower is not None and j.upper is not None:
            rad = min(max(rad, j.lower), j.upper)
        kw: dict[str, float] = {}
        if j.max_velocity is not None:
            kw["maxVelocity"] = j.max_velocity
        p.setJointMotorControl2(
            j.body,
            j.index,
            p.POSITION_CONTROL,
            targetPosition=(rad - j.zero) * j.sign,
            force=j.max_force,
            positionGain=j.position_gain,
            velocityGain=j.velocity_gain,
            physicsClientId=self._cid,
            **kw,
        )

    def set_joint_target_velocity(self, handle: int | str, rad_s: float) -> None:
        """Velocity control with the joint's max torque (CoppeliaSim: motor on, position off).

        On a position-controlled joint (the 2W1A arm) this switches it to velocity control
        until the next set_joint_target_position; CoppeliaSim would instead keep position
        control and ignore the velocity. Scripts in the course never do this."""
        j = self._joint(handle)
        p.setJointMotorControl2(
            j.body,
            j.index,
            p.VELOCITY_CONTROL,
            targetVelocity=rad_s * j.sign,
            force=j.max_force,
            physicsClientId=self._cid,
        )

    def _init_motor(self, j: JointRef) -> None:
        c = self._cid
        if j.lower is not None and j.upper is not None:
            a, b = sorted(((j.lower - j.zero) * j.sign, (j.upper - j.zero) * j.sign))
            p.changeDynamics(
                j.body, j.index, jointLowerLimit=a, jointUpperLimit=b, physicsClientId=c
            )
        if j.mode == "position":
            self.set_joint_target_position(j.name, j.zero)
        elif j.mode == "velocity":
            self.set_joint_target_velocity(j.name, 0.0)
        else:  # free: pybullet's default velocity motor replaced by a small friction torque
            p.setJointMotorControl2(
                j.body,
                j.index,
                p.VELOCITY_CONTROL,
                targetVelocity=0.0,
                force=j.friction_torque,
                physicsClientId=c,
            )

    # -- sensors and contacts ----------------------------------------------------------------
    def proximity_scan(self, name: str) -> list[float | None]:
        """Distances (m) along each ray of a proximity sensor, left to right; None = nothing."""
        s = self._sensors[self._lookup(name)]
        pos, orn = self._link_frame(s.body, s.link)
        starts, ends = [], []
        for direction in s.rays():
            start, _ = p.multiplyTransforms(pos, orn, s.origin, (0, 0, 0, 1))
            tip = tuple(s.origin[k] + direction[k] * s.max_range for k in range(3))
            end, _ = p.multiplyTransforms(pos, orn, tip, (0, 0, 0, 1))
            starts.append(start)
            ends.append(end)
        hits = p.rayTestBatch(starts, ends, physicsClientId=self._cid)
        return [None if h[0] < 0 else h[2] * s.max_range for h in hits]

    def proximity(self, name: str) -> float | None:
        """Nearest detected distance (m) of a proximity sensor, or None when nothing is in range."""
        found = [d for d in self.proximity_scan(name) if d is not None]
        return min(found) if found else None

    def obstacle_contacts(self) -> list[tuple[str, int]]:
        """Contacts between the robot and any obstacle/wall: [(robot object name, obstacle id)]."""
        robot = self._objects[self.model.robot].body
        by_link = {o.link: o.name for o in self.model.objects if o.body == robot}
        out = []
        for obstacle in self.model.obstacles:
            for cp in p.getContactPoints(robot, obstacle, physicsClientId=self._cid):
                out.append((by_link.get(cp[3], str(cp[3])), obstacle))
        return out

    # -- rendering ---------------------------------------------------------------------------
    def render(self, width: int, height: int, follow: str | None = None) -> np.ndarray:
        """HxWx3 uint8 RGB from a chase camera on ``follow`` (default: the scene's robot)."""
        if self._renderer is None:
            from sims.render import Renderer

            self._renderer = Renderer(self, prefer="tinyrenderer")
        return self._renderer.render(width, height, follow or self.model.robot)

    @property
    def renderer(self) -> str:
        """Which renderer ran (or will run): "egl" or "tinyrenderer"."""
        return "tinyrenderer" if self._renderer is None else self._renderer.name
