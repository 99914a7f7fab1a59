"""A dynamic part held by a gripper link moves with the arm and comes loose when released
(issue 28: the course's grippers re-parent a grasped part or re-make a force sensor)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sims.quiet import pybullet as p
from sims.world import World
from tests.shared_data import shared


def relative(world: World, a: str, b: str):
    pa, qa = world.object_pose(a)
    pb, qb = world.object_pose(b)
    return p.multiplyTransforms(*p.invertTransform(pa, qa), pb, qb)


def test_held_part_follows_the_arm_and_falls_when_released():
    world = World(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    try:
        world.step(20)
        # the block held 30 cm out along the gripper's axis, clear of its fingers
        pos, orn = world.object_pose("RG2_attachPoint")
        axis = p.getMatrixFromQuaternion(orn)[2::3]
        at = [pos[k] + 0.3 * axis[k] for k in range(3)]
        ref = next(o for o in world.model.objects if o.name == "Cuboid")
        p.resetBasePositionAndOrientation(ref.body, at, orn, physicsClientId=world.client_id)
        world.hold("Cuboid", "RG2")
        world.step(10)  # the hold takes the block's weight
        before = relative(world, "RG2", "Cuboid")
        assert world.held_by("Cuboid") is not None
        world.set_joint_target_position("UR5_joint1", math.radians(90))
        world.set_joint_target_position("UR5_joint2", math.radians(-30))
        for _ in range(40):  # 2 s: the arm swings a quarter turn at 180 deg/s
            world.step(10)
            now = relative(world, "RG2", "Cuboid")
            assert math.dist(now[0], before[0]) < 0.002
        assert world.joint_position("UR5_joint1") == pytest.approx(math.radians(90), abs=0.02)
        lifted = world.object_pose("Cuboid")[0]
        assert world.release("Cuboid") and not world.release("Cuboid")
        world.step(100)
        assert world.object_pose("Cuboid")[0][2] < lifted[2] - 0.1  # it fell
        with pytest.raises(ValueError):
            world.hold("ConveyorBelt", "RG2")  # a static shape is not a part to hold
    finally:
        world.close()


def test_rg2_closes_on_a_block_and_keeps_it_while_the_arm_swings():
    """The RG2's fingers are a linkage closed by four loop closures and driven by one prismatic
    motor; its centre joint follows through the scene's joint callback (emulated here as the
    scene's script computes it: P = 0.1 toward half the motor's opening)."""
    world = World(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    try:

        def centre(data):
            error = -world.joint_position("RG2_openCloseJoint") / 2 - data["currentPos"]
            v = max(
                -data["velUpperLimit"],
                min(data["velUpperLimit"], error * 0.1 / data["dynStepSize"]),
            )
            return {"velocity": v, "force": data["maxForce"]}

        world.set_joint_callback("RG2_centerJoint1", centre)
        world.set_joint_max_force("RG2_openCloseJoint", 20)
        world.set_joint_target_velocity("RG2_openCloseJoint", 0.11)  # open
        world.step(300)
        left, right = (np.array(world.object_pose(f"RG2_{s}Touch")[0]) for s in ("left", "right"))
        assert np.linalg.norm(right - left) > 0.1
        # a 5 x 5 x 20 cm block between the fingers, its long side across the jaw
        jaw = (right - left) / np.linalg.norm(right - left)
        approach = np.array(p.getMatrixFromQuaternion(world.object_pose("RG2_attachPoint")[1]))
        long_side = np.cross(jaw, approach.reshape(3, 3)[:, 2])
        frame = np.stack([jaw, np.cross(long_side, jaw), long_side / np.linalg.norm(long_side)], 1)
        block = next(o for o in world.model.objects if o.name == "Cuboid")
        p.resetBasePositionAndOrientation(
            block.body, ((left + right) / 2).tolist(), _quat(frame), physicsClientId=world.client_id
        )
        world.set_joint_target_velocity("RG2_openCloseJoint", -0.11)  # close on it
        world.step(200)
        world.set_joint_target_position("UR5_joint1", math.radians(90))
        world.set_joint_target_position("UR5_joint2", math.radians(-30))
        for _ in range(60):  # 3 s: the arm swings a quarter turn and stops
            world.step(10)
            left, right = (
                np.array(world.object_pose(f"RG2_{s}Touch")[0]) for s in ("left", "right")
            )
            held = np.array(world.object_pose("Cuboid")[0])
            assert np.linalg.norm(held - (left + right) / 2) < 0.05, f"dropped at {world.time:.2f}"
        assert world.joint_position("UR5_joint1") == pytest.approx(math.radians(90), abs=0.02)
    finally:
        world.close()


def _quat(m: np.ndarray) -> tuple[float, float, float, float]:
    w = math.sqrt(max(0.0, 1 + m[0, 0] + m[1, 1] + m[2, 2])) / 2
    return (
        (m[2, 1] - m[1, 2]) / (4 * w),
        (m[0, 2] - m[2, 0]) / (4 * w),
        (m[1, 0] - m[0, 1]) / (4 * w),
        w,
    )
