"""The scene readers on the course's own scene files (``../shared/data/scenes``): every scene
loads, holds the objects its scripts look up, and the FANUC scene saved both ways reads the same
from the binary file as from its XML (the XML is the ground truth for the binary decoder)."""

from __future__ import annotations

import json
import math
import re
import struct
from pathlib import Path

import numpy as np
import pytest
from shared_data import shared

from sims.scene import ttt_huffman
from sims.scene.load import load_scene
from sims.scene.model import Pose, Scene, SceneObject
from sims.scene.show import main as scene_main

# each scene with the scripts written for it (SOURCES.md and the issue say which goes with which)
SCENES = {
    "vrep_remoteapi_ex/2w1a/2w1a.ttt": ["vrep_remoteapi_ex/2w1a/2w1a.py"],
    "vrep_remoteapi_ex/bubble/bubbleRob_remoteAPI.ttt": [
        "vrep_remoteapi_ex/bubble/bubbleRob_remoteAPI.py"
    ],
    "vrep_remoteapi_ex/onelink/one_link_robot_remoteAPI.ttt": [
        "vrep_remoteapi_ex/onelink/one_link_robot_remoteAPI.py"
    ],
    "vrep_remoteapi_ex/fourbar/solvespace_fourbar.ttt": [
        "vrep_remoteapi_ex/fourbar/fourbar_remoteAPI.py"
    ],
    "vrep_remoteapi_ex/fourbar/solvespace_fourbar_with_motor_on.ttt": [
        "vrep_remoteapi_ex/fourbar/fourbar_remoteAPI.py"
    ],
    "vrep_remoteapi_ex/pioneer/Pioneer.ttt": ["vrep_remoteapi_ex/pioneer/pioneer.py"],
    "vrep_remoteapi_ex/pioneer/testAllComponents.ttt": [
        "vrep_remoteapi_ex/pioneer/testallcomponent.py"
    ],
    "vrep_remoteapi_ex/vrep_ex/motionPlanningServerDemo.ttt": [
        "vrep_remoteapi_ex/vrep_ex/pathPlanningTest.py"
    ],
    "vrep_remoteapi_ex/vrep_ex/remoteApiCommandServerExample.ttt": [],
    "course/Pioneer_p3dx.ttt": [],
    "course/two_wheeler.ttt": [],
    "course/simpleLineFollower_api.ttt": ["course/vrep_linefollower.py"],
    "course/Scene_CheckPoint1.ttt": ["course/Scene_CheckPoint1.py"],
    "course/fanuc_m710ic_50_pick_and_place.ttt": [],
    "course/fanuc_m710ic_50_pick_and_place.simscene.xml": [],
    "course/tablefootball.ttt": ["course/AvsB.py"],
    "course2/Scene_CheckPoint3.ttt": ["course2/Scene_CheckPoint3.py"],
    "course2/jansen_solvespace.ttt": [],
    "course2/invertedPendulum.ttt": [],
    "course2/ur5WithRg2Grasping.ttt": [],
}
# names passed to simxGetObjectHandle, or to the Pioneer package's joint/sensor helpers
LOOKUPS = re.compile(
    r"""(?:GetObjectHandle\(\s*[\w.]+\s*,|\.(?:with_velocity_control|with_position_control|"""
    r"""passive|spherical|spring|proximity|vision|force)\()\s*['"]([^'"]+)['"]"""
)


def scenes_dir() -> Path:
    return shared("data", "scenes")


def looked_up(script: Path) -> set[str]:
    return {m.group(1).rstrip("#") for m in LOOKUPS.finditer(script.read_text(errors="replace"))}


def test_every_course_scene_is_listed():
    root = scenes_dir()
    found = {
        str(p.relative_to(root))
        for p in root.rglob("*")
        if p.suffix == ".ttt" or p.name.endswith(".simscene.xml")
    }
    assert found == set(SCENES)


@pytest.mark.parametrize("rel", sorted(SCENES))
def test_scene_loads_and_has_what_its_scripts_look_up(rel, capsys):
    root = scenes_dir()
    assert scene_main(["show", str(root / rel), "--json"]) == 0
    captured = capsys.readouterr()
    assert captured.err == ""
    doc = json.loads(captured.out)
    names = {o["name"] for o in doc["objects"]}
    assert len(names) == len(doc["objects"]) > 5  # names are unique in a scene
    wanted: set[str] = set()
    for script in SCENES[rel]:
        wanted |= looked_up(root / script)
    assert wanted <= names, f"missing: {sorted(wanted - names)}"
    if SCENES[rel]:
        assert wanted, "the scripts' lookups were not found: the pattern is out of date"
    handles = {o["handle"] for o in doc["objects"]}
    assert all(o["parent"] is None or o["parent"] in handles for o in doc["objects"])


# --- the FANUC scene, saved as .ttt and as .simscene.xml ------------------------------------


def _rot(q: tuple[float, ...]) -> np.ndarray:
    x, y, z, w = q
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def _same_rotation(a: Pose, b: Pose, tol: float = 1e-4) -> bool:
    return bool(np.abs(_rot(a.quaternion) - _rot(b.quaternion)).max() < tol)


def _mesh_points(obj: SceneObject) -> list[np.ndarray]:
    out = []
    for m in obj.shape.meshes:
        if m.vertices and m.primitive is None:  # a .ttt keeps a primitive's triangles too
            v = np.array(m.vertices).reshape(-1, 3)
            out.append(v @ _rot(m.local.quaternion).T + np.array(m.local.position))
    return sorted(out, key=lambda p: (len(p), tuple(p.min(axis=0).round(4))))


@pytest.fixture(scope="module")
def fanuc() -> tuple[Scene, Scene]:
    base = shared("data", "scenes", "course") / "fanuc_m710ic_50_pick_and_place"
    return load_scene(f"{base}.ttt"), load_scene(f"{base}.simscene.xml")


def test_fanuc_binary_and_xml_have_the_same_tree(fanuc):
    binary, xml = fanuc
    b = {o.name: o for o in binary.objects}
    x = {o.name: o for o in xml.objects}
    assert set(b) == set(x)
    for name, xo in x.items():
        bo = b[name]
        assert bo.kind == xo.kind, name
        parent_b = binary.by_handle()[bo.parent].name if bo.parent is not None else None
        parent_x = xml.by_handle()[xo.parent].name if xo.parent is not None else None
        assert parent_b == parent_x, name
        if name == "DefaultCamera":  # the view was moved between the two saves
            continue
        assert bo.pose.position == pytest.approx(xo.pose.position, abs=1e-5), name
        assert _same_rotation(bo.pose, xo.pose), name
        assert bo.dummy == xo.dummy, name
    assert binary.gravity == pytest.approx(xml.gravity)
    assert binary.time_step == pytest.approx(xml.time_step)
    # the customization script of the floor, in both (the XML format has no main script)
    custom = [s for s in binary.scripts if s.kind == "customization"]
    assert [s.text.strip() for s in custom] == [s.text.strip() for s in xml.scripts]
    assert binary.by_handle()[custom[0].object].name == "ResizableFloor_5_25"


def test_fanuc_binary_and_xml_have_the_same_shapes_and_dynamics(fanuc):
    binary, xml = fanuc
    b = {o.name: o for o in binary.objects}
    shapes = [o for o in xml.objects if o.kind == "shape"]
    assert len(shapes) == 9
    for xo in shapes:
        bo = b[xo.name]
        bd, xd = bo.shape.dynamics, xo.shape.dynamics
        assert (bd.static, bd.respondable, bd.respondable_mask) == (
            xd.static,
            xd.respondable,
            xd.respondable_mask,
        )
        assert bd.mass == pytest.approx(xd.mass, rel=1e-6)
        assert bd.inertia == pytest.approx(xd.inertia, rel=1e-4)
        assert bd.inertia_frame.position == pytest.approx(xd.inertia_frame.position, abs=1e-5)
        assert bd.friction == pytest.approx(xd.friction, abs=1e-6)
        assert bo.shape.compound == xo.shape.compound
        assert len(bo.shape.meshes) == len(xo.shape.meshes)
        prims_b = sorted((m.primitive or "", m.size) for m in bo.shape.meshes)
        prims_x = sorted((m.primitive or "", m.size) for m in xo.shape.meshes)
        assert [p for p, _ in prims_b] == [p for p, _ in prims_x]
        for (_, sb), (_, sx) in zip(prims_b, prims_x, strict=True):
            assert sb == pytest.approx(sx, abs=1e-6)
        # the XML holds colours as 0-255 integers (CoppeliaSim truncates)
        colors_b = sorted(m.color for m in bo.shape.meshes)
        colors_x = sorted(m.color for m in xo.shape.meshes)
        for cb, cx in zip(colors_b, colors_x, strict=True):
            assert cb == pytest.approx(cx, abs=1.01 / 255)
        # mesh vertices, put in the shape frame, cover the same points
        for pb, px in zip(_mesh_points(bo), _mesh_points(xo), strict=True):
            assert pb.shape == px.shape, xo.name
            assert pb.min(axis=0) == pytest.approx(px.min(axis=0), abs=2e-4)
            assert pb.max(axis=0) == pytest.approx(px.max(axis=0), abs=2e-4)
            assert pb.mean(axis=0) == pytest.approx(px.mean(axis=0), abs=2e-4)


# --- the 2W1A, against the reference geometry (../shared/reference/2w1a-robot.md) -----------


def _world(scene: Scene, obj: SceneObject) -> tuple[np.ndarray, np.ndarray]:
    rot, pos = np.eye(3), np.zeros(3)
    chain = []
    cur: SceneObject | None = obj
    table = scene.by_handle()
    while cur is not None:
        chain.append(cur)
        cur = table.get(cur.parent) if cur.parent is not None else None
    for o in reversed(chain):
        pos = pos + rot @ np.array(o.pose.position)
        rot = rot @ _rot(o.pose.quaternion)
        if o.joint is not None and o is not obj and o.joint.kind == "revolute":
            # a joint's children hang from its frame turned by the joint's position
            half = o.joint.position / 2
            rot = rot @ _rot((0.0, 0.0, math.sin(half), math.cos(half)))
    return rot, pos


def test_2w1a_matches_the_reference_description():
    scene = load_scene(scenes_dir() / "vrep_remoteapi_ex/2w1a/2w1a.ttt")
    by = {o.name: o for o in scene.objects}
    body_rot, body_pos = _world(scene, by["2W1A"])
    assert body_pos == pytest.approx((-0.0201, 0, 0.070), abs=1e-3)
    assert body_rot[:, 2] == pytest.approx((1, 0, 0), abs=1e-3)  # its z axis along world +x
    body = by["2W1A"].shape.dynamics
    assert (body.static, body.respondable, body.mass) == (
        False,
        True,
        pytest.approx(0.560, abs=1e-3),
    )
    for name, y in (("LeftWheel", 0.035), ("RightWheel", -0.035)):
        _rot_w, pos = _world(scene, by[name])
        assert pos == pytest.approx((0.050, y, 0.040), abs=1e-3), name
        (mesh,) = by[name].shape.meshes
        assert (mesh.primitive, mesh.size) == (
            "cylinder",
            pytest.approx((0.08, 0.08, 0.01), abs=1e-6),
        )
        assert by[name].shape.dynamics.mass == pytest.approx(0.402, abs=1e-3)
        joint = by[name + "Joint"].joint
        assert (joint.mode, joint.motor_enabled, joint.control_enabled) == ("velocity", True, False)
        assert (joint.target_velocity, joint.max_force) == (0.0, pytest.approx(0.01))
    for name, pos, saved in (
        ("ShoulderMotor", (0.0675, 0, 0.090), 150),
        ("ElbowMotor", (0.1303, 0, 0.0798), 120),
        ("WristMotor", (0.1930, 0, 0.1160), 250),
    ):
        assert _world(scene, by[name])[1] == pytest.approx(pos, abs=1e-3), name
        j = by[name].joint
        assert (j.kind, j.mode, j.cyclic) == ("revolute", "position", False)
        assert math.degrees(j.minimum) == pytest.approx(0, abs=1e-4)
        assert math.degrees(j.minimum + j.range) == pytest.approx(300, abs=1e-4)
        assert math.degrees(j.position) == pytest.approx(saved, abs=1e-4)
        assert (j.p_gain, j.i_gain, j.d_gain) == pytest.approx((0.1, 0, 0))
        assert j.max_force == pytest.approx(2.5)
    masses = {
        n: by[n].shape.dynamics.mass
        for n in ("ArmRespondable", "ForearmRespondable", "HandRespondable")
    }
    assert masses == pytest.approx(
        {"ArmRespondable": 0.05, "ForearmRespondable": 0.15, "HandRespondable": 0.10}
    )
    # primitives sit centred on their mesh frame: the body cube and the hand's foot sphere
    cube = next(m for m in by["2W1A"].shape.meshes if m.primitive == "cuboid")
    assert body_pos + body_rot @ np.array(cube.local.position) == pytest.approx(
        (0.0435, 0, 0.070), abs=1e-3
    )
    hand_rot, hand_pos = _world(scene, by["HandRespondable"])
    foot = next(m for m in by["HandRespondable"].shape.meshes if m.primitive == "sphere")
    assert foot.size == pytest.approx((0.01, 0.01, 0.01), abs=1e-6)
    assert hand_pos + hand_rot @ np.array(foot.local.position) == pytest.approx(
        (0.1845, 0, 0.0046), abs=1e-3
    )
    assert scene.gravity == pytest.approx((0, 0, -9.81), abs=1e-6)
    assert scene.time_step == pytest.approx(0.05)


def test_table_decoder_agrees_with_bit_by_bit_decoding_on_a_real_scene():
    data = (scenes_dir() / "vrep_remoteapi_ex/bubble/bubbleRob_remoteAPI.ttt").read_bytes()
    (size,) = struct.unpack_from("<i", data, 13)
    body = data[1021:]
    codes, start = ttt_huffman._read_tree(body)
    assert ttt_huffman.decompress(body, size) == ttt_huffman._decompress_slow(
        body, size, codes, start
    )


def test_scripts_are_extracted_with_their_objects():
    scene = load_scene(scenes_dir() / "vrep_remoteapi_ex/bubble/bubbleRob_remoteAPI.ttt")
    table = scene.by_handle()
    kinds = sorted(
        (s.kind, table[s.object].name if s.object is not None else None) for s in scene.scripts
    )
    assert kinds == [
        ("child", "bubbleRob"),
        ("customization", "ResizableFloor_5_25"),
        ("main", None),
    ]
    child = next(s for s in scene.scripts if s.kind == "child")
    assert "simExtRemoteApiStart(19999)" in child.text and child.threaded


def test_four_bar_closes_its_loop_with_linked_dummies():
    scene = load_scene(scenes_dir() / "vrep_remoteapi_ex/fourbar/solvespace_fourbar.ttt")
    by = {o.name: o for o in scene.objects}
    a, b = by["Dummy"], by["Dummy0"]
    assert a.dummy.linked_to == b.handle and b.dummy.linked_to == a.handle
    assert a.dummy.link_type == b.dummy.link_type == "dynamics_loop_closure"
