"""What moves a World's mechanisms beyond its motors (a mixin of World): joint modes (IK,
passive, force), the IK groups (``world.kinematics``, sims/kinematics.py), path objects
(``world.paths``, sims/path_objects.py), dynamic parts held by a gripper, and the whole physics
state saved and restored (``get_state`` / ``set_state``).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from sims.joint_motors import HOLD_FORCE
from sims.models.common import JointRef, ObjectRef, SceneModel
from sims.path_objects import PathObjects
from sims.quiet import pybullet as p

JOINT_MODES = ("passive", "ik", "dependent", "force")  # CoppeliaSim's sim.jointmode_*


@dataclass
class WorldState:
    """A snapshot of a World (``World.get_state``): pybullet's bodies and velocities, the time,
    the motors' commands and the mechanisms' own state. Valid for the World that made it, until
    its next ``reset()``."""

    build: int
    saved: int
    time: float
    steps: int
    commands: dict[str, tuple[str, float]]
    springs: dict[str, float]
    modes: dict[str, tuple[str, bool]]
    extra: dict[str, Any] = field(default_factory=dict)


class Mechanisms:
    """Joint modes, IK, paths, held parts and state snapshots; World supplies the rest."""

    model: SceneModel
    source: Any
    time: float
    steps: int
    _joints: dict[str, JointRef]
    _objects: dict[str, ObjectRef]
    _commands: dict[str, tuple[str, float]]
    _springs: dict[str, float]
    _modes: dict[str, tuple[str, bool]]
    _build_count: int

    if TYPE_CHECKING:  # supplied by World and JointMotors

        @property
        def _cid(self) -> int: ...

        def joint(self, handle: int | str) -> JointRef: ...

        def object_name(self, handle: int | str) -> str: ...

        def handle(self, name: str) -> int | None: ...

        def joint_position(self, handle: int | str) -> float: ...

        def set_joint_target_position(self, handle: int | str, rad: float) -> None: ...

        def set_joint_target_velocity(self, handle: int | str, rad_s: float) -> None: ...

        def moved(self) -> None: ...

        def object_pose(self, handle: int | str) -> tuple: ...

        def link_frame(self, body: int, link: int) -> tuple: ...

    def _build_mechanisms(self) -> None:
        """After the scene is built: joint modes from the scene, its IK groups and paths."""
        from sims.kinematics import Kinematics

        self._modes = {}
        for j in self._joints.values():
            data = self.model.data.get(j.name)
            jd = getattr(data, "joint", None)
            mode = getattr(jd, "mode", "force")
            hybrid = bool(getattr(jd, "hybrid", False))
            self._modes[j.name] = (mode if mode in JOINT_MODES else "force", hybrid)
        self.kinematics = Kinematics.of(self, self.source)
        self.paths = PathObjects(self, self.source)
        self._belts = {}
        self._held = {}
        self._broken = set()  # force sensors broken this run (sim.breakForceSensor)
        self._enable_force_sensors()
        self._dummy_links = {}
        self._link_constraints = {}
        # CoppeliaSim's main script handles paths and IK groups at each pass's actuation; the
        # World does it before a pass's first physics step (after the scripts' actuation)
        self._pass_work = bool(self.kinematics.groups or self.paths.paths)

    def main_script_actuation(self, dt: float) -> None:
        """What CoppeliaSim's default main script does in each pass's actuation after the child
        scripts: paths with a velocity advance, IK groups not explicitly handled are solved.
        World.step calls it before each pass's first physics step: drivers need not."""
        self.paths.main_script_pass(dt)
        self.kinematics.main_script_pass()

    def place_on_path(self, name: str, path: str, local: tuple) -> None:
        """Put a dummy that follows a path at ``local`` (a pose in the path's frame): the new
        offset of the object on the link that carries it."""
        ref, at = self._objects[name], self._objects[path]
        offset = p.multiplyTransforms(at.offset_pos, at.offset_orn, *local)
        if (ref.body, ref.link) != (at.body, at.link):
            world = p.multiplyTransforms(*self.object_pose(path), *local)
            offset = p.multiplyTransforms(
                *p.invertTransform(*self.link_frame(ref.body, ref.link)), *world
            )
        new = replace(ref, offset_pos=tuple(offset[0]), offset_orn=tuple(offset[1]))
        self._objects[name] = new
        self.model.objects[self.model.objects.index(ref)] = new
        self.moved()

    # -- joint modes --------------------------------------------------------------------------
    def joint_mode(self, handle: int | str) -> tuple[str, bool]:
        """The joint's CoppeliaSim mode ("passive", "ik", "dependent", "force") and whether it
        is hybrid (IK sets the target its motor drives to)."""
        return self._modes.get(self.joint(handle).name, ("force", False))

    def set_joint_mode(self, handle: int | str, mode: str, hybrid: bool = False) -> None:
        """sim.setJointMode. Passive and plain IK joints are kinematic: held where they are
        put; a hybrid IK joint and a force-mode joint are driven by their motor (force mode
        resumes the scene's motor settings, holding the current position)."""
        j = self.joint(handle)
        if mode not in JOINT_MODES:
            raise ValueError(f"joint mode {mode!r} is not one of {', '.join(JOINT_MODES)}")
        self._modes[j.name] = (mode, bool(hybrid))
        if j.closure is not None or j.kind == "spherical":
            return
        here = self.joint_position(j.name)
        if mode in ("passive", "dependent") or (mode == "ik" and not hybrid):
            self._hold(j, here)
        elif mode == "ik" or j.mode in ("position", "hold"):
            last = self._commands.get(j.name)
            self.set_joint_target_position(
                j.name, last[1] if last and last[0] == "position" else here
            )
        elif j.mode == "velocity":
            last = self._commands.get(j.name)
            self.set_joint_target_velocity(
                j.name, last[1] if last and last[0] == "velocity" else 0.0
            )

    def _hold(self, j: JointRef, value: float) -> None:
        """A kinematic joint: put at ``value`` and held there against the physics."""
        c = self._cid
        q = value - j.zero
        p.resetJointState(j.body, j.index, q, physicsClientId=c)
        p.setJointMotorControl2(
            j.body, j.index, p.POSITION_CONTROL, targetPosition=q, force=HOLD_FORCE,
            physicsClientId=c,
        )  # fmt: skip
        self._commands[j.name] = ("position", value)
        self.moved()

    # -- what the IK solver reads and writes ----------------------------------------------------
    def joint_in_ik(self, name: str) -> bool:
        return (
            self._modes.get(name, ("force", False))[0] == "ik"
            or self._modes.get(name, ("force", False))[1]
        )

    def joint_ik_weight(self, name: str) -> float:
        data = getattr(self.model.data.get(name), "joint", None)
        return float(getattr(data, "ik_weight", 1.0))

    def linked_dummy(self, handle: int | str) -> int | None:
        """The handle of the dummy a dummy is linked to (an IK tip's target), or None: the
        scene's link unless a script made or undid one (sim.setLinkDummy)."""
        name = self.object_name(handle)
        if name in self._dummy_links:
            other = self._dummy_links[name]
            return None if other is None else self.handle(other)
        data = self.model.data.get(name)
        dummy = getattr(data, "dummy", None)
        if dummy is None or dummy.linked_to is None:
            return None
        names = {o.handle: o.name for o in getattr(self.source, "objects", ())}
        return self.handle(names.get(dummy.linked_to, ""))

    def apply_ik(self, name: str, value: float) -> None:
        """An IK result: a hybrid joint's new position target, a plain IK joint put there."""
        j = self.joint(name)
        mode, hybrid = self.joint_mode(name)
        if hybrid or mode == "force":  # a joint its motor drives (simIK over dynamic joints)
            self.set_joint_target_position(name, value)
        else:
            self._hold(j, value)

    # -- state --------------------------------------------------------------------------------
    def get_state(self) -> WorldState:
        """The whole physics state, to be put back by ``set_state``."""
        saved = p.saveState(physicsClientId=self._cid)
        return WorldState(
            build=self._build_count,
            saved=saved,
            time=self.time,
            steps=self.steps,
            commands=dict(self._commands),
            springs=dict(self._springs),
            modes=dict(self._modes),
        )

    def set_state(self, state: WorldState) -> None:
        """Back to a state this World saved since its last (re)build: bodies, velocities,
        time, motor commands and joint modes."""
        if state.build != self._build_count:
            raise ValueError("the state was saved before the World was rebuilt (reset)")
        p.restoreState(stateId=state.saved, physicsClientId=self._cid)
        self.time, self.steps = state.time, state.steps
        self._springs = dict(state.springs)
        self._modes = dict(state.modes)
        for name, (kind, value) in state.commands.items():
            mode, hybrid = self._modes.get(name, ("force", False))
            if mode in ("passive", "dependent") or (mode == "ik" and not hybrid):
                self._hold(self.joint(name), value)
            elif kind == "velocity":
                self.set_joint_target_velocity(name, value)
            else:
                self.set_joint_target_position(name, value)
        self._commands = dict(state.commands)
        self.moved()
