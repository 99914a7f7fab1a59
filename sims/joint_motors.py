"""Joints of one World in CoppeliaSim's conventions: reading them and driving their motors.

A mixin of sims.world.World, apart from the stepping core so each file says what it holds. A
joint's angle is reported and commanded in CoppeliaSim's convention (``JointRef.zero`` maps
it to pybullet's); its CoppeliaSim mode (position, velocity, hold = passive,
spring, free) picks the pybullet motor set up after every (re)build.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from sims.models.common import JointRef, SceneModel, Vec3
from sims.quiet import pybullet as p

Pose = tuple[tuple[float, float, float], tuple[float, float, float, float]]
JointCallback = Callable[[dict[str, Any]], "dict[str, float] | None"]
HOLD_FORCE = 1e4  # N or N·m: a kinematic (passive-mode) joint is held where it is set


class JointMotors:
    """Joint reads and motor commands; World supplies the scene and the name lookup."""

    model: SceneModel
    _joints: dict[str, JointRef]
    _springs: dict[str, float]  # spring-damper joints: rest position
    _commands: dict[str, tuple[str, float]]  # last motor command per joint
    _callbacks: dict[str, JointCallback]  # custom joint controllers
    timestep: float

    if TYPE_CHECKING:  # supplied by World

        @property
        def _cid(self) -> int: ...

        def joint(self, handle: int | str) -> JointRef: ...

        def moved(self) -> None: ...

        def link_frame(self, body: int, link: int) -> Pose: ...

        def handle(self, name: str) -> int | None: ...

    def kinematic(self, j: JointRef) -> bool:
        """Held where it is put, not driven by a motor: a passive (or dependent) joint, or
        one in plain IK mode (World tracks the modes: sims/world_mech.py)."""
        modes = getattr(self, "_modes", {})
        mode, hybrid = modes.get(j.name, ("force", False))
        return j.mode == "hold" or mode in ("passive", "dependent") or (mode == "ik" and not hybrid)

    def joint_position(self, handle: int | str) -> float:
        j = self.joint(handle)
        if j.kind == "spherical":
            return 0.0
        if j.closure is not None:
            return self._closure_position(j)
        q = p.getJointState(j.body, j.index, physicsClientId=self._cid)[0]
        return j.zero + q

    def joint_velocity(self, handle: int | str) -> float:
        j = self.joint(handle)
        if j.kind == "spherical":
            return 0.0
        if j.closure is not None:
            return self._closure_velocity(j)
        return p.getJointState(j.body, j.index, physicsClientId=self._cid)[1]

    def _closure_frames(self, j: JointRef) -> tuple[Pose, Pose]:
        """A closing joint's frame on its parent link and on its child link, in the world."""
        c = j.closure
        assert c is not None
        a = p.multiplyTransforms(*self.link_frame(j.body, j.index), *c.parent_frame)
        b = p.multiplyTransforms(*self.link_frame(c.child_body, c.child_link), *c.child_frame)
        return a, b  # type: ignore[return-value]

    def _closure_position(self, j: JointRef) -> float:
        a, b = self._closure_frames(j)
        pos, (x, y, z, w) = p.multiplyTransforms(*p.invertTransform(*a), *b)
        if j.kind == "prismatic":
            return pos[2]
        return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))

    def _closure_velocity(self, j: JointRef) -> float:
        c = j.closure
        assert c is not None
        a, _ = self._closure_frames(j)
        axis = p.getMatrixFromQuaternion(a[1])[2::3]
        lin_a, ang_a = self.link_velocity(j.body, j.index)
        lin_b, ang_b = self.link_velocity(c.child_body, c.child_link)
        rel = ang_b if j.kind != "prismatic" else lin_b
        base = ang_a if j.kind != "prismatic" else lin_a
        return sum((rel[k] - base[k]) * axis[k] for k in range(3))

    def link_velocity(self, body: int, link: int) -> tuple[Vec3, Vec3]:
        """Linear velocity of a link's centre of mass and its angular velocity (world frame);
        zero for the world (``body`` -1)."""
        c = self._cid
        if body < 0:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
        if link < 0:
            lin, ang = p.getBaseVelocity(body, physicsClientId=c)
            return tuple(lin), tuple(ang)  # type: ignore[return-value]
        state = p.getLinkState(body, link, computeLinkVelocity=1, physicsClientId=c)
        return tuple(state[6]), tuple(state[7])  # type: ignore[return-value]

    def _unmotored(self, j: JointRef, what: str) -> None:
        """A closing joint has no motor (it is constraints): the command is noted, once."""
        note = f"{j.name}: closes a loop and has no motor here: {what} ignored"
        if note not in self.model.notes:
            self.model.notes.append(note)

    def set_joint_target_position(self, handle: int | str, rad: float) -> None:
        """Position control, clamped to the joint's CoppeliaSim range. A spring-damper joint
        takes the target as its spring's rest position."""
        j = self.joint(handle)
        if j.kind == "spherical":
            return
        if j.lower is not None and j.upper is not None:
            rad = min(max(rad, j.lower), j.upper)
        if j.closure is not None:
            return self._unmotored(j, "target position")
        if j.mode == "spring":
            self._springs[j.name] = rad
            return
        self._commands[j.name] = ("position", rad)
        kw: dict[str, float] = {}
        if j.max_velocity is not None:
            kw["maxVelocity"] = j.max_velocity
        p.setJointMotorControl2(
            j.body,
            j.index,
            p.POSITION_CONTROL,
            targetPosition=rad - j.zero,
            force=HOLD_FORCE if self.kinematic(j) else j.max_force,
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
        j = self.joint(handle)
        if j.kind == "spherical":
            return
        if j.closure is not None:
            return self._unmotored(j, "target velocity")
        self._springs.pop(j.name, None)
        self._commands[j.name] = ("velocity", rad_s)
        p.setJointMotorControl2(
            j.body,
            j.index,
            p.VELOCITY_CONTROL,
            targetVelocity=rad_s,
            force=j.max_force,
            physicsClientId=self._cid,
        )

    def set_joint_max_force(self, handle: int | str, force: float) -> None:
        """The motor's force/torque limit (CoppeliaSim's setJointMaxForce); the motor keeps
        its mode and its last target."""
        j = self.joint(handle)
        new = dataclasses.replace(j, max_force=force)
        self._joints[j.name] = new
        self.model.joints[self.model.joints.index(j)] = new
        kind, value = self._commands.get(j.name, (None, 0.0))
        if kind == "velocity":
            self.set_joint_target_velocity(j.name, value)
        elif kind == "position":
            self.set_joint_target_position(j.name, value)

    def set_joint_position(self, handle: int | str, rad: float) -> None:
        """Put a joint at ``rad`` at once (CoppeliaSim's setJointPosition). A passive-mode
        joint stays there; a motor keeps its own target."""
        j = self.joint(handle)
        if j.kind == "spherical":
            return
        if j.closure is not None:
            return self._unmotored(j, "set position")
        p.resetJointState(j.body, j.index, rad - j.zero, physicsClientId=self._cid)
        self.moved()  # proximity readings see the new pose
        if self.kinematic(j):
            self.set_joint_target_position(j.name, rad)

    def _init_motor(self, j: JointRef) -> None:
        c = self._cid
        if j.closure is not None:
            return
        if j.kind == "spherical":  # free, or held where it is (pybullet's default motor off)
            quat = p.getJointStateMultiDof(j.body, j.index, physicsClientId=c)[0]
            force = HOLD_FORCE if j.mode == "hold" else 0.0
            p.setJointMotorControlMultiDof(
                j.body,
                j.index,
                p.POSITION_CONTROL,
                targetPosition=list(quat),
                targetVelocity=[0.0, 0.0, 0.0],
                force=[force] * 3,
                physicsClientId=c,
            )
            return
        if j.lower is not None and j.upper is not None:
            a, b = sorted((j.lower - j.zero, j.upper - j.zero))
            p.changeDynamics(
                j.body, j.index, jointLowerLimit=a, jointUpperLimit=b, physicsClientId=c
            )
        if j.mode in ("position", "hold"):
            target = j.zero if j.initial_target is None else j.initial_target
            if j.mode == "hold":
                target = self.joint_position(j.name)
            self.set_joint_target_position(j.name, target)
        elif j.mode == "velocity":
            self.set_joint_target_velocity(j.name, j.initial_velocity)
        else:  # free or spring: pybullet's default velocity motor replaced by a friction torque
            p.setJointMotorControl2(
                j.body,
                j.index,
                p.VELOCITY_CONTROL,
                targetVelocity=0.0,
                force=j.friction_torque,
                physicsClientId=c,
            )
            if j.mode == "spring":
                self._springs[j.name] = j.zero if j.initial_target is None else j.initial_target

    def _apply_springs(self) -> None:
        """Spring-damper joints: torque = -k (q - rest) - c dq/dt, capped at the max force."""
        for name, rest in self._springs.items():
            j = self._joints[name]
            q, dq = p.getJointState(j.body, j.index, physicsClientId=self._cid)[:2]
            error = rest - (j.zero + q)
            torque = j.spring_k * error - j.spring_c * dq
            torque = max(-j.max_force, min(j.max_force, torque)) if j.max_force > 0 else torque
            p.setJointMotorControl2(
                j.body,
                j.index,
                p.TORQUE_CONTROL,
                force=torque,
                physicsClientId=self._cid,
            )

    # -- custom joint controllers (sysCall_jointCallback) -------------------------------------
    def set_joint_callback(self, handle: int | str, callback: JointCallback | None) -> None:
        """A custom controller for the joint, called before every physics step as CoppeliaSim
        calls a script's ``sysCall_jointCallback``: it gets CoppeliaSim's ``inData`` fields and
        returns ``{"velocity": v, "force": f}`` (the joint's motor is then driven at v with at
        most f), or None to leave the motor as it is. None removes the controller."""
        j = self.joint(handle)
        if callback is None:
            self._callbacks.pop(j.name, None)
        else:
            self._callbacks[j.name] = callback

    def _run_joint_callbacks(self) -> None:
        c = self._cid
        for name, callback in list(self._callbacks.items()):
            j = self._joints[name]
            q, dq = self.joint_position(name), self.joint_velocity(name)
            kind, value = self._commands.get(name, ("position", q))
            target = value if kind == "position" else q
            data = {
                "handle": self.handle(name),
                "revolute": j.kind == "revolute",
                "cyclic": j.lower is None,
                "lowLimit": j.lower if j.lower is not None else 0.0,
                "highLimit": j.upper if j.upper is not None else 0.0,
                "passCnt": 0,
                "totalPasses": 1,
                "currentPos": q,
                "currentVel": dq,
                "targetPos": target,
                "errorValue": target - q,
                "effort": 0.0,
                "dynStepSize": self.timestep,
                "targetVel": value if kind == "velocity" else 0.0,
                "maxForce": j.max_force,
                "velUpperLimit": j.max_velocity if j.max_velocity is not None else 1e6,
            }
            out = callback(data)
            if not out or "velocity" not in out:
                continue
            force = float(out.get("force", j.max_force))
            p.setJointMotorControl2(
                j.body, j.index, p.VELOCITY_CONTROL,
                targetVelocity=float(out["velocity"]), force=abs(force),
                physicsClientId=c,
            )  # fmt: skip
