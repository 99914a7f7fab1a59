"""IK groups saved with course scenes, solved on the World as CoppeliaSim solves them (issue 28):
checked on where the tip ends up and on the joint angles, kinematically and under dynamics."""

from __future__ import annotations

import math

import pytest

from sims.kinematics import FAIL, HANDLE_ALL_EXCEPT_EXPLICIT, NOT_PERFORMED, SUCCESS
from sims.scene.load import load_scene
from sims.world import World
from tests.shared_data import shared

UR5 = [f"UR5_joint{i}" for i in range(1, 7)]
AWAY = [0.4, -0.3, 0.5, 0.2, -0.4, 0.3]  # rad: a configuration the tip is 10 cm off in


@pytest.fixture(scope="module")
def ur5_scene():
    return load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))


def gap(world: World) -> tuple[float, float]:
    """Tip-to-target distance (m) and angle (rad)."""
    (tp, tq), (gp, gq) = world.object_pose("UR5_ikTip"), world.object_pose("UR5_ikTarget")
    dot = abs(sum(a * b for a, b in zip(tq, gq, strict=True)))
    return math.dist(tp, gp), 2 * math.acos(min(1.0, dot))


def test_scene_ik_group_is_read_with_its_tip_target_and_settings(ur5_scene):
    (group,) = ur5_scene.ik_groups
    names = {o.handle: o.name for o in ur5_scene.objects}
    (element,) = group.elements
    assert group.name == "UR5" and group.explicit and group.iterations == 3
    assert group.method == "pseudo_inverse"
    assert names[element.tip] == "UR5_ikTip" and names[element.base] == "UR5"
    assert element.constraints == 31  # x, y, z, alpha-beta, gamma
    assert element.precision == pytest.approx((0.0005, math.radians(0.1)), rel=1e-5)


def test_ik_brings_the_tip_back_onto_its_target_kinematically(ur5_scene):
    with World(ur5_scene) as world:
        group = world.kinematics.group_handle("UR5")
        assert world.kinematics.handle(group) == NOT_PERFORMED  # no joint in IK mode yet
        for name, q in zip(UR5, AWAY, strict=True):
            world.set_joint_mode(name, "ik")
            world.set_joint_position(name, q)
        assert gap(world)[0] > 0.05
        results = [world.kinematics.handle(group) for _ in range(4)]
        assert results[0] == FAIL and results[-1] == SUCCESS  # 3 iterations a resolution
        distance, angle = gap(world)
        assert distance < 0.0005 and angle < math.radians(0.1)


def test_hybrid_ik_drives_the_arm_motors_to_the_target_under_dynamics(ur5_scene):
    """The pick-and-place script's enableIk(true): joints in hybrid IK mode, the group handled
    by the main script's pass; the motors (max 180 deg/s) follow the IK solution."""
    with World(ur5_scene) as world:
        group = world.kinematics.group_handle("UR5")
        for name, q in zip(UR5, AWAY, strict=True):
            world.set_joint_mode(name, "passive")
            world.set_joint_position(name, q)
        for name in UR5:
            world.set_joint_mode(name, "ik", hybrid=True)
        world.kinematics.set_explicit_handling(group, False)
        assert world.kinematics.main_script_pass() == 1
        for _ in range(40):  # 2 s of 50 ms passes
            world.step(10)
            world.kinematics.handle(HANDLE_ALL_EXCEPT_EXPLICIT)
        assert gap(world)[0] < 0.002
        assert all(abs(world.joint_position(n)) < 0.05 for n in UR5)  # the saved pose


def test_config_for_tip_pose_finds_joint_values_that_put_the_tip_on_the_target(ur5_scene):
    with World(ur5_scene, seed=3) as world:
        group = world.kinematics.group_handle("UR5")
        config = world.kinematics.config_for_tip_pose(group, UR5, threshold=0.65, trials=200)
        assert config is not None
        again = World(ur5_scene, seed=3)
        try:  # same seed, same answer
            assert again.kinematics.config_for_tip_pose(group, UR5, 0.65, 200) == config
        finally:
            again.close()
        for name, q in zip(UR5, config, strict=True):
            world.set_joint_mode(name, "passive")
            world.set_joint_position(name, q)
        distance, angle = gap(world)
        assert distance < 0.0005 and angle < math.radians(0.1)


def test_unknown_group_names_and_handles_are_errors(ur5_scene):
    with World(ur5_scene) as world:
        with pytest.raises(KeyError):
            world.kinematics.group_handle("NoSuchGroup")
        with pytest.raises(KeyError):
            world.kinematics.handle(12345)
        assert world.kinematics.handle(world.kinematics.group_handle("UR5#")) in (
            NOT_PERFORMED,
            SUCCESS,
        )


def test_simik_environment_group_built_from_the_scene_solves_the_same_chain(ur5_scene):
    """simIK (4.2+): a script builds its own group from the scene's tip, target and base;
    every joint between base and tip takes part, whatever its mode."""
    from sims.ik_environment import IkEnvironment

    with World(ur5_scene) as world:
        env = IkEnvironment(world)
        group = env.create_group("arm")
        assert env.add_element_from_scene(group, "UR5", "UR5_ikTip", "UR5_ikTarget") == 1
        env.set_group_calculation(group, "damped_least_squares", 0.01, 10)
        env.set_element_precision(group, 1, 0.0005, math.radians(0.1))
        for name, q in zip(UR5, AWAY, strict=True):
            world.set_joint_mode(name, "passive")
            world.set_joint_position(name, q)
        results = [env.handle_group(group) for _ in range(4)]
        assert results[-1] == SUCCESS
        distance, angle = gap(world)
        assert distance < 0.0005 and angle < math.radians(0.1)
