"""Scene models become pybullet worlds: tree and paths, dynamics rules, joint modes, sensors.

Scenes here are built in Python (no course data needed); the repository's own XML scene and the
shipped 2W1A description are loaded from data/scenes/.
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest
from shared_data import shared

from sims.quiet import pybullet as p
from sims.scene.jsonfile import SceneJSONError, dumps, read_json
from sims.scene.model import (
    Dynamics,
    JointData,
    Mesh,
    Pose,
    ProximitySensorData,
    Scene,
    SceneObject,
    ShapeData,
    VisionSensorData,
)
from sims.scene.resolve import SceneFileError, open_scene
from sims.world import TreeEntry, World

REPO = Path(__file__).resolve().parents[1]
ROVER = REPO / "data" / "scenes" / "rover.simscene.xml"


def q_axis(axis, angle):
    s = math.sin(angle / 2)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(angle / 2))


WHEEL_AXIS = q_axis((1, 0, 0), -math.pi / 2)  # joint z along world +y


def box(handle, name, pos, size, parent=None, static=True, mass=1.0, **kw):
    dyn = kw.pop("dynamics", None) or Dynamics(
        static=static, mass=mass, inertia=(mass * 0.01,) * 3, friction=kw.pop("friction", None)
    )
    return SceneObject(
        handle,
        name,
        "shape",
        parent=parent,
        pose=Pose(pos, kw.pop("quat", (0.0, 0.0, 0.0, 1.0))),
        shape=ShapeData(
            meshes=(Mesh(primitive="cuboid", size=size, color=kw.pop("color", (0.5, 0.5, 0.5))),),
            dynamics=dyn,
        ),
        **kw,
    )


def floor(handle=1):
    return box(handle, "Floor", (0, 0, -0.01), (6, 6, 0.02), friction=1.0)


MOTOR = JointData(mode="velocity", cyclic=True, motor_enabled=True, max_force=2.0)


def cart_scene(motor=MOTOR):
    """Floor, a dynamic cart (model base) on two wheel motors, a static caster, a cone sensor
    looking ahead, a camera, a tip dummy, and a wall 1 m ahead."""
    objects = [
        floor(),
        box(2, "cart", (0, 0, 0.06), (0.2, 0.1, 0.04), static=False, mass=1.0, model_base=True),
    ]
    h = 3
    for side, y in (("left", 0.07), ("right", -0.07)):
        objects.append(
            SceneObject(
                h,
                f"{side}Motor",
                "joint",
                parent=2,
                pose=Pose((0.05, y, -0.02), WHEEL_AXIS),
                joint=motor,
            )
        )
        objects.append(
            SceneObject(
                h + 1,
                f"{side}Wheel",
                "shape",
                parent=h,
                shape=ShapeData(
                    meshes=(Mesh(primitive="cylinder", size=(0.08, 0.08, 0.02)),),
                    dynamics=Dynamics(static=False, mass=0.1, inertia=(1e-4,) * 3, friction=1.0),
                ),
            )
        )
        h += 2
    objects += [
        SceneObject(
            7,
            "caster",
            "shape",
            parent=2,
            pose=Pose((-0.08, 0, -0.04)),
            shape=ShapeData(
                meshes=(Mesh(primitive="sphere", size=(0.04,) * 3),),
                dynamics=Dynamics(static=True, friction=0.0),
            ),
        ),
        SceneObject(
            8,
            "sensor",
            "proximity_sensor",
            parent=2,
            pose=Pose((0.1, 0, 0.01), q_axis((0, 1, 0), math.pi / 2)),
            proximity_sensor=ProximitySensorData(volume="ray", range=0.8),
        ),
        box(9, "wall", (1.1, 0, 0.1), (0.1, 1.0, 0.2), color=(1.0, 0.0, 0.0)),
        SceneObject(10, "tip", "dummy", parent=2, pose=Pose((0.1, 0, 0.05)), alias="tip"),
        SceneObject(
            11,
            "eye",
            "vision_sensor",
            parent=2,
            pose=Pose((0.1, 0, 0.03), (0.5, 0.5, 0.5, 0.5)),
            vision_sensor=VisionSensorData(resolution=(32, 24), view_angle=math.radians(50)),
        ),
    ]
    return Scene(objects=tuple(objects), source="cart test scene")


def test_tree_lists_every_object_with_parents_and_kinds():
    with World(cart_scene()) as w:
        tree = w.tree()
        assert [e.handle for e in tree] == list(range(1, 12))
        by_name = {e.name: e for e in tree}
        assert by_name["leftWheel"] == TreeEntry(4, "leftWheel", "", 3, "shape")
        assert by_name["leftMotor"].parent == by_name["cart"].handle
        assert by_name["cart"].parent is None
        assert {e.kind for e in tree} == {
            "shape",
            "joint",
            "proximity_sensor",
            "dummy",
            "vision_sensor",
        }
        assert w.kind("sensor") == "proximity_sensor" and w.parent("tip") == 2


def test_find_resolves_names_and_object_paths():
    with World(cart_scene()) as w:
        assert w.find("leftMotor") == 3
        assert w.find("leftMotor#") == 3 and w.find("leftMotor#0") == 3
        assert w.find("leftMotor#1") is None
        assert w.find("/cart/leftMotor/leftWheel") == 4
        assert w.find("/cart/leftWheel") == 4  # a descendant when no child matches
        assert w.find("/cart/*[1]") == 5  # the second child of the cart
        assert w.find("/cart/leftMotor{0}") == 3
        assert w.find("./leftWheel", relative_to=3) == 4
        # without a calling object, ./ searches the scene (CoppeliaSim's getObjectFromPath)
        assert w.find("./leftWheel") == 4 and w.find(".") is None
        assert w.find("tip") == 10  # a bare alias
        assert w.find("/nothing") is None and w.find("/cart//x") is None


def test_saved_pose_frames_and_a_dynamic_body_resting_on_the_floor():
    with World(cart_scene()) as w:
        assert w.object_pose("leftWheel")[0] == pytest.approx((0.05, 0.07, 0.04), abs=1e-6)
        _, q = w.object_pose("leftMotor")
        z = p.getMatrixFromQuaternion(q)[2::3]
        assert z == pytest.approx((0.0, 1.0, 0.0), abs=1e-6)  # the joint axis is its frame's z
        w.advance(1.0)
        (x, y, z0), _ = w.object_pose("cart")
        assert abs(x) < 0.01 and abs(y) < 0.01 and z0 == pytest.approx(0.06, abs=0.005)


def test_velocity_motors_drive_the_cart_into_the_wall_and_the_sensor_sees_it():
    with World(cart_scene()) as w:
        assert w.proximity("sensor") is None  # the wall is 1 m away, range 0.8 m
        for m in ("leftMotor", "rightMotor"):
            w.set_joint_target_velocity(m, 5.0)  # 0.2 m/s on 40 mm wheels
        w.advance(2.0)
        assert w.joint_velocity("leftMotor") == pytest.approx(5.0, abs=0.1)
        (x, _, _), _ = w.object_pose("cart")
        assert x == pytest.approx(0.4, abs=0.05)
        d = w.proximity("sensor")
        assert d is not None and d == pytest.approx(1.05 - 0.1 - x, abs=0.02)
        tip = w.object_pose("tip")[0]
        assert tip[0] == pytest.approx(x + 0.1, abs=0.01)  # the dummy rides on the cart
        w.advance(6.0)
        (x, _, _), _ = w.object_pose("cart")
        assert x < 1.05 - 0.1  # stopped by the wall


def test_vision_sensor_sees_the_red_wall():
    from sims.scene.camera import image_for_remote_api, render_sensor

    with World(cart_scene()) as w:
        rgb = render_sensor(w, "eye")
        assert rgb.shape == (24, 32, 3)
        centre = rgb[10:14, 14:18].astype(int)
        assert centre[..., 0].mean() > 150 and centre[..., 1].mean() < 80  # red, ahead
        assert rgb[0, :, 1].mean() > rgb[12, :, 1].mean() + 50  # above the wall: not red
        resolution, flat = image_for_remote_api(rgb, grey=False)
        assert resolution == [32, 24] and len(flat) == 32 * 24 * 3
        assert min(flat) >= -128 and max(flat) <= 127
        bottom_first = np.array(flat, dtype=np.int16).astype(np.uint8).reshape(24, 32, 3)
        assert (bottom_first[::-1] == rgb).all()


def test_position_control_reaches_targets_at_the_saved_speed_and_range():
    joint = JointData(
        mode="position",
        motor_enabled=True,
        control_enabled=True,
        minimum=-1.0,
        range=2.0,
        max_force=50.0,
        max_velocity=math.radians(45),
        position=0.5,
        target=0.5,
    )
    arm = (
        floor(),
        box(2, "base", (0, 0, 0.1), (0.1, 0.1, 0.2)),
        SceneObject(3, "hinge", "joint", parent=2, pose=Pose((0, 0, 0.15)), joint=joint),
        box(4, "arm", (0.1, 0, 0.02), (0.2, 0.02, 0.02), parent=3, static=False, mass=0.2),
    )
    with World(Scene(objects=arm)) as w:
        assert w.joint_position("hinge") == pytest.approx(0.5, abs=1e-6)
        # children hang on the joint frame turned by the saved position
        x, y, _ = w.object_pose("arm")[0]
        assert (x, y) == pytest.approx((0.1 * math.cos(0.5), 0.1 * math.sin(0.5)), abs=1e-4)
        w.set_joint_target_position("hinge", -0.5)
        w.advance(0.5)
        halfway = w.joint_position("hinge")
        assert halfway == pytest.approx(0.5 - math.radians(45) * 0.5, abs=0.05)  # speed capped
        w.advance(2.0)
        assert w.joint_position("hinge") == pytest.approx(-0.5, abs=0.02)
        w.set_joint_target_position("hinge", 3.0)  # beyond the range: clamped to 1.0
        w.advance(3.0)
        assert w.joint_position("hinge") == pytest.approx(1.0, abs=0.03)


def _hinge_scene(mode, **joint):
    data = JointData(mode=mode, cyclic=True, motor_enabled=mode != "free", **joint)
    return Scene(
        objects=(
            box(1, "base", (0, 0, 1.0), (0.1, 0.1, 0.1)),
            SceneObject(
                2,
                "hinge",
                "joint",
                parent=1,
                pose=Pose((0, 0, 0), q_axis((1, 0, 0), math.pi / 2)),
                joint=data,
            ),
            box(3, "bob", (0.3, 0, 0), (0.05, 0.05, 0.05), parent=2, static=False, mass=1.0),
        )
    )


def test_free_passive_and_spring_joints():
    free = JointData(mode="velocity", cyclic=True, motor_enabled=False)
    with World(
        Scene(
            objects=_hinge_scene("velocity").objects[:1]
            + (
                SceneObject(
                    2,
                    "hinge",
                    "joint",
                    parent=1,
                    pose=Pose((0, 0, 0), q_axis((1, 0, 0), math.pi / 2)),
                    joint=free,
                ),
            )
            + _hinge_scene("velocity").objects[2:]
        )
    ) as w:
        w.advance(1.0)  # a horizontal pendulum with the motor off swings down
        assert abs(w.joint_position("hinge")) > 0.5
    with World(_hinge_scene("passive")) as w:
        w.advance(1.0)  # passive (kinematic): stays where it is
        assert w.joint_position("hinge") == pytest.approx(0.0, abs=1e-3)
        w.set_joint_position("hinge", 0.7)
        w.advance(0.5)
        assert w.joint_position("hinge") == pytest.approx(0.7, abs=1e-3)
    with World(_hinge_scene("spring", spring_k=20.0, spring_c=2.0, max_force=100.0)) as w:
        w.advance(3.0)  # sags under gravity to where the spring holds it: k q = m g l cos q
        q = w.joint_position("hinge")
        assert q != pytest.approx(0.0, abs=0.05)
        assert 20.0 * abs(q) == pytest.approx(9.81 * 0.3 * math.cos(q), rel=0.1)


def test_dynamic_shape_under_a_dynamic_shape_is_a_separate_body():
    objects = (
        floor(),
        box(2, "table", (0, 0, 0.3), (0.4, 0.4, 0.02), static=False, mass=2.0),
        box(3, "cup", (0.5, 0, 0.5), (0.05, 0.05, 0.05), parent=2, static=False, mass=0.1),
        box(4, "label", (0, 0, 0.05), (0.02, 0.02, 0.02), parent=2, static=True),
    )
    with World(Scene(objects=objects)) as w:
        w.advance(1.0)
        # the cup is not held by the table: it falls to the floor on its own
        assert w.object_pose("cup")[0][2] == pytest.approx(0.025, abs=0.005)
        assert w.object_pose("table")[0][2] == pytest.approx(0.01, abs=0.005)
        # a static shape under a dynamic one rides along
        assert w.object_pose("label")[0][2] == pytest.approx(0.06, abs=0.005)


def eye(handle=4):
    """A 2 m proximity sensor 0.1 m above the origin, looking along +x."""
    return SceneObject(
        handle,
        "eye",
        "proximity_sensor",
        pose=Pose((0, 0, 0.1), q_axis((0, 1, 0), math.pi / 2)),
        proximity_sensor=ProximitySensorData(range=2.0),
    )


def test_non_respondable_shapes_fall_through_but_sensors_see_them():
    ghost = Dynamics(static=False, respondable=False, mass=1.0, inertia=(0.01,) * 3)
    objects = (
        floor(),
        box(2, "ghost", (0, 0, 0.5), (0.1, 0.1, 0.1), dynamics=ghost),
        box(
            3,
            "ghost_wall",
            (1.0, 0, 0.1),
            (0.1, 1, 0.2),
            dynamics=Dynamics(static=True, respondable=False),
        ),
        eye(),
    )
    with World(Scene(objects=objects)) as w:
        assert w.proximity("eye") == pytest.approx(0.95, abs=0.01)
        w.advance(1.0)
        assert w.object_pose("ghost")[0][2] < -1.0


def test_respondable_masks_decide_which_shapes_collide():
    def falling(mask_a, mask_b):
        objects = (
            box(
                1,
                "ground",
                (0, 0, -0.01),
                (2, 2, 0.02),
                dynamics=Dynamics(static=True, respondable_mask=mask_a),
            ),
            box(
                2,
                "block",
                (0, 0, 0.2),
                (0.1, 0.1, 0.1),
                dynamics=Dynamics(
                    static=False, mass=1, inertia=(0.01,) * 3, respondable_mask=mask_b
                ),
            ),
        )
        with World(Scene(objects=objects), floor=False) as w:
            w.advance(1.0)
            return w.object_pose("block")[0][2]

    assert falling(0xFFFF, 0xFFFF) == pytest.approx(0.05, abs=0.005)
    assert falling(0xFF00, 0x00FF) < -1.0  # no common bit: passes through
    assert falling(0x0100, 0x01FF) == pytest.approx(0.05, abs=0.005)  # different models: high byte


def test_reset_rebuilds_the_saved_scene_and_handles_stay():
    with World(cart_scene()) as w:
        handles = [e.handle for e in w.tree()]
        w.set_joint_target_velocity("leftMotor", 8.0)
        w.advance(1.0)
        w.reset()
        assert [e.handle for e in w.tree()] == handles
        assert w.object_pose("cart")[0] == pytest.approx((0, 0, 0.06), abs=1e-6)


def test_json_description_round_trips_and_bad_files_are_named(tmp_path):
    scene = cart_scene()
    path = tmp_path / "cart.scene.json"
    path.write_text(dumps(scene), encoding="utf-8")
    again = read_json(path)
    assert [(o.name, o.kind, o.parent) for o in again.objects] == [
        (o.name, o.kind, o.parent) for o in scene.objects
    ]
    assert (
        json.loads(dumps(again))["scene"]["objects"] == json.loads(dumps(scene))["scene"]["objects"]
    )
    assert again.source.startswith(str(path)) and "cart test scene" in again.source
    with World(path) as w:
        assert w.find("/cart/tip") == 10
    bad = tmp_path / "bad.scene.json"
    bad.write_text(
        '{"format": "sitegen-scene/1", "scene": {"objects": [{"handle": 1, "nme": "x"}]}}'
    )
    with pytest.raises(SceneJSONError, match=r"bad.scene.json.objects\[0\]: unknown field 'nme'"):
        read_json(bad)
    with pytest.raises(SceneFileError, match="nope.ttt: no such scene file"):
        open_scene(str(tmp_path / "nope.ttt"))


def test_repository_rover_scene_loads_from_xml():
    with World(ROVER) as w:
        names = {e.name for e in w.tree()}
        assert {"Rover", "LeftMotor", "RightWheel", "FrontSensor", "Camera", "Mast"} <= names
        assert w.find("/Rover/LeftMotor") == w.handle("LeftMotor")
        assert w.model.robot == "Rover"
        w.set_joint_target_velocity("LeftMotor", 6.0)
        w.set_joint_target_velocity("RightMotor", 6.0)
        start = w.object_pose("Rover")[0]
        w.advance(2.0)
        end = w.object_pose("Rover")[0]
        assert end[0] - start[0] == pytest.approx(0.48, abs=0.05)  # 6 rad/s x 40 mm x 2 s
        frame = w.render(64, 48)
        assert frame.shape == (48, 64, 3) and frame.std() > 5


def test_bundled_2w1a_comes_from_the_shipped_scene_description():
    with World("2w1a") as w:
        assert "2w1a/2w1a.ttt" in w.source.source  # derived from the course scene
        joints = {j.name: j for j in w.model.joints}
        assert joints["LeftWheelJoint"].max_force == pytest.approx(0.01)  # not 1 N*m
        assert joints["ShoulderMotor"].max_velocity == pytest.approx(math.radians(60), rel=1e-3)
        assert joints["ElbowMotor"].max_velocity == pytest.approx(math.radians(360), rel=1e-3)
        deg = [
            math.degrees(w.joint_position(j)) for j in ("ShoulderMotor", "ElbowMotor", "WristMotor")
        ]
        assert deg == pytest.approx([150, 120, 250], abs=1e-4)
        for name, at in {
            "ElbowMotor": (0.1303, 0, 0.0798),
            "WristMotor": (0.1930, 0, 0.1160),
        }.items():
            assert w.object_pose(name)[0] == pytest.approx(at, abs=1e-3)  # the reference's figures


def test_cli_names_what_the_scene_lacks_and_strict_fails(tmp_path):
    import subprocess
    import sys

    script = tmp_path / "student.py"
    script.write_text(
        "import vrep\n"
        "cid = vrep.simxStart('127.0.0.1', 19997, True, True, 5000, 5)\n"
        "print(vrep.simxGetObjectHandle(cid, 'LeftMotr', vrep.simx_opmode_blocking))\n"
        "print(vrep.simxGetObjectHandle(cid, '/Rover/Mast', vrep.simx_opmode_blocking)[0])\n"
        "print(vrep.simxReadForceSensor(cid, 1, vrep.simx_opmode_blocking)[0])\n",
        encoding="utf-8",
    )
    command = [sys.executable, "-m", "sims.remote_api", "run", str(script), "--scene", str(ROVER)]
    proc = subprocess.run(command, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert proc.returncode == 0, proc.stderr
    # CoppeliaSim's return codes (handle 1 is no force sensor: a remote error)
    assert proc.stdout.splitlines() == ["(8, 0)", "0", "8"]
    assert "student.py:3: 'LeftMotr' (nearest in the scene: LeftMotor" in proc.stderr
    strict = subprocess.run([*command, "--strict"], capture_output=True, text=True, cwd=REPO)
    assert strict.returncode == 3 and "--strict" in strict.stderr
    missing = subprocess.run(
        [*command[:-1], str(tmp_path / "none.ttt")], capture_output=True, text=True, cwd=REPO
    )
    assert missing.returncode == 2 and "none.ttt: no such scene file" in missing.stderr
    assert "Traceback" not in missing.stderr


def test_egl_draws_the_scene_look_not_the_physics_shapes():
    """The 2W1A is white with grey wheels and arm; its respondable shapes are hidden in the
    scene. pybullet's EGL renderer would draw a link without a visual shape from its collision
    shape in its own palette (green, yellow, red), over the scene's look."""
    with World("2w1a", render_with="auto") as w:
        if w.renderer != "egl":
            pytest.skip("EGL is not available here (the TinyRenderer fallback draws visuals only)")
        for _ in range(10):
            w.step()
        rgb = w.render(320, 240).astype(int)
    r, g, b = rgb[..., 0], rgb[..., 1], rgb[..., 2]
    palette = ((g - r > 60) & (g - b > 60)) | ((r - b > 120) & (g - b > 100))  # green or yellow
    assert palette.sum() < 20, f"{palette.sum()} pixels in pybullet's collision-shape colours"


@pytest.mark.parametrize("renderer", ["auto", "tinyrenderer"])
def test_the_floor_outline_is_not_drawn_over_the_floor(renderer):
    """The course floor's visible element holds its two tile colours and a black quad over the
    whole floor that CoppeliaSim draws as a wireframe (its outline). Drawn filled, it fights
    the tiles for depth: black streaks with EGL, black patches with TinyRenderer."""
    scene = open_scene("2w1a")
    floor = next(o for o in scene.objects if o.name == "ResizableFloor_5_25_visibleElement")
    assert [m.wireframe for m in floor.shape.meshes] == [False, False, True]
    with World(scene, render_with=renderer) as w:
        for _ in range(10):
            w.step()
        rgb = w.render(320, 240)
        used = w.renderer
    black = (rgb.max(axis=2) < 8).sum()
    assert black < 30, f"{black} black pixels ({used})"


def test_proximity_sensors_see_only_detectable_shapes():
    """CoppeliaSim's models keep their respondable shapes undetectable (special property bits
    clear) and their visible shapes detectable: a sensor sees through the first."""
    objects = (
        floor(),
        box(2, "hidden_wall", (0.5, 0, 0.1), (0.1, 1, 0.2), detectable=False),
        box(3, "seen_wall", (1.0, 0, 0.1), (0.1, 1, 0.2)),
        eye(),
    )
    with World(Scene(objects=objects)) as w:
        assert w.proximity("eye") == pytest.approx(0.95, abs=0.01)
    seen = dataclasses.replace(objects[1], detectable=True)
    with World(Scene(objects=(objects[0], seen, *objects[2:]))) as w:
        assert w.proximity("eye") == pytest.approx(0.45, abs=0.01)


def test_course_scenes_read_which_shapes_are_detectable():
    pioneer = open_scene(shared("data", "scenes", "course", "Pioneer_p3dx.ttt"))
    kinds = {o.name: o.detectable for o in pioneer.objects if o.kind == "shape"}
    assert kinds["Pioneer_p3dx_leftWheel"] is False  # respondable: Omp 0
    assert kinds["Pioneer_p3dx_leftWheel_visible"] is True
    assert kinds["ResizableFloor_5_25_element"] is False
    xml = shared("data", "scenes", "course", "fanuc_m710ic_50_pick_and_place.simscene.xml")
    ttt = xml.with_name("fanuc_m710ic_50_pick_and_place.ttt")
    assert {o.name: o.detectable for o in open_scene(xml).objects} == {
        o.name: o.detectable for o in open_scene(ttt).objects
    }
