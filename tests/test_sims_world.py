"""World contract: names/handles, CoppeliaSim joint convention, arm control, independence."""

from __future__ import annotations

import math

import pytest

from sims.quiet import pybullet as p
from sims.world import World

ARM = ("ShoulderMotor", "ElbowMotor", "WristMotor")
TOLERANCE_DEG = 3.0


def test_names_and_handles_are_stable_across_reset():
    with World("2w1a") as w:
        names = w.names()
        for required in ("2W1A", "LeftWheelJoint", "RightWheelJoint", *ARM):
            assert required in names
        handles = {n: w.handle(n) for n in names}
        assert len(set(handles.values())) == len(names)
        assert all(w.name_of(h) == n for n, h in handles.items())
        assert w.handle("nope") is None and w.name_of(0) is None
        assert w.is_joint(w.handle("ElbowMotor")) and not w.is_joint(w.handle("2W1A"))
        w.advance(0.5)
        w.reset()
        assert w.time == 0.0
        assert {n: w.handle(n) for n in w.names()} == handles


def test_saved_pose_in_coppeliasim_convention():
    with World("2w1a") as w:
        degrees = [math.degrees(w.joint_position(j)) for j in ARM]
        assert degrees == pytest.approx([150.0, 120.0, 250.0], abs=1e-4)  # saved as float32
        (x, y, z), _ = w.object_pose("2W1A")
        assert (x, y, z) == pytest.approx((-0.0201, 0.0, 0.070), abs=1e-4)  # 2w1a.ttt: -0.020125
        for joint, deg in zip(ARM, (150.0, 120.0, 250.0), strict=True):
            # hold the saved pose: the scene's saved targets (12, 152, 3 deg) move the arm
            w.set_joint_target_position(joint, math.radians(deg))
        w.advance(0.5)
        hand = next(o for o in w.model.objects if o.name == "HandRespondable")
        foot_bottom = p.getAABB(hand.body, hand.link, physicsClientId=w.client_id)[0][2]
        assert abs(foot_bottom) < 0.003  # the hand's foot rests on the floor
        assert [math.degrees(w.joint_position(j)) for j in ARM] == pytest.approx(
            [150.0, 120.0, 250.0], abs=TOLERANCE_DEG
        )


# (68, 291, 32) folds the arm into the body: the scene's self-collision stops it (see
# tests/test_scene_world_course.py); these targets are free
@pytest.mark.parametrize("targets", [(68, 200, 32), (130, 60, 253), (230, 241, 194)])
def test_arm_reaches_commanded_targets(targets):
    with World("2w1a") as w:
        for joint, deg in zip(ARM, targets, strict=True):
            w.set_joint_target_position(joint, math.radians(deg))
        w.advance(5.0)
        reached = [math.degrees(w.joint_position(j)) for j in ARM]
        assert reached == pytest.approx(list(targets), abs=TOLERANCE_DEG)


def test_targets_are_clamped_to_the_joint_range():
    with World("2w1a") as w:
        w.set_joint_target_position("ElbowMotor", math.radians(400))
        w.advance(3.0)
        assert math.degrees(w.joint_position("ElbowMotor")) <= 300.0 + TOLERANCE_DEG


def _trace(world: World, steps: int) -> list[tuple[float, ...]]:
    out = []
    for _ in range(steps):
        world.step(20)
        (x, y, z), _ = world.object_pose("2W1A")
        out.append((x, y, z, world.joint_position("WristMotor")))
    return out


def _command(world: World) -> None:
    for joint, deg in zip(ARM, (40, 250, 100), strict=True):
        world.set_joint_target_position(joint, math.radians(deg))


def test_two_worlds_side_by_side_do_not_disturb_each_other():
    with World("2w1a") as alone:
        _command(alone)
        expected = _trace(alone, 50)
    with World("2w1a") as a, World("cart") as b, World("2w1a") as c:
        _command(a)
        b.set_joint_target_velocity("left_m", 2.0)
        c.set_joint_target_position("ShoulderMotor", 0.0)
        got = []
        for _ in range(50):
            got += _trace(a, 1)
            b.step(7)
            c.step(13)
        assert got == expected


def test_cart_reverses_straight_along_its_heading():
    with World("cart", start=(0.0, 0.0, 30.0)) as w:
        for motor in ("left_m", "right_m"):
            w.set_joint_target_velocity(motor, -1.0)
        w.advance(5.0)
        (x, y, _), _ = w.object_pose("cart")
        heading = math.radians(30.0)
        along = x * math.cos(heading) + y * math.sin(heading)
        across = -x * math.sin(heading) + y * math.cos(heading)
        assert along == pytest.approx(-5.0 * 0.028, rel=0.1)  # 1 rad/s * 28 mm wheel radius
        assert abs(across) < 0.005
        assert w.joint_velocity("left_m") == pytest.approx(-1.0, abs=0.02)


def test_proximity_sensor_sees_the_wall_ahead():
    with World("cart", obstacles=0, start=(1.2, 0.0, 0.0)) as w:
        d = w.proximity("Proximity_sensor")
        assert d is not None and d == pytest.approx(0.253, abs=0.01)
    with World("cart", obstacles=0) as w:
        assert w.proximity("Proximity_sensor") is None  # 1.45 m away: out of range


def test_render_returns_rgb_image_and_close_is_idempotent():
    w = World("cart")
    image = w.render(64, 48)
    assert image.shape == (48, 64, 3) and image.dtype.name == "uint8"
    assert w.renderer in ("egl", "tinyrenderer")
    w.close()
    w.close()
    with pytest.raises(RuntimeError):
        w.step()


def test_only_one_world_per_process_uses_egl():
    """The EGL plugin's state is process-wide: a second EGL World would spoil the first's frames."""
    with World("2w1a", render_with="egl") as first, World("cart", render_with="egl") as second:
        first.render(64, 48)
        before = first.render(64, 48).tobytes()
        second.render(64, 48)
        assert second.renderer == "tinyrenderer"
        assert first.render(64, 48).tobytes() == before
