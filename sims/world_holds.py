"""Bodies a World holds or moves beyond its joints (a mixin of World): static surfaces that
carry what lies on them (a conveyor's belt) and dynamic parts held by a gripper.

A static shape given a velocity (CoppeliaSim's init velocity on a static respondable shape, the
conveyor models' "forwarder") keeps its place while its surface moves: a heavy stand-in body
takes its collisions and is put back each step at the shape's place with that velocity, its
weight carried, so what lies on it is dragged by friction as in CoppeliaSim's Bullet engine.

A dynamic part re-parented onto a gripper (``hold``: sim.setObjectParent of a grasped part onto
a gripper's attach point, a force sensor) is held by a fixed constraint at its pose at that
moment, until ``release`` or until that force sensor breaks (``break_force_sensor``: CoppeliaSim
links two dynamic bodies only through a joint or a force sensor, and a broken sensor links
nothing for the rest of the simulation).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from sims.models.common import JointRef, ObjectRef, SceneModel
from sims.quiet import pybullet as p

BELT_MASS = 1e4  # kg: a moving static surface barely feels what lies on it
GRAVITY_Z = -9.81
HOLD_FORCE_N = 1e5  # N: what a gripper's hold withstands (rigid for the course's parts)


@dataclass
class Belt:
    """A stand-in body for a static shape whose surface moves (set_initial_velocity)."""

    uid: int
    name: str
    mass: float
    linear: tuple = (0.0, 0.0, 0.0)
    angular: tuple = (0.0, 0.0, 0.0)


@dataclass
class Hold:
    """A part held by a link: the constraint and the collision pair switched off."""

    constraint: int
    part: tuple[int, int]
    by: tuple[int, int]
    via: str = ""  # the force sensor the part hangs on ("" if held by another object)


class Holds:
    """Moving surfaces and held parts; World supplies the scene and its frames."""

    model: SceneModel
    _objects: dict[str, ObjectRef]
    _joints: dict[str, JointRef]
    _belts: dict[str, Belt]
    _held: dict[str, Hold]
    _broken: set[str]
    _dummy_links: dict[str, str | None]  # links scripts made or undid (sim.setLinkDummy)
    _link_constraints: dict[str, int]  # a dynamically linked dummy -> its pybullet constraint
    _forces: dict[str, tuple[tuple, tuple]]

    if TYPE_CHECKING:  # supplied by World

        @property
        def _cid(self) -> int: ...

        def object_name(self, handle: int | str) -> str: ...

        def object_pose(self, handle: int | str) -> tuple: ...

        def moved(self) -> None: ...

        def link_frame(self, body: int, link: int) -> tuple: ...

        def proximity_sensor(self, handle: int | str) -> Any: ...

        def kind(self, handle: int | str) -> str: ...

        def created(self, handle: int) -> Any: ...

        def handle_of(self, handle: int | str) -> int: ...

    # -- static shapes that move what lies on them (conveyor belts) ----------------------------
    def set_initial_velocity(
        self, handle: int | str, linear: tuple, angular: tuple = (0.0, 0.0, 0.0)
    ) -> None:
        """CoppeliaSim's shapefloatparam_init_velocity_*: a dynamic shape starts moving at it;
        a static respondable shape keeps its place but its surface moves at it, carrying what
        lies on it (the conveyor models' "forwarder"). Here a heavy stand-in body takes the
        static shape's place, put back each step with that velocity."""
        name = self.object_name(handle)
        obj = self.model.data.get(name)
        shape = getattr(obj, "shape", None)
        if shape is None:
            raise KeyError(f"{name!r} is not a shape")
        lin = tuple(float(v) for v in linear)
        ang = tuple(float(v) for v in angular)
        if not shape.dynamics.static:
            ref = self._objects.get(name)
            if ref is not None and ref.link < 0 and ref.body >= 0:
                p.resetBaseVelocity(ref.body, lin, ang, physicsClientId=self._cid)
            return
        belt = self._belts.get(name) or self._make_belt(name, shape)
        if belt is not None:
            belt.linear, belt.angular = lin, ang

    def reset_dynamic_object(self, handle: int | str) -> None:
        """sim.resetDynamicObject: the object is taken out of the physics and put back; a
        moving static surface keeps its velocity (it is set again each step)."""
        self.object_name(handle)
        self.moved()

    def _make_belt(self, name: str, shape: Any) -> Belt | None:
        from sims.scene import shapes as S
        from sims.scene.bodies import STATIC, collision_group, compound_shape
        from sims.scene.model import Pose as MPose

        c = self._cid
        parts = [
            S.Part(m, MPose(m.local.position, m.local.quaternion), True, False, False, name)
            for m in shape.meshes
        ]
        col = compound_shape(c, parts)
        if col < 0 and len(parts) == 1:
            col = S.create_collision(c, parts[0], fixed=False)
        if col < 0 or not shape.dynamics.respondable:
            return None
        pos, orn = self.object_pose(name)
        hidden = p.createVisualShape(  # drawn by the shape's own look, not by this body
            p.GEOM_SPHERE, radius=1e-6, rgbaColor=(0.0, 0.0, 0.0, 0.0), physicsClientId=c
        )
        uid = p.createMultiBody(BELT_MASS, col, hidden, pos, orn, physicsClientId=c)
        friction = shape.dynamics.friction
        p.changeDynamics(
            uid, -1, lateralFriction=0.71 if friction is None else friction,
            linearDamping=0.0, angularDamping=0.0, physicsClientId=c,
        )  # fmt: skip
        group, mask = collision_group(True, False)
        p.setCollisionFilterGroupMask(uid, -1, group, mask & ~STATIC, physicsClientId=c)
        for body, row in self.model.data.get("collision_rows", {}).get(name, []):
            p.setCollisionFilterGroupMask(body, row, 0, 0, physicsClientId=c)
        belt = Belt(uid, name, BELT_MASS)
        self._belts[name] = belt
        return belt

    def _drive_belts(self) -> None:
        """Each belt back at its shape's place, moving at its velocity, its weight carried."""
        c = self._cid
        for belt in self._belts.values():
            pos, orn = self.object_pose(belt.name)
            p.resetBasePositionAndOrientation(belt.uid, pos, orn, physicsClientId=c)
            p.resetBaseVelocity(belt.uid, belt.linear, belt.angular, physicsClientId=c)
            com = p.getBasePositionAndOrientation(belt.uid, physicsClientId=c)[0]
            p.applyExternalForce(
                belt.uid, -1, (0.0, 0.0, -GRAVITY_Z * belt.mass), com, p.WORLD_FRAME,
                physicsClientId=c,
            )  # fmt: skip

    # -- parts held by a gripper ---------------------------------------------------------------
    def _carrier(self, name: str) -> tuple[int, int]:
        """The pybullet (body, link) an object rides on (a joint: its moving link)."""
        if name in self._joints:
            j = self._joints[name]
            return j.body, j.index
        if name in self._objects:
            ref = self._objects[name]
            return ref.body, ref.link
        sensor = self.proximity_sensor(name)
        return sensor.body, sensor.link

    def _com(self, body: int, link: int) -> tuple:
        c = self._cid
        if body < 0:
            return (0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)
        if link < 0:
            return p.getBasePositionAndOrientation(body, physicsClientId=c)
        return p.getLinkState(body, link, computeForwardKinematics=1, physicsClientId=c)[:2]

    def _dynamic_shape(self, name: str) -> bool:
        shape = getattr(self.model.data.get(name), "shape", None)
        return shape is not None and not shape.dynamics.static

    def _free_dynamic(self, name: str) -> bool:
        """A dynamic shape that is its own body's base (not a link of a chain)."""
        ref = self._objects.get(name)
        if ref is None or ref.body < 0 or ref.link >= 0:
            return False
        shape = getattr(self.model.data.get(name), "shape", None)
        if shape is not None:
            return not shape.dynamics.static
        made = self.created(self.handle_of(name))  # a shape a script created
        return made is not None and made.kind == "shape" and made.mass > 0

    def can_hold(self, part: int | str) -> bool:
        """True when ``part`` is a free dynamic shape (what hold() takes)."""
        return self._free_dynamic(self.object_name(part))

    def hold(self, part: int | str, by: int | str | None) -> None:
        """Hold a dynamic part rigidly on the link ``by`` rides on (None: the world), where it
        is now (what a gripper's script means by re-parenting a grasped part onto its attach
        point, or by making it static under the gripper); held again if already held.
        ValueError for a part that is not a free dynamic shape, or a broken force sensor."""
        name = self.object_name(part)
        holder = None if by is None else self.object_name(by)
        if not self._free_dynamic(name):
            raise ValueError(f"{name!r} is not a free dynamic shape: it cannot be held")
        if holder in self._broken:
            raise ValueError(f"force sensor {holder!r} is broken: it holds nothing")
        ref = self._objects[name]
        self.release(name)
        at = (-1, -1) if holder is None else self._carrier(holder)
        if at[0] == ref.body:
            raise ValueError(f"{name!r} cannot hold itself")
        c = self._cid
        child = self._com(ref.body, -1)
        if at[0] < 0:  # on the world (or an object that stands on it): the part's own frame
            cid = p.createConstraint(
                ref.body, -1, -1, -1, p.JOINT_FIXED, (0, 0, 0), (0, 0, 0), child[0],
                (0, 0, 0, 1), child[1], physicsClientId=c,
            )  # fmt: skip
        else:
            rel = p.multiplyTransforms(*p.invertTransform(*self._com(*at)), *child)
            cid = p.createConstraint(
                at[0], at[1], ref.body, -1, p.JOINT_FIXED, (0, 0, 0), rel[0], (0, 0, 0),
                rel[1], (0, 0, 0, 1), physicsClientId=c,
            )  # fmt: skip
            p.setCollisionFilterPair(at[0], ref.body, at[1], -1, 0, physicsClientId=c)
        p.changeConstraint(cid, maxForce=HOLD_FORCE_N, erp=0.8, physicsClientId=c)
        via = holder if holder is not None and self.kind(holder) == "force_sensor" else ""
        self._held[name] = Hold(cid, (ref.body, -1), at, via)

    def release(self, part: int | str) -> bool:
        """Let a held part go (False: it was not held)."""
        hold = self._held.pop(self.object_name(part), None)
        if hold is None:
            return False
        c = self._cid
        p.removeConstraint(hold.constraint, physicsClientId=c)
        if hold.by[0] >= 0:
            p.setCollisionFilterPair(
                hold.by[0], hold.part[0], hold.by[1], hold.part[1], 1, physicsClientId=c
            )
        return True

    def held_by(self, part: int | str) -> tuple[int, int] | None:
        """The (body, link) holding a part, or None."""
        hold = self._held.get(self.object_name(part))
        return None if hold is None else hold.by

    def break_force_sensor(self, sensor: int | str) -> list[str]:
        """sim.breakForceSensor: the sensor links nothing any more (until the scene is rebuilt,
        as CoppeliaSim restores it at the simulation's end); the parts held on it come loose.
        Returns their names. A sensor built as a joint of a dynamic chain (a force sensor between
        two links of one model) keeps its links together: the chain is one pybullet body."""
        name = self.object_name(sensor)
        if self.kind(name) != "force_sensor":
            raise ValueError(f"{name!r} is not a force sensor")
        self._broken.add(name)
        at = self.force_sensor_joint(name)
        if at is not None and any(
            (r.body, r.link) == at and r.name != name and self._dynamic_shape(r.name)
            for r in self._objects.values()
        ):
            note = f"{name}: broken, but it joins two links of one body here: they stay together"
            if note not in self.model.notes:
                self.model.notes.append(note)
        loose = [part for part, hold in self._held.items() if hold.via == name]
        for part in loose:
            self.release(part)
        return loose

    def force_sensor_broken(self, sensor: int | str) -> bool:
        return self.object_name(sensor) in self._broken

    def _enable_force_sensors(self) -> None:
        """Force sensors measure from the first physics step on (CoppeliaSim's readForceSensor
        has values once the dynamics ran): pybullet reports a joint's reaction only when asked
        before stepping."""
        for o in self.model.data.values():
            if getattr(o, "kind", "") == "force_sensor":
                at = self.force_sensor_joint(o.name)
                if at is not None:
                    p.enableJointForceTorqueSensor(*at, True, physicsClientId=self._cid)

    def force_sensor_joint(self, sensor: int | str) -> tuple[int, int] | None:
        """The pybullet (body, joint index) a force sensor was built as: the fixed joint of its
        own link (its reaction is what the sensor measures), or None when the sensor is not
        part of a dynamic body (nothing dynamic on either side)."""
        name = self.object_name(sensor)
        j = self._joints.get(name)
        if j is not None:
            return j.body, j.index
        ref = self._objects.get(name)
        if ref is None or ref.body < 0 or ref.link < 0 or ref.offset_pos != (0.0, 0.0, 0.0):
            return None
        info = p.getJointInfo(ref.body, ref.link, physicsClientId=self._cid)
        return (ref.body, ref.link) if info[2] == p.JOINT_FIXED else None

    # -- dummy-dummy links a script makes (sim.setLinkDummy) ------------------------------------
    def link_dummies(self, dummy: int | str, other: int | str | None, dynamic: bool) -> None:
        """sim.setLinkDummy: link two dummies (``other`` None: undo the dummy's link). A link
        of a dynamics type ("overlap constraint": a suction pad's dummy re-parented onto the
        part, linked to the pad's) holds the two dummies' frames together through the bodies
        they ride on, as a loop closure does; an IK tip-target link only pairs them for IK
        (``linked_dummy``). A loop closure saved with the scene stays built when undone."""
        a = self.object_name(dummy)
        self._unlink(a)
        if other is None:
            return
        b = self.object_name(other)
        if a == b:
            raise ValueError(f"dummy {a!r} cannot be linked to itself")
        self._unlink(b)
        self._dummy_links[a], self._dummy_links[b] = b, a
        if dynamic:
            self._overlap(a, b)

    def _unlink(self, name: str) -> None:
        partner = self.linked_dummy(name)
        for n in (name, None if partner is None else self.object_name(partner)):
            if n is None:
                continue
            self._dummy_links[n] = None
            cid = self._link_constraints.pop(n, None)
            if cid is not None:
                p.removeConstraint(cid, physicsClientId=self._cid)

    def _overlap(self, a: str, b: str) -> None:
        """A constraint bringing dummy ``a``'s frame onto dummy ``b``'s (riding their links)."""
        ra, rb = self._objects.get(a), self._objects.get(b)
        if ra is None or rb is None:
            raise ValueError(f"{a!r} and {b!r} must be dummies on the scene's bodies or the world")
        if (ra.body, ra.link) == (rb.body, rb.link) or (ra.body < 0 and rb.body < 0):
            return  # nothing moves one against the other
        if ra.body < 0:
            ra, rb, a, b = rb, ra, b, a
        c = self._cid
        ends = []
        for ref, name in ((ra, a), (rb, b)):
            com = self._com(ref.body, ref.link)
            ends.append(p.multiplyTransforms(*p.invertTransform(*com), *self.object_pose(name)))
        cid = p.createConstraint(
            ra.body, ra.link, rb.body, rb.link, p.JOINT_FIXED, (0, 0, 0), ends[0][0], ends[1][0],
            ends[0][1], ends[1][1], physicsClientId=c,
        )  # fmt: skip
        p.changeConstraint(cid, maxForce=HOLD_FORCE_N, erp=0.8, physicsClientId=c)
        self._link_constraints[a] = cid

    # -- forces a script adds (sim.addForce, sim.addForceAndTorque) ----------------------------
    def add_force_and_torque(self, handle: int | str, force: tuple, torque: tuple) -> None:
        """sim.addForceAndTorque: a force at the shape's centre of mass and a torque, both in
        the world frame, added to what the pass's dynamics steps apply (cleared at the pass's
        end, as CoppeliaSim clears them after sim.handleDynamics)."""
        name = self.object_name(handle)
        ref = self._objects.get(name)
        shape = getattr(self.model.data.get(name), "shape", None)
        if ref is None or shape is None or shape.dynamics.static or ref.body < 0:
            return  # CoppeliaSim ignores forces on shapes that are not dynamic
        f0, t0 = self._forces.get(name, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))
        f = tuple(a + float(b) for a, b in zip(f0, force, strict=True))
        t = tuple(a + float(b) for a, b in zip(t0, torque, strict=True))
        self._forces[name] = (f, t)

    def add_force(self, handle: int | str, position: tuple, force: tuple) -> None:
        """sim.addForce: ``force`` applied at ``position``, both in the shape's own frame: the
        force at the centre of mass and the torque ``position x force`` (CoppeliaSim's own
        reckoning), turned into the world frame."""
        name = self.object_name(handle)
        orn = self.object_pose(name)[1]
        r = [float(v) for v in position]
        f = [float(v) for v in force]
        t = (r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0])
        m = p.getMatrixFromQuaternion(orn)

        def world(v) -> tuple:
            return tuple(
                m[3 * i] * v[0] + m[3 * i + 1] * v[1] + m[3 * i + 2] * v[2] for i in range(3)
            )

        self.add_force_and_torque(name, world(f), world(t))

    def _apply_forces(self) -> None:
        c = self._cid
        for name, (force, torque) in self._forces.items():
            ref = self._objects[name]
            if ref.link < 0:
                com = p.getBasePositionAndOrientation(ref.body, physicsClientId=c)[0]
            else:
                com = p.getLinkState(ref.body, ref.link, physicsClientId=c)[0]
            p.applyExternalForce(ref.body, ref.link, force, com, p.WORLD_FRAME, physicsClientId=c)
            p.applyExternalTorque(ref.body, ref.link, torque, p.WORLD_FRAME, physicsClientId=c)
