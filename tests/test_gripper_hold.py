"""A dynamic part held by a gripper link moves with the arm and comes loose when released
(issue 28: the course's grippers re-parent a grasped part or re-make a force sensor)."""

from __future__ import annotations

import math

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
