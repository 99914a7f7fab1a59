"""Mechanisms of the course scenes move as in CoppeliaSim (issue 28), checked by positions and
angles over simulated time: loop closures hold within 1 mm while their motors turn them, every
scene runs 10 s with its own scripts without bodies leaving it or falling through its floor."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from sims.quiet import pybullet as p
from sims.scene.load import load_scene
from sims.scene.loops import linked_pairs
from sims.world import World
from tests.shared_data import SHARED, shared

SCENES = SHARED / "data" / "scenes"


def scene(*parts: str) -> Path:
    return shared("data", "scenes", *parts)


def run_loops(path: Path, seconds: float) -> tuple[float, dict[str, float]]:
    """Step the scene (no scripts); the widest gap (m) between linked dummies, sampled every
    pass (50 ms), and how far each motorised joint turned (unwrapped, rad)."""
    model = load_scene(path)
    pairs = [(a.name, b.name) for a, b in linked_pairs(model)]
    motors = [
        o.name
        for o in model.objects
        if o.joint is not None and o.joint.mode == "velocity" and o.joint.motor_enabled
    ]
    assert pairs and motors
    world = World(model)
    try:
        turned = dict.fromkeys(motors, 0.0)
        last = {m: world.joint_position(m) for m in motors}
        widest = 0.0
        for step in range(round(seconds / world.timestep)):
            world.step()
            for m in motors:
                q = world.joint_position(m)
                turned[m] += (q - last[m] + math.pi) % (2 * math.pi) - math.pi
                last[m] = q
            if step % 10 == 9:
                for a, b in pairs:
                    gap = math.dist(world.object_pose(a)[0], world.object_pose(b)[0])
                    widest = max(widest, gap)
        return widest, turned
    finally:
        world.close()


def test_jansen_linkage_loops_stay_closed_while_the_motor_turns_it():
    path = scene("course2", "jansen_solvespace.ttt")
    widest, turned = run_loops(path, 10.0)
    commanded = math.radians(-20.0) * 10.0  # the motor's saved target velocity, -20 deg/s
    assert widest < 0.001, f"a loop closure opened by {widest * 1000:.2f} mm"
    assert abs(turned["motor"] - commanded) <= 0.05 * abs(commanded), math.degrees(turned["motor"])


def test_four_bar_with_motor_turns_through_full_cycles_with_its_loop_closed():
    path = scene("vrep_remoteapi_ex", "fourbar", "solvespace_fourbar_with_motor_on.ttt")
    widest, turned = run_loops(path, 4.0)
    commanded = math.radians(-200.0) * 4.0  # -200 deg/s: over two full turns
    assert widest < 0.001, f"the loop closure opened by {widest * 1000:.2f} mm"
    crank = turned["Revolute_joint"]
    assert abs(crank - commanded) <= 0.05 * abs(commanded), math.degrees(crank)


def test_closing_joint_reads_its_angle_from_the_two_links_it_joins():
    """The rocker's ground pivot of the four-bar (Revolute_joint2) is built as constraints:
    its angle follows the rocker as a joint's would (it swings back and forth)."""
    world = World(scene("vrep_remoteapi_ex", "fourbar", "solvespace_fourbar_with_motor_on.ttt"))
    try:
        assert world.joint("Revolute_joint2").closure is not None
        angles = []
        for _ in range(200):  # 1 s: the crank turns 200 degrees
            world.step(5)
            angles.append(world.joint_position("Revolute_joint2"))
        assert max(angles) - min(angles) > math.radians(20)
        assert all(abs(a) < math.pi for a in angles)
    finally:
        world.close()


# --- every scene runs 10 s with its own scripts ------------------------------------------------

ALL = (
    sorted(str(p.relative_to(SCENES)) for p in [*SCENES.rglob("*.ttt"), *SCENES.rglob("*.xml")])
    if SCENES.is_dir()
    else ["none"]
)


def _boxes(world: World) -> dict[tuple[int, int], tuple[np.ndarray, np.ndarray]]:
    c = world.client_id
    out = {}
    for i in range(p.getNumBodies(physicsClientId=c)):
        body = p.getBodyUniqueId(i, physicsClientId=c)
        for link in range(-1, p.getNumJoints(body, physicsClientId=c)):
            lo, hi = p.getAABB(body, link, physicsClientId=c)
            if hi[0] >= lo[0] and p.getDynamicsInfo(body, link, physicsClientId=c)[0] > 0:
                out[(body, link)] = (np.array(lo), np.array(hi))
    return out


def _floor_top(world: World) -> float | None:
    """The top of the widest fixed respondable shape (the scene's floor)."""
    c = world.client_id
    best, top = 0.0, None
    for i in range(p.getNumBodies(physicsClientId=c)):
        body = p.getBodyUniqueId(i, physicsClientId=c)
        if p.getDynamicsInfo(body, -1, physicsClientId=c)[0] != 0:
            continue
        lo, hi = p.getAABB(body, -1, physicsClientId=c)
        area = (hi[0] - lo[0]) * (hi[1] - lo[1])
        if area > best and hi[2] - lo[2] < 0.5:
            best, top = area, hi[2]
    return top


@pytest.mark.parametrize("name", ALL)
def test_every_scene_runs_ten_seconds_without_losing_a_body(name):
    from sims.lua.run import run_scene

    path = scene(name)
    world = World(str(path))
    try:
        start = _boxes(world)
        scene_lo = np.min([lo for lo, _ in start.values()] or [np.zeros(3)], axis=0)
        scene_hi = np.max([hi for _, hi in start.values()] or [np.zeros(3)], axis=0)
        floor = _floor_top(world)
        run_scene(str(path), 10.0, world=world)
        for key, (lo, hi) in _boxes(world).items():
            centre = (lo + hi) / 2
            out = np.maximum(scene_lo - centre, centre - scene_hi).max()
            owner = world.model.data.get(("link", *key), str(key))
            assert out < 10.0, f"{owner} left the scene by {out:.1f} m"
            if floor is not None and key in start and start[key][0][2] >= floor - 0.01:
                assert lo[2] > floor - 0.05, f"{owner} fell through the floor to {lo[2]:.2f} m"
    finally:
        world.close()


# --- collision shapes cover what the scene's shapes cover --------------------------------------

PRIMITIVE_TYPES = {"cuboid": p.GEOM_BOX, "sphere": p.GEOM_SPHERE, "cylinder": p.GEOM_CYLINDER}


def _collision_shapes(world: World) -> list[tuple[int, np.ndarray, tuple, tuple]]:
    """Every collision shape of the World: (type, dimensions, world position, quaternion)."""
    c = world.client_id
    out = []
    for i in range(p.getNumBodies(physicsClientId=c)):
        body = p.getBodyUniqueId(i, physicsClientId=c)
        for link in range(-1, p.getNumJoints(body, physicsClientId=c)):
            if link < 0:
                frame = p.getBasePositionAndOrientation(body, physicsClientId=c)
            else:
                frame = p.getLinkState(body, link, 1, 1, physicsClientId=c)[:2]
            for shape in p.getCollisionShapeData(body, link, physicsClientId=c):
                pos, orn = p.multiplyTransforms(*frame, shape[5], shape[6])
                out.append((shape[2], np.array(shape[3]), pos, orn))
    return out


def _matches(shape: tuple, kind: int, dims: np.ndarray, pos: tuple, orn: tuple) -> bool:
    got_kind, got_dims, got_pos, got_orn = shape
    if got_kind != kind or math.dist(got_pos, pos) > 1e-3:
        return False
    if np.abs(got_dims[: len(dims)] - dims).max() > 1e-3:
        return False
    if kind != p.GEOM_BOX:
        return kind == p.GEOM_SPHERE or abs(abs(np.dot(_z(got_orn), _z(orn))) - 1) < 1e-3
    a = np.array(p.getMatrixFromQuaternion(got_orn)).reshape(3, 3)
    b = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)
    return np.abs(np.abs(a.T @ b) - np.eye(3)).max() < 1e-3


def _z(quat: tuple) -> np.ndarray:
    return np.array(p.getMatrixFromQuaternion(quat)).reshape(3, 3)[:, 2]


@pytest.mark.parametrize("name", ALL)
def test_every_respondable_primitive_collides_with_its_size_and_frame(name):
    """Each pure cuboid, sphere and cylinder that responds is a pybullet primitive of the same
    size at the same place (the conveyor's belt box was left out once: pybullet keeps 16 shapes
    of an array and drops the others silently)."""
    model = load_scene(scene(name))
    world = World(model)
    try:
        shapes = _collision_shapes(world)
        for o in model.objects:
            if o.shape is None or not o.shape.dynamics.respondable:
                continue
            frame = world.object_pose(o.name)
            for mesh in o.shape.meshes:
                if mesh.primitive not in PRIMITIVE_TYPES:
                    continue
                sx, sy, sz = mesh.size
                dims = {
                    "cuboid": np.array([sx, sy, sz]),
                    "sphere": np.array([sx / 2]),
                    "cylinder": np.array([sz, sx / 2]),
                }[mesh.primitive]
                pos, orn = p.multiplyTransforms(*frame, mesh.local.position, mesh.local.quaternion)
                kind = PRIMITIVE_TYPES[mesh.primitive]
                assert any(_matches(s, kind, dims, pos, orn) for s in shapes), (o.name, mesh.size)
    finally:
        world.close()


def test_world_state_is_saved_and_restored_exactly():
    """World.get_state / set_state (issue 34): back to the saved time, poses and motor
    commands; stepping on from there repeats what followed the first time."""
    world = World(scene("vrep_remoteapi_ex", "fourbar", "solvespace_fourbar_with_motor_on.ttt"))
    try:
        world.step(50)
        world.set_joint_target_velocity("Revolute_joint", -1.0)
        state = world.get_state()
        saved = (world.time, world.joint_position("Revolute_joint"), world.object_pose("link2"))
        world.step(100)
        after = world.object_pose("link2")
        world.set_joint_target_velocity("Revolute_joint", 2.0)
        world.step(30)
        world.set_state(state)
        assert (world.time, world.joint_position("Revolute_joint")) == saved[:2]
        assert world.object_pose("link2") == saved[2]
        assert world.motor_command("Revolute_joint") == ("velocity", -1.0)
        world.step(100)
        assert math.dist(world.object_pose("link2")[0], after[0]) < 1e-9
        world.reset()
        with pytest.raises(ValueError):
            world.set_state(state)  # saved before the rebuild
    finally:
        world.close()


def test_cart_pole_stays_balanced_under_its_scripts_controller():
    """The inverted pendulum scene's child script (an LQR: sim.addForce on the cart from the
    joint positions and the dummies' velocities, run here as the script computes it each 50 ms
    pass) keeps the pole up while it drives the cart from -0.7 m toward its 0.5 m set point."""
    from sims.remote_api.object_commands import velocity

    world = World(scene("course2", "invertedPendulum.ttt"))
    try:
        gains = (-31.6228, -118.9923, 200.9721, 70.7427)
        goal = 0.5
        pend, cart = world.handle("pendDummy"), world.handle("cartDummy")
        # nudged away from the slider's end stop: left alone the pole falls within 2 s
        world.set_joint_position("revoluteJoint", -0.05)
        tilt = 0.0
        for _ in range(200):  # 10 s
            x = world.joint_position("sliderJoint")
            pv, cv = velocity(world, pend)[0], velocity(world, cart)[0]
            pp, cp = world.object_pose(pend)[0], world.object_pose(cart)[0]
            rx, rz = pp[0] - cp[0], pp[2] - cp[2]
            omega = (rx * (pv[2] - cv[2]) - rz * (pv[0] - cv[0])) / (rx * rx + rz * rz)
            theta = world.joint_position("revoluteJoint")
            u = gains[0] * (x - goal) + gains[1] * cv[0] + gains[2] * theta + gains[3] * omega
            world.add_force("cartV", (0, 0, 0), (0, -u, 0))
            world.step(world.pass_steps)
            tilt = max(tilt, abs(world.joint_position("revoluteJoint")))
        assert tilt < 0.2, f"the pole tilted {math.degrees(tilt):.0f} degrees"
        assert world.joint_position("sliderJoint") > 0.3  # from -0.7 toward 0.5
    finally:
        world.close()
