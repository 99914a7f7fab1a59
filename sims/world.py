"""One headless pybullet world holding one course scene, addressed CoppeliaSim-style by name.

Contract used by the scenarios, the clip renderer and the remote API (see docs/DESIGN.md):
everything goes through names and stable integer handles, never raw pybullet ids, and every
pybullet call passes ``physicsClientId`` so several Worlds in one process stay independent.
Joint angles are reported and commanded in CoppeliaSim's convention for that joint (the model's
``JointRef`` holds the mapping). ``reset()`` rebuilds the scene like CoppeliaSim's stop/start.

A World holds a bundled scene (``"2w1a"``, ``"cart"``), a scene file (a ``.ttt`` or
``.simscene.xml`` path) or a loaded :class:`sims.scene.model.Scene`; ``tree()`` lists every object
(handle, name, alias, parent, kind) and ``find()`` resolves names and 4.x object paths.

This file is the stepping core (build, step, names, poses); the parts a World is made of live
beside it: sims/world_tree.py (handles and the object tree), sims/joint_motors.py (joint reads
and motors, a mixin), sims/proximity.py (sensor rays) and sims/render.py (drawing).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from sims.joint_motors import JointMotors
from sims.models import build_scene
from sims.models.common import IDENTITY, JointRef, ObjectRef, ProxSensor, SceneModel
from sims.proximity import Hit, ProximitySensors
from sims.quiet import pybullet as p
from sims.world_drawing import WorldDrawing
from sims.world_holds import Holds
from sims.world_mech import Mechanisms
from sims.world_objects import WorldObjects
from sims.world_tree import TreeEntry, make_tree

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]
StepHook = Callable[["World"], None]
GRAVITY = -9.81


def _scene_label(scene: Any) -> str:
    if isinstance(scene, (str, Path)):
        return str(scene)
    return str(getattr(scene, "source", "") or "scene")


class World(JointMotors, WorldDrawing, Mechanisms, Holds, WorldObjects):
    """One pybullet physics client in DIRECT mode holding one scene ("2w1a" or "cart")."""

    def __init__(
        self,
        scene: Any,
        seed: int = 0,
        timestep: float = 0.005,
        *,
        render_with: str | None = None,
        sensors: str = "lazy",
        **scene_options: Any,
    ):
        """``render_with``: "egl" or "auto" loads pybullet's EGL renderer plugin *before* the
        scene is built (the plugin only sees shapes created after it loads), falling back to
        TinyRenderer if it fails; None/"tinyrenderer" uses TinyRenderer.

        ``scene``: a bundled scene name, a scene file path or a loaded Scene model; a file is
        read once (``reset()`` rebuilds from the loaded model).

        ``sensors``: when proximity sensors are cast: "lazy" (at a read) or "main-script" (every
        pass, as CoppeliaSim's main script handles them; sims/proximity.py)."""
        from sims.scene.resolve import open_scene

        self.source = open_scene(scene) if isinstance(scene, (str, Path)) else scene
        self.scene = scene if isinstance(scene, str) else _scene_label(scene)
        self.seed = seed
        self.timestep = timestep
        self.scene_options = dict(scene_options)
        self.sensors = sensors
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
                self.sync_visuals()  # a scene file's looks, before the renderer's first frame
                self._renderer.verify()
        except BaseException:
            self.close()  # an unknown scene or bad option must not leak the pybullet client
            raise

    # -- lifecycle ---------------------------------------------------------------------------
    def _build(self) -> None:
        c = self._cid
        p.resetSimulation(physicsClientId=c)
        self.gravity = tuple(getattr(self.source, "gravity", None) or (0.0, 0.0, GRAVITY))
        p.setGravity(*self.gravity, physicsClientId=c)  # the scene's own (a .ttt's DYN chunk)
        p.setTimeStep(self.timestep, physicsClientId=c)
        p.setPhysicsEngineParameter(deterministicOverlappingPairs=1, physicsClientId=c)
        physics = getattr(self.source, "physics", None)
        if physics is not None:  # the scene's own solver settings (CoppeliaSim saves them)
            p.setPhysicsEngineParameter(numSolverIterations=physics.iterations, physicsClientId=c)
        if isinstance(self.source, str):
            self.model: SceneModel = build_scene(self.source, c, self.seed, **self.scene_options)
        else:
            from sims.scene.build import build

            self.model = build(self.source, c, self.seed, **self.scene_options)
        self._objects: dict[str, ObjectRef] = {o.name: o for o in self.model.objects}
        self._joints: dict[str, JointRef] = {j.name: j for j in self.model.joints}
        self._proximity = ProximitySensors(self, self.model, self.sensors)
        self._sensors: dict[str, ProxSensor] = self._proximity.by_name
        self._tree = make_tree(self.model, c)
        self._names = [e.name for e in self._tree]
        self._handles = {e.name: e.handle for e in self._tree}  # 0 means "not found"
        self._inertial: dict[int, Pose] = {}
        self._springs: dict[str, float] = {}  # spring-damper joints: rest position
        self._commands: dict[str, tuple[str, float]] = {}  # last motor command per joint
        self._modes: dict[str, tuple[str, bool]] = {}  # CoppeliaSim joint modes (world_mech)
        self._callbacks = {}  # custom joint controllers (set_joint_callback)
        self._forces = {}  # forces scripts added this pass (sim.addForce)
        step = getattr(self.source, "time_step", 0.05) or 0.05
        self.pass_steps = max(1, round(step / self.timestep))  # physics steps per pass
        for j in self.model.joints:
            self._init_motor(j)
        self._objects_rebuilt()  # objects created while stopped come back (world_objects.py)
        self._build_count = getattr(self, "_build_count", 0) + 1
        self._build_mechanisms()
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

    def set_gravity(self, gravity: tuple[float, float, float]) -> None:
        """sim.setArrayParam(sim.arrayparam_gravity): from the next physics step on."""
        self.gravity = tuple(float(v) for v in gravity)
        p.setGravity(*self.gravity, physicsClientId=self._cid)

    @property
    def client_id(self) -> int:
        """The pybullet client id, for code that needs raw pybullet calls (contact checks)."""
        return self._cid

    # -- time --------------------------------------------------------------------------------
    def step(self, n: int = 1) -> None:
        c, step_simulation = self._cid, p.stepSimulation  # looked up once: this loop is hot
        sensors = self._proximity if self._proximity.mode == "main-script" else None
        for _ in range(n):
            if self._pass_work and self.steps % self.pass_steps == 0:
                self.main_script_actuation(self.pass_steps * self.timestep)
            if self._springs or self._belts or self._callbacks or self._forces:
                self._before_step()
            step_simulation(physicsClientId=c)
            self.steps += 1
            self.time = self.steps * self.timestep
            if self._forces and self.steps % self.pass_steps == 0:
                self._forces.clear()  # a pass's added forces end with its dynamics
            if sensors is not None:
                sensors.stepped()
            if self._hooks:
                for hook in tuple(self._hooks):
                    hook(self)

    def _before_step(self) -> None:
        """Springs, moving surfaces and custom joint controllers act before each step."""
        if self._springs:
            self._apply_springs()
        if self._belts:
            self._drive_belts()
        if self._callbacks:
            self._run_joint_callbacks()
        if self._forces:
            self._apply_forces()

    def advance(self, seconds: float) -> None:
        self.step(max(0, round(seconds / self.timestep)))

    def add_step_hook(self, hook: StepHook) -> Callable[[], None]:
        """Call ``hook(world)`` after every physics step (recording, limits); returns a remover."""
        self._hooks.append(hook)
        return lambda: self._hooks.remove(hook) if hook in self._hooks else None

    # -- names -------------------------------------------------------------------------------
    def tree(self) -> list[TreeEntry]:
        """Every object of the scene, in handle order (removed objects leave no entry)."""
        return [e for e in self._tree if e is not None]

    def find(self, path_or_name: str, relative_to: int | None = None) -> int | None:
        """Handle of an old-style name (``name``, ``name#0``) or a 4.x path (``/robot/joint``,
        ``/robot/joint[0]``, ``./child`` from ``relative_to``); None when nothing matches."""
        from sims.scene.paths import PathError, resolve

        try:
            return resolve(self.object_tree(), str(path_or_name), relative_to)
        except PathError:  # a malformed path names nothing
            return None

    def kind(self, handle: int | str) -> str:
        return self._tree[self.handle_of(handle) - 1].kind

    def parent(self, handle: int | str) -> int | None:
        return self._tree[self.handle_of(handle) - 1].parent

    def handle_of(self, handle: int | str) -> int:
        h = self._handles.get(handle) if isinstance(handle, str) else handle
        if not isinstance(h, int) or not 1 <= h <= len(self._tree) or self._tree[h - 1] is None:
            raise KeyError(f"no object with handle {handle!r} in scene {self.scene!r}")
        return h

    def names(self) -> list[str]:
        return [n for n in self._names if n is not None]

    def handle(self, name: str) -> int | None:
        return self._handles.get(name)

    def name_of(self, handle: int) -> str | None:
        return self._names[handle - 1] if 1 <= handle <= len(self._names) else None

    def is_joint(self, handle: int) -> bool:
        return self.name_of(handle) in self._joints

    def object_name(self, handle: int | str) -> str:
        """The name of a handle (or a name): KeyError when the scene has no such object."""
        name = handle if isinstance(handle, str) else self.name_of(handle)
        if name is None or name not in self._handles:
            raise KeyError(f"no object with handle {handle!r} in scene {self.scene!r}")
        return name

    def joint(self, handle: int | str) -> JointRef:
        """The joint's record (its pybullet body and index, limits, mode): KeyError when the
        object is not a joint."""
        name = self.object_name(handle)
        if name not in self._joints:
            raise KeyError(f"{name!r} is not a joint")
        return self._joints[name]

    def joints(self) -> list[JointRef]:
        """Every joint, in the scene's order."""
        return list(self._joints.values())

    def motor_command(self, handle: int | str) -> tuple[str, float] | None:
        """The last command sent to the joint's motor: ("position", rad or m) or ("velocity",
        rad/s or m/s); None when none was sent since the (re)start."""
        return self._commands.get(self.joint(handle).name)

    def object_ref(self, handle: int | str) -> ObjectRef | None:
        """The pybullet (body, link) an object rides on and its offset there, as it is now
        (re-parenting changes it); None for a joint, a sensor or an object on nothing."""
        return self._objects.get(self.object_name(handle))

    def object_refs(self) -> list[ObjectRef]:
        """Every object's ``object_ref`` (shapes, dummies... riding a body or the world)."""
        return list(self._objects.values())

    @property
    def closed(self) -> bool:
        """True once ``close()`` disconnected the physics client."""
        return self._client is None

    def proximity_sensor(self, handle: int | str) -> ProxSensor:
        """The proximity sensor's record (its frame on a link and its rays)."""
        name = self.object_name(handle)
        if name not in self._sensors:
            raise KeyError(f"{name!r} is not a proximity sensor")
        return self._sensors[name]

    # -- poses -------------------------------------------------------------------------------
    def object_pose(self, handle: int | str) -> Pose:
        """World position and quaternion (xyzw) of the object's CoppeliaSim frame."""
        name = self.object_name(handle)
        if name in self._joints:
            j = self._joints[name]
            if j.closure is not None:
                return self._closure_frames(j)[0]
            pos, orn = self.link_frame(j.body, j.index)
            if j.own_frame and j.kind != "spherical":
                q = p.getJointState(j.body, j.index, physicsClientId=self._cid)[0]
                if j.kind == "prismatic":
                    back = ((0.0, 0.0, -q), (0.0, 0.0, 0.0, 1.0))
                else:
                    back = ((0.0, 0.0, 0.0), (0.0, 0.0, math.sin(-q / 2), math.cos(-q / 2)))
                pos, orn = p.multiplyTransforms(pos, orn, *back)
            return tuple(pos), tuple(orn)  # type: ignore[return-value]
        if name in self._sensors:
            s = self._sensors[name]
            ref = ObjectRef(name, s.body, s.link, s.offset_pos, s.offset_orn)
        else:
            ref = self._objects[name]
            if ref.via:
                return self._hanging_pose(ref)
        pos, orn = self.link_frame(ref.body, ref.link)
        pos, orn = p.multiplyTransforms(pos, orn, ref.offset_pos, ref.offset_orn)
        return tuple(pos), tuple(orn)  # type: ignore[return-value]

    def _hanging_pose(self, ref: ObjectRef) -> Pose:
        """An object under a loop's closing joint: the joint's frame on its parent link, moved
        by the joint's position, then the object's offset (sims/scene/loops.py)."""
        j = self._joints[ref.via]
        pos, orn = self._closure_frames(j)[0]
        q = self.joint_position(j.name)
        if j.kind == "prismatic":
            move: Pose = ((0.0, 0.0, q), IDENTITY)
        else:
            move = ((0.0, 0.0, 0.0), (0.0, 0.0, math.sin(q / 2), math.cos(q / 2)))
        pos, orn = p.multiplyTransforms(pos, orn, *move)
        pos, orn = p.multiplyTransforms(pos, orn, *ref.via_offset)
        return tuple(pos), tuple(orn)  # type: ignore[return-value]

    def link_frame(self, body: int, link: int) -> Pose:
        """World frame of a pybullet link (``link`` -1: the body's base frame, not its centre
        of mass; ``body`` -1: the world)."""
        c = self._cid
        if body < 0:  # a frame fixed in the world
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
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
        """CoppeliaSim Euler angles (alpha, beta, gamma) in rad: R =
        Rx(alpha)·Ry(beta)·Rz(gamma)."""
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

    # -- sensors and contacts ----------------------------------------------------------------
    @property
    def proximity_sensors(self) -> ProximitySensors:
        """The proximity sensors: handling and kept results (sims/proximity.py)."""
        return self._proximity

    def moved(self) -> None:
        """Something was put somewhere between steps: lazy sensor readings are cast again."""
        self._proximity.forget()

    def sensor_hits(self, name: str) -> list[Hit | None]:
        """Each ray of a proximity sensor: None, or (distance from the sensor origin, point and
        normal in the sensor frame, body, link). The sensor frame's z is its sensing axis."""
        return self._proximity.hits(name)

    def nearest_hit(self, name: str) -> Hit | None:
        """The nearest of ``sensor_hits`` (the first of equals), what a proximity sensor
        reports (sims/proximity.py casts the rays)."""
        return self._proximity.nearest(name)

    def proximity_scan(self, name: str) -> list[float | None]:
        """Distances (m) along each ray of a proximity sensor (a bundled fan: left to right);
        None = nothing."""
        return [None if h is None else h[0] for h in self.sensor_hits(name)]

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
