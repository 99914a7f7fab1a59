"""The scene readers on files the tests write themselves (no course data needed): the Huffman
decoder, the binary ``.ttt`` layout, the XML format, broken input, and ``sitegen scene show``."""

from __future__ import annotations

import json
import math
import os
import random
import struct

import pytest
from scene_read_helpers import (
    chunk,
    floats,
    huffman_compress,
    ints,
    scene_object,
    scramble,
    string,
    ttt_file,
)

from sims.scene import ttt_huffman
from sims.scene.load import SceneError, load_scene, read_scene
from sims.scene.show import main as scene_main
from sims.scene.xml_write import write_xml

# --- Huffman -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "data",
    [
        b"x",
        b"ab" * 5000,
        bytes(range(256)) * 40,
        # long runs of a symbol with a 2-bit code: block decodes started out of step never meet
        # the real codes inside the run (the slow join path)
        b"\x00" * 200_000 + b"\x01\x02" * 30_000 + b"\x00" * 70_000 + b"end",
        # eight equally frequent symbols: 3-bit codes, so a run of one of them is read out of
        # step by the block decodes that start inside it (they never meet the real codes there:
        # the real chain crosses those blocks code by code)
        b"".join(bytes([c]) * 60_000 for c in b"abcdefgh") + b"abcdefgh" * 1000,
        bytes(random.Random(7).choices(b"aaaaaaaabbbbccd\xff", k=120_000)),
        random.Random(8).randbytes(50_000),
    ],
)
def test_huffman_decoder_matches_what_was_encoded(data):
    packed = huffman_compress(data)
    assert ttt_huffman.decompress(packed, len(data)) == data


def test_huffman_table_decoder_agrees_with_the_bit_by_bit_one():
    data = bytes(random.Random(5).choices(range(40), weights=range(1, 41), k=30_000))
    packed = huffman_compress(data)
    codes, start = ttt_huffman._read_tree(packed)
    slow = ttt_huffman._decompress_slow(packed, len(data), codes, start)
    assert slow == ttt_huffman.decompress(packed, len(data)) == data


def test_huffman_block_by_block_join_gives_the_same_bytes(monkeypatch):
    # the join used when the all-blocks-at-once one gives up
    data = b"".join(bytes([c]) * 20_000 for c in b"abcdefgh") + random.Random(2).randbytes(9000)
    packed = huffman_compress(data)
    monkeypatch.setattr(ttt_huffman, "_join_fast", lambda *args: None)
    assert ttt_huffman.decompress(packed, len(data)) == data
    with pytest.raises(ttt_huffman.HuffmanError):
        ttt_huffman.decompress(packed[: len(packed) // 2], len(data))


def test_huffman_truncated_stream_is_an_error():
    data = random.Random(3).randbytes(20_000)
    packed = huffman_compress(data)
    with pytest.raises(ttt_huffman.HuffmanError):
        ttt_huffman.decompress(packed[: len(packed) // 2], len(data))
    with pytest.raises(ttt_huffman.HuffmanError):
        ttt_huffman.decompress(packed[:10], len(data))


# --- a synthetic .ttt ----------------------------------------------------------------------

SCRIPT = "function sysCall_threadmain()\n    sim.setJointTargetVelocity(h, 1.5)\nend\n"


def _cuboid_shape(handle: int, name: str, parent: int) -> bytes:
    wrapper = (
        chunk("Nme", string("part"))
        + chunk("Mas", floats(2.0))
        # inertia frame: position first, then quaternion (w, x, y, z); then mass-less moments
        + chunk("Ine", floats(0.0, 0.0, 0.01, 1.0, 0.0, 0.0, 0.0, 0.01, 0.02, 0.03))
        + chunk("Vtb", floats(0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0))
        + b"EOO"
    )
    color = chunk("Cl3", floats(*([0.2, 0.4, 0.6] + [0.0] * 12))) + b"EOO"
    mesh = (
        chunk("Cl0", color)
        + chunk("Vev", ints(0))
        + chunk("Inv", ints(0))
        + chunk("Ppr", ints(3) + floats(0.1, 0.2, 0.3))
        + chunk("Ppf", floats(0.0, 0.0, 0.05, 1.0, 0.0, 0.0, 0.0))
        + b"EOO"
    )
    geometry = chunk("Gst", wrapper + mesh) + b"EOO"
    material = chunk("Ipa", ints(7)) + chunk("BuN", ints(3, 0) + floats(0.0, 0.4, 0.9)) + b"EOO"
    own = [
        chunk("Ge2", geometry),
        chunk("Mat", material),
        chunk("Dc2", struct.pack("<H", 0xFF00)),
        chunk("Sss", bytes([0x80])),  # bit 7: dynamic
        chunk("Ss3", bytes([0x01])),  # bit 0: respondable
    ]
    return scene_object("SHP", handle, name, own, parent=parent, position=(0.0, 0.0, 0.2))


def _pool() -> bytes:
    verts = floats(0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1)
    return chunk("VIN", chunk("Ver", verts) + chunk("Ind", ints(0, 1, 2, 0, 2, 3)) + b"EOO")


def _joint(handle: int, parent: int) -> bytes:
    own = [
        chunk("Jtt", ints(10)),
        chunk("Jmd", ints(5)),
        chunk("Va9", bytes([0x30])),  # motor on, position control on
        chunk("Pmr", floats(-1.0, 2.0)),
        chunk("Prt", floats(0.25)),
        chunk("Dmp", floats(0.0, 4.5)),
        chunk("Dtp", floats(0.75)),
        chunk("Dp2", floats(0.3, 0.0, 0.0)),
        chunk("Ulv", floats(1.2)),
    ]
    rot = (math.cos(math.pi / 4), math.sin(math.pi / 4), 0.0, 0.0)  # 90° about x
    return scene_object("JNT", handle, "arm_joint", own, parent, rot, (0.1, 0.0, 0.0))


def _sensor(handle: int, parent: int) -> bytes:
    volume = chunk("Ss3", floats(0.01, 0.4, 0, 0, 0, 0, 0.0, 0.05, 0.5)) + b"EOO"
    own = [chunk("Snt", ints(33)), chunk("Vod", volume)]
    return scene_object("SNR", handle, "nose#0", own, parent, alias="sensingNose")


def _script(handle: int) -> bytes:
    return chunk(
        "LST",
        chunk("Si2", ints(0, handle, 1))
        + chunk("Va2", bytes([0x01]))
        + chunk("Ste", scramble(SCRIPT.encode()))
        + b"EOO",
    )


def _body(extra: bytes = b"") -> bytes:
    return (
        _pool()
        + scene_object("DMY", 3, "robot", [chunk("Dy2", floats(0.01))])
        + _cuboid_shape(5, "body", 3)
        + _joint(6, 5)
        + _sensor(8, 5)
        + extra
        + _script(3)
        + chunk("DYN", chunk("En2", ints(0) + floats(0.0, 0.0, -3.7) + ints(0)) + b"EOO")
    )


@pytest.fixture
def ttt_path(tmp_path):
    path = tmp_path / "robot.ttt"
    path.write_bytes(ttt_file(_body()))
    return path


def test_ttt_object_tree_joint_shape_sensor_script(ttt_path):
    scene = load_scene(ttt_path)
    by_name = {o.name: o for o in scene.objects}
    assert [o.name for o in scene.objects] == ["robot", "body", "arm_joint", "nose#0"]
    assert scene.path(scene.objects[3]) == "/robot/body/sensingNose"  # 4.2+ alias
    assert by_name["body"].parent == 3 and by_name["arm_joint"].parent == 5
    assert scene.path(by_name["arm_joint"]) == "/robot/body/arm_joint"
    joint = by_name["arm_joint"]
    assert joint.pose.position == pytest.approx((0.1, 0.0, 0.0))
    # stored (w, x, y, z), modelled (x, y, z, w)
    assert joint.pose.quaternion == pytest.approx((math.sqrt(0.5), 0, 0, math.sqrt(0.5)))
    j = joint.joint
    assert (j.kind, j.mode, j.cyclic) == ("revolute", "position", False)
    assert (j.minimum, j.range, j.position, j.target) == pytest.approx((-1, 2, 0.25, 0.75))
    assert (j.max_force, j.max_velocity, j.p_gain) == pytest.approx((4.5, 1.2, 0.3))
    assert j.motor_enabled and j.control_enabled
    shape = by_name["body"].shape
    (mesh,) = shape.meshes
    assert mesh.primitive == "cuboid" and mesh.size == pytest.approx((0.1, 0.2, 0.3))
    assert mesh.local.position == pytest.approx((0, 0, 0.05))
    assert mesh.indices == (0, 1, 2, 0, 2, 3) and len(mesh.vertices) == 12
    assert mesh.color == pytest.approx((0.2, 0.4, 0.6))
    d = shape.dynamics
    assert not d.static and d.respondable and d.respondable_mask == 0xFF00
    assert d.mass == pytest.approx(2.0)
    assert d.inertia == pytest.approx((0.02, 0.04, 0.06))  # mass-less moments times the mass
    assert d.inertia_frame.position == pytest.approx((0, 0, 0.01))
    assert d.friction == pytest.approx(0.4)
    nose = by_name["nose#0"].proximity_sensor
    assert (nose.volume, nose.range, nose.offset, nose.angle) == pytest.approx(
        ("cone", 0.4, 0.01, 0.5)
    ) or (nose.volume == "cone" and nose.range == pytest.approx(0.4))
    assert nose.angle == pytest.approx(0.5)
    (script,) = scene.scripts
    assert (script.kind, script.object, script.threaded) == ("child", 3, True)
    assert script.text == SCRIPT
    assert scene.gravity == pytest.approx((0, 0, -3.7))
    assert scene.format == "ttt" and "serialization 22" in scene.version


def test_uncompressed_ttt_reads_the_same(tmp_path, ttt_path):
    plain = tmp_path / "plain.ttt"
    plain.write_bytes(ttt_file(_body(), compress=False))
    assert load_scene(plain).objects == load_scene(ttt_path).objects


def test_unknown_chunks_and_object_types_are_listed_not_fatal(tmp_path):
    extra = (
        chunk("ZZZ", b"future top-level data")
        + scene_object("MKR", 9, "marker", [chunk("Xyz", b"12345")], parent=3)
        + scene_object("JNT", 10, "new_joint", [chunk("Jtt", ints(11)), chunk("Qqq", b"?")], 3)
    )
    path = tmp_path / "future.ttt"
    path.write_bytes(ttt_file(_body(extra)))
    scene = load_scene(path)
    names = [o.name for o in scene.objects]
    assert "body" in names and "marker" in names
    notes = " | ".join(f"{n.where}: {n.message}" for n in scene.notes)
    assert "'ZZZ'" in notes and "marker" in notes
    assert "joint chunk 'Qqq' not understood, skipped (in new_joint)" in notes
    assert next(o for o in scene.objects if o.name == "new_joint").joint.kind == "prismatic"


@pytest.mark.parametrize(
    ("version", "oldest", "expected"),
    [(30, 26, "knows up to 25"), (17, 17, "older than any CoppeliaSim")],
)
def test_unsupported_versions_are_clear_errors(tmp_path, version, oldest, expected):
    path = tmp_path / "v.ttt"
    path.write_bytes(ttt_file(_body(), version=version, oldest_reader=oldest))
    with pytest.raises(SceneError) as err:
        load_scene(path)
    assert err.value.obj == "header" and expected in err.value.message
    assert str(err.value).startswith(f"{path}: error: header: ")


def test_truncated_and_corrupt_ttt_are_located_errors(tmp_path):
    data = ttt_file(_body())
    cut = tmp_path / "cut.ttt"
    cut.write_bytes(data[: 1021 + (len(data) - 1021) // 2])
    with pytest.raises(SceneError, match="truncated"):
        load_scene(cut)
    (tmp_path / "head.ttt").write_bytes(data[:100])
    with pytest.raises(SceneError, match="header"):
        load_scene(tmp_path / "head.ttt")
    # an object whose chunk claims more bytes than it holds
    bad_shape = _cuboid_shape(5, "body", 3).replace(b"Mas\x04\x00\x00\x00", b"Mas\xff\x00\x00\x00")
    body = _pool() + scene_object("DMY", 3, "robot", []) + bad_shape
    corrupt = tmp_path / "corrupt.ttt"
    corrupt.write_bytes(ttt_file(body))
    with pytest.raises(SceneError) as err:
        load_scene(corrupt)
    assert err.value.obj in ("body", "shape #1") and "corrupt" in err.value.message


def test_not_a_scene(tmp_path):
    for name, content in (("empty.ttt", b""), ("text.ttt", b"hello"), ("bin.ttt", os.urandom(64))):
        (tmp_path / name).write_bytes(content)
        with pytest.raises(SceneError) as err:
            load_scene(tmp_path / name)
        assert err.value.file.endswith(name)
    with pytest.raises(SceneError, match="directory"):
        load_scene(tmp_path)
    with pytest.raises(SceneError, match="no such file"):
        load_scene(tmp_path / "missing.ttt")


# --- XML -----------------------------------------------------------------------------------

TINY_XML = """<?xml version="1.0" encoding="UTF-8"?>
<CoppeliaSim>
    <filetype>simpleScene</filetype>
    <xmlSerializationNb>1</xmlSerializationNb>
    <prgVer>40100</prgVer>
    <dynamics><gravity>0 0 -9.81</gravity></dynamics>
    <simulation><simulationTimeStep>0.025</simulationTimeStep></simulation>
    <shape>
        <common>
            <name>base</name>
            <localFrame><position>0 0 0.1</position><euler>0 0 90</euler></localFrame>
            <switches><modelBase>true</modelBase></switches>
        </common>
        <primitive>
            <type>cylinder</type><size>0.2 0.2 0.05</size>
            <color><ambientDiffuse>255 0 51</ambientDiffuse></color>
        </primitive>
        <dynamics>
            <mass>2</mass>
            <localInertiaFrame><position>0 0 0.01</position><euler>0 0 0</euler></localInertiaFrame>
            <principalMomentOfInertia>0.01 0.01 0.02</principalMomentOfInertia>
            <switches><static>false</static><respondable>true</respondable></switches>
            <material><engines><bullet>
                <friction>0.8</friction><oldfriction>0.6</oldfriction>
            </bullet></engines></material>
        </dynamics>
        <childScript><switches><enabled>true</enabled></switches>
            <scriptText><![CDATA[if a < b then print("<ok>") end]]></scriptText></childScript>
        <joint>
            <common><name>hinge</name>
                <localFrame><position>0.05 0 0.1</position><euler>90 0 0</euler></localFrame>
            </common>
            <type>revolute</type><mode>force</mode>
            <minPosition>-90</minPosition><range>180</range><position>10</position>
            <dynamics><maxForce>3</maxForce><targetPosition>45</targetPosition>
                <upperVelocityLimit>90</upperVelocityLimit><pidValues>0.2 0 0</pidValues>
                <switches><motorEnabled>true</motorEnabled>
                    <controlLoopEnabled>true</controlLoopEnabled></switches>
            </dynamics>
            <dummy><common><name>tip</name></common>
                <linkType>dynamics_loopClosure</linkType><linkedDummy>anchor</linkedDummy></dummy>
        </joint>
        <dummy><common><name>anchor</name></common>
            <linkType>dynamics_loopClosure</linkType><linkedDummy>tip</linkedDummy></dummy>
        <proximitySensor>
            <common><name>sonar</name></common>
            <type>cone</type>
            <volume><offset>0.01</offset><range>0.5</range><angle>30</angle>
                <closeFarRadius>0 0.1</closeFarRadius></volume>
        </proximitySensor>
    </shape>
</CoppeliaSim>
"""


def test_xml_scene_reads_tree_units_and_scripts(tmp_path):
    path = tmp_path / "tiny.simscene.xml"
    path.write_text(TINY_XML)
    scene = load_scene(path)
    assert [(o.handle, o.name, o.parent) for o in scene.objects] == [
        (0, "base", None),
        (1, "hinge", 0),
        (2, "tip", 1),
        (3, "anchor", 0),
        (4, "sonar", 0),
    ]
    base, hinge, tip, anchor, sonar = scene.objects
    assert (tip.dummy.linked_to, anchor.dummy.linked_to) == (3, 2)
    assert tip.dummy.link_type == "dynamics_loop_closure"
    half = math.sqrt(0.5)
    assert base.pose.quaternion == pytest.approx((0, 0, half, half))
    assert base.model_base
    (mesh,) = base.shape.meshes
    assert (mesh.primitive, mesh.size) == ("cylinder", pytest.approx((0.2, 0.2, 0.05)))
    assert mesh.color == pytest.approx((1.0, 0.0, 0.2))
    d = base.shape.dynamics
    assert (d.static, d.respondable, d.mass, d.friction) == (False, True, 2.0, 0.6)
    assert d.inertia == pytest.approx((0.02, 0.02, 0.04))
    j = hinge.joint
    assert hinge.pose.quaternion == pytest.approx((half, 0, 0, half))
    assert (j.mode, j.minimum, j.range) == (
        "position",
        pytest.approx(-math.pi / 2),
        pytest.approx(math.pi),
    )
    assert (j.position, j.target) == pytest.approx((math.radians(10), math.radians(45)))
    assert (j.max_force, j.max_velocity, j.p_gain) == pytest.approx((3, math.pi / 2, 0.2))
    s = sonar.proximity_sensor
    assert (s.volume, s.range, s.angle) == ("cone", 0.5, pytest.approx(math.radians(30)))
    (script,) = scene.scripts
    assert (script.kind, script.object, script.text) == (
        "child",
        0,
        'if a < b then print("<ok>") end',
    )
    assert scene.time_step == 0.025 and scene.format == "xml"


def test_xml_round_trip_through_the_writer(tmp_path):
    path = tmp_path / "tiny.simscene.xml"
    path.write_text(TINY_XML)
    first = load_scene(path)
    text = write_xml(first)
    assert text == write_xml(read_scene(text.encode(), "again"))  # deterministic, stable
    second = read_scene(text.encode(), "written")
    assert [(o.name, o.kind, o.parent) for o in second.objects] == [
        (o.name, o.kind, o.parent) for o in first.objects
    ]
    for a, b in zip(first.objects, second.objects, strict=True):
        assert b.pose.position == pytest.approx(a.pose.position, abs=1e-12)
        assert abs(
            sum(x * y for x, y in zip(a.pose.quaternion, b.pose.quaternion, strict=True))
        ) == (pytest.approx(1.0, abs=1e-12))
    assert second.objects[1].joint == pytest.approx(first.objects[1].joint) or (
        second.objects[1].joint.range == pytest.approx(first.objects[1].joint.range)
    )
    assert second.objects[0].shape.dynamics.inertia == pytest.approx(
        first.objects[0].shape.dynamics.inertia
    )
    assert second.scripts == first.scripts
    assert [o.dummy for o in second.objects] == [o.dummy for o in first.objects]


def test_xml_refuses_entities_and_reports_lines(tmp_path):
    bomb = tmp_path / "bomb.simscene.xml"
    bomb.write_text(
        '<?xml version="1.0"?>\n<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;">]>\n'
        "<CoppeliaSim><filetype>&lol2;</filetype></CoppeliaSim>\n"
    )
    with pytest.raises(SceneError, match="not allowed") as err:
        load_scene(bomb)
    assert err.value.obj == "line 2"
    broken = tmp_path / "broken.simscene.xml"
    broken.write_text("<CoppeliaSim>\n<filetype>simpleScene</filetype>\n<shape>\n</CoppeliaSim>\n")
    with pytest.raises(SceneError, match="not well-formed") as err:
        load_scene(broken)
    assert err.value.obj == "line 4"


def test_xml_bad_values_name_the_object(tmp_path):
    bad = TINY_XML.replace("<range>180</range>", "<range>wide</range>")
    path = tmp_path / "bad.simscene.xml"
    path.write_text(bad)
    with pytest.raises(SceneError) as err:
        load_scene(path)
    assert err.value.obj == "hinge" and "range" in err.value.message
    path.write_text(TINY_XML.replace("simpleScene", "exhaustiveScene"))
    with pytest.raises(SceneError, match="filetype"):
        load_scene(path)


def test_xml_external_mesh_file_is_listed(tmp_path):
    text = TINY_XML.replace(
        "<primitive>\n            <type>cylinder</type><size>0.2 0.2 0.05</size>",
        "<mesh><fileName>base_mesh.dae</fileName>",
    ).replace("</primitive>", "</mesh>", 1)
    path = tmp_path / "ext.simscene.xml"
    path.write_text(text)
    scene = load_scene(path)
    assert scene.objects[0].shape.meshes == ()
    assert any("base_mesh.dae" in n.message for n in scene.notes)


# --- sitegen scene show ----------------------------------------------------------------------


def test_scene_show_text_and_json(ttt_path, capsys):
    assert scene_main(["show", str(ttt_path)]) == 0
    out = capsys.readouterr().out
    assert "arm_joint [6] joint" in out and "revolute, position, range [-57.296°, 57.296°]" in out
    assert "child (on robot) threaded" in out
    assert scene_main(["show", str(ttt_path), "--json"]) == 0
    first = capsys.readouterr().out
    doc = json.loads(first)
    assert [o["path"] for o in doc["objects"]][:3] == [
        "/robot",
        "/robot/body",
        "/robot/body/arm_joint",
    ]
    assert doc["objects"][1]["shape"]["mass"] == 2.0
    assert scene_main(["show", str(ttt_path), "--json"]) == 0
    assert capsys.readouterr().out == first  # same file, same bytes


def test_scene_show_bad_input_is_one_line(tmp_path, capsys):
    from sitegen.cli import main as sitegen_main

    bad = tmp_path / "bad.ttt"
    bad.write_bytes(b"VREP" + b"\x00" * 50)
    assert sitegen_main(["scene", "show", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"{bad}: error: header: ")
    assert "Traceback" not in err


def test_scene_xml_command_writes_a_scene_that_reads_back(ttt_path, tmp_path):
    out = tmp_path / "robot.simscene.xml"
    assert scene_main(["xml", str(ttt_path), "-o", str(out)]) == 0
    again = load_scene(out)
    assert [o.name for o in again.objects] == ["robot", "body", "arm_joint", "nose#0"]
    assert again.objects[3].alias == "sensingNose"
    assert again.objects[2].joint.max_velocity == pytest.approx(1.2)
    assert again.scripts[0].text == SCRIPT and again.scripts[0].threaded


def test_script_objects_of_coppeliasim_4_6_become_scripts(tmp_path):
    detached = (
        chunk("Si2", ints(0, -1, 1))
        + chunk("Ste", scramble(b"sim = require('sim')\nfunction sysCall_init() end\n"))
        + b"EOO"
    )
    script_obj = scene_object("SCT", 11, "Script", [chunk("Soo", detached)], parent=3)
    path = tmp_path / "new.ttt"
    path.write_bytes(ttt_file(_body(script_obj), version=25, oldest_reader=24, program=40900))
    scene = load_scene(path)
    new = [s for s in scene.scripts if "require" in s.text]
    assert len(new) == 1 and new[0].object == 3 and new[0].kind == "child"
    assert any(o.name == "Script" and o.kind == "unknown" for o in scene.objects)


def test_damaged_files_give_scene_errors_never_other_exceptions():
    rng = random.Random(11)
    body = _body()
    packed = ttt_file(body)
    outcomes = set()
    for i in range(60):
        if i % 2:
            damaged = bytearray(body)
            for _ in range(rng.randint(1, 4)):
                damaged[rng.randrange(len(damaged))] = rng.randrange(256)
            data = ttt_file(bytes(damaged), compress=False)
        else:
            damaged = bytearray(packed)
            damaged[rng.randrange(1021, len(damaged))] ^= 1 << rng.randrange(8)
            data = bytes(damaged)
        try:
            read_scene(data, "damaged.ttt")
            outcomes.add("loaded")
        except SceneError as exc:
            assert str(exc).startswith("damaged.ttt: ")
            outcomes.add("error")
    assert outcomes == {"loaded", "error"}
