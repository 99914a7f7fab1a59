"""Textures from scene files: read from .ttt, mapped as CoppeliaSim maps them, seen by sensors."""

from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest
from shared_data import shared

from sims.quiet import pybullet as p
from sims.scene.camera import render_sensor
from sims.scene.limits import LimitError, TextureBudget
from sims.scene.load import load_scene
from sims.scene.model import (
    Dynamics,
    Mesh,
    Pose,
    Scene,
    SceneObject,
    ShapeData,
    TextureImage,
    TextureMapping,
    VisionSensorData,
)
from sims.scene.show import json_report, text_report
from sims.scene.textures import read_texture_object, texture_coordinates
from sims.scene.ttt_chunks import Chunk, ChunkError
from sims.world import World

DOWN = (1.0, 0.0, 0.0, 0.0)  # 180° about x: the sensor's +z looks down, its +y along world -y


def plate_scene(color=(1.0, 1.0, 1.0), apply="modulate") -> Scene:
    """A 1 m plate at z = 0 wearing an 8 x 8 texture: a dark block at texture rows 0-1 and
    columns 0-1 (v = 0 is y = -0.5, u = 0 is x = -0.5 in plane mapping) and a dark column 6
    (x from 0.25 to 0.375); an orthographic sensor 1 m above sees exactly the plate."""
    tex = np.full((8, 8, 4), 255, np.uint8)
    tex[0:2, 0:2, :3] = 0
    tex[:, 6, :3] = 40
    image = TextureImage(7, "marks", 8, 8, tex.tobytes())
    mapping = TextureMapping(7, image=image, apply=apply)
    plate = Mesh(
        vertices=(-0.5, -0.5, 0, 0.5, -0.5, 0, 0.5, 0.5, 0, -0.5, 0.5, 0),
        indices=(0, 1, 2, 0, 2, 3),
        color=color,
        texture=mapping,
    )
    sensor = VisionSensorData(
        resolution=(16, 16), perspective=False, ortho_size=1.0, near=0.01, far=2.0
    )
    return Scene(
        objects=(
            SceneObject(1, "plate", "shape", shape=ShapeData(meshes=(plate,), dynamics=Dynamics())),
            SceneObject(
                2, "eye", "vision_sensor", pose=Pose((0, 0, 1), DOWN), vision_sensor=sensor
            ),
        )
    )


def pixel(x: float, y: float) -> tuple[int, int]:
    """(row, column) of the plate point (x, y) in the eye's image: rows go along world -y
    (the sensor's +y is up), columns along world -x (the eye looks down its +z)."""
    return int((0.5 + y) * 16), int((0.5 - x) * 16)


def test_a_sensor_sees_the_texture_where_coppeliasim_lays_it():
    with World(plate_scene()) as w:
        grey = render_sensor(w, "eye").astype(int).mean(axis=2)
        again = render_sensor(w, "eye")
    light = grey[pixel(0.0, 0.0)]
    assert light > 100
    assert grey[pixel(-0.4, -0.4)] < 20  # the block, at u, v near 0
    for x, y in ((0.4, 0.4), (-0.4, 0.4), (0.4, -0.4)):  # not mirrored either way
        assert grey[pixel(x, y)] == pytest.approx(light, abs=10)
    for y in (-0.3, 0.0, 0.3):  # the stripe, full height
        assert grey[pixel(0.31, y)] < light / 3
        assert grey[pixel(0.1, y)] == pytest.approx(light, abs=10)
    with World(plate_scene()) as other:  # a second world draws the same bytes
        assert render_sensor(other, "eye").tobytes() == again.tobytes()


def test_a_red_mesh_modulates_its_texture_and_a_decal_shows_the_texture_itself():
    centre = pixel(0.0, 0.0)
    with World(plate_scene(color=(1.0, 0.0, 0.0))) as w:
        red = render_sensor(w, "eye")[centre].astype(int)
    with World(plate_scene(color=(1.0, 0.0, 0.0), apply="decal")) as w:
        decal = render_sensor(w, "eye")[centre].astype(int)
    assert red[0] > 100 and red[1] == red[2] == 0
    assert decal[0] == decal[1] == decal[2] > 100  # the texture's white


def test_texture_coordinates_follow_the_mapping():
    image = TextureImage(1, "wide", 4, 2, bytes(32))
    square = np.array([[-1.0, -1.0, 0.0], [1.0, -1.0, 0.0], [1.0, 1.0, 0.0]])
    tri = np.array([0, 1, 2])
    plane = texture_coordinates(TextureMapping(1, scaling=(2.0, 2.0), image=image), square, tri)
    # a 4 x 2 image is twice as wide as tall: a texel is square, v runs twice as fast
    assert plane.tolist() == [[0.0, -0.5], [1.0, -0.5], [1.0, 1.5]]
    moved = TextureMapping(1, pose=Pose((1.0, 0.0, 0.0)), image=image)
    assert texture_coordinates(moved, square, tri)[0, 0] == pytest.approx(-1.5)
    fixed = TextureMapping(1, coordinates=(0.0, 0.0, 1.0, 0.0, 1.0, 1.0))
    assert texture_coordinates(fixed, square, tri).tolist() == [[0, 0], [1, 0], [1, 1]]
    assert texture_coordinates(TextureMapping(1, coordinates=(0.0, 0.0)), square, tri) is None
    cube = texture_coordinates(TextureMapping(1, mode="cube"), square, tri)
    assert cube.tolist() == [[-0.5, -0.5], [1.5, -0.5], [1.5, 1.5]]  # z normal: (x, y)
    cyl = texture_coordinates(TextureMapping(1, mode="cylinder"), square, tri)
    assert cyl[:, 0].tolist() == pytest.approx([0.125, 0.375, 0.625])


def _tex_chunk(width: int, height: int, pixels: int) -> tuple[bytes, Chunk]:
    def part(name: bytes, payload: bytes) -> bytes:
        return name + struct.pack("<i", len(payload)) + payload

    body = part(b"Ipa", struct.pack("<iii", 9, width, height)) + part(b"Gon", b"\x01\x00\x00\x00t")
    body += part(b"Bst", b"\x00") + part(b"Img", bytes(pixels)) + b"EOO"
    return body, Chunk("TEX", 0, len(body))


def test_bad_textures_are_refused_with_what_is_wrong():
    buf, c = _tex_chunk(2, 2, 12)
    assert read_texture_object(buf, c, TextureBudget()).rgba[3::4] == b"\xff" * 4
    with pytest.raises(ChunkError, match="need 12 bytes, the file holds 11"):
        read_texture_object(*_tex_chunk(2, 2, 11), TextureBudget())
    with pytest.raises(ChunkError, match="not an image"):
        read_texture_object(*_tex_chunk(0, 5, 0), TextureBudget())
    with pytest.raises(LimitError, match="more than 4096 on a side"):
        read_texture_object(*_tex_chunk(5000, 1, 0), TextureBudget())
    with pytest.raises(LimitError, match="pixels in all"):
        read_texture_object(*_tex_chunk(2, 2, 12), TextureBudget(limit=3))


@pytest.mark.needs_shared("data", "scenes", "course", "simpleLineFollower_api.ttt")
def test_the_line_followers_sensors_see_the_floor_texture():
    """The line follower's floor wears CoppeliaSim's concrete texture (the scene holds no line):
    each 16 x 16 sensor sees a 1 cm patch of it, as the texture's plane mapping predicts."""
    scene = load_scene(shared("data", "scenes", "course", "simpleLineFollower_api.ttt"))
    (image,) = scene.textures
    assert (image.name, image.width, image.height) == ("garageConcrete3", 256, 256)
    floor = [m.texture for o in scene.objects if o.shape for m in o.shape.meshes if m.texture]
    assert len(floor) == 2 and all(t.image is image and t.mode == "plane" for t in floor)
    assert "garageConcrete3 [2180009] 256x256: ResizableFloor_5_25_visibleElement" in (
        text_report(scene)
    )
    (listed,) = json.loads(json_report(scene))["textures"]
    assert [w["shape"] for w in listed["worn_by"]] == ["ResizableFloor_5_25_visibleElement"] * 2
    assert listed["worn_by"][0]["mode"] == "plane" and listed["worn_by"][0]["repeat_u"]
    texels = np.frombuffer(image.rgba, np.uint8).reshape(256, 256, 4)[:, :, :3].mean(axis=2)
    with World(scene) as w:
        for name in ("LeftSensor", "MiddleSensor", "RightSensor"):
            seen = render_sensor(w, name).astype(float).mean(axis=2)
            size = w.model.data[name].vision_sensor.ortho_size
            pos, orn = w.object_pose(name)
            rot = np.array(p.getMatrixFromQuaternion(orn)).reshape(3, 3)
            expected = np.zeros_like(seen)
            for i in range(16):
                for j in range(16):
                    local = np.array(
                        [-((j + 0.5) / 16 - 0.5) * size, (0.5 - (i + 0.5) / 16) * size, 0]
                    )
                    start = np.array(pos) + rot @ local
                    hit = start - start[2] / rot[2, 2] * rot[:, 2]  # down to the floor, z = 0
                    u, v = (hit[0] + 0.5) % 1.0, (hit[1] + 0.5) % 1.0
                    expected[i, j] = texels[int(v * 256), int(u * 256)]
            assert np.corrcoef(expected.ravel(), seen.ravel())[0, 1] > 0.6, name
            if name == "RightSensor":  # a dark texel under its upper left
                assert np.unravel_index(seen.argmin(), seen.shape) == (3, 0)
                assert np.median(seen) - seen.min() > 30


def _ttt(chunks: bytes) -> bytes:
    """An uncompressed .ttt: CoppeliaSim's 1021-byte header, then the chunks and EOF."""
    body = chunks + b"EOF"
    header = b"VREP" + struct.pack("<ii", 20, 18) + b"\x00" + struct.pack("<ii", len(body), 0)
    header += struct.pack("<H", 40100) + bytes(1021 - len(header) - 2)
    return header + body


def test_a_broken_texture_in_a_ttt_is_one_located_line(tmp_path):
    from sims.scene.errors import SceneError
    from sims.scene.load import read_scene

    good, _ = _tex_chunk(2, 2, 12)
    scene = read_scene(_ttt(b"TEX" + struct.pack("<i", len(good)) + good), "ok.ttt")
    assert [(t.name, t.width, t.height) for t in scene.textures] == [("t", 2, 2)]
    bad, _ = _tex_chunk(2, 2, 5)
    with pytest.raises(SceneError) as caught:
        read_scene(_ttt(b"TEX" + struct.pack("<i", len(bad)) + bad), "bad.ttt")
    assert str(caught.value) == (
        "bad.ttt: error: texture #0: corrupt 'TEX' chunk: t: 2x2 pixels of 3 bytes need "
        "12 bytes, the file holds 5"
    )
    huge, _ = _tex_chunk(9000, 9000, 0)
    with pytest.raises(SceneError, match="more than 4096 on a side"):
        read_scene(_ttt(b"TEX" + struct.pack("<i", len(huge)) + huge), "huge.ttt")


LINE_CENTRE, LINE_RADIUS, LINE_WIDTH = (0.0, 0.6), 0.6, 0.03  # m: a circle on the floor


def line_follower_scene() -> Scene:
    """The test cart (two wheel motors, a caster; tests/test_scene_world.py) on a 3 m plate
    whose 600 x 600 texture (5 mm texels) draws a dark circle 3 cm wide; the cart starts on the
    circle, heading along it, with three down-looking 1 cm orthographic sensors in front, 2.5 cm
    apart, as the course's line tracer has them."""
    import dataclasses

    from test_scene_world import cart_scene

    side = 600
    centres = (np.arange(side) + 0.5) / side * 3.0 - 1.5
    x, y = np.meshgrid(centres, centres)  # row r is v = (r + 0.5) / side: y grows with rows
    off = np.abs(np.hypot(x - LINE_CENTRE[0], y - LINE_CENTRE[1]) - LINE_RADIUS)
    grey = np.where(off < LINE_WIDTH / 2, 20, 255).astype(np.uint8)
    rgba = np.dstack([grey, grey, grey, np.full_like(grey, 255)])
    image = TextureImage(50, "circle", side, side, rgba.tobytes())
    plate = Mesh(
        vertices=(-1.5, -1.5, 0, 1.5, -1.5, 0, 1.5, 1.5, 0, -1.5, 1.5, 0),
        indices=(0, 1, 2, 0, 2, 3),
        color=(1.0, 1.0, 1.0),
        texture=TextureMapping(50, scaling=(3.0, 3.0), image=image),
    )
    keep = [o for o in cart_scene().objects if o.name not in ("wall", "sensor", "eye")]
    eye = VisionSensorData(resolution=(4, 4), perspective=False, ortho_size=0.01, near=0.001)
    extra = [
        SceneObject(20, "plate", "shape", pose=Pose((0, 0, 0.0005)),
                    shape=ShapeData(meshes=(plate,), dynamics=Dynamics())),
    ] + [
        SceneObject(21 + i, name, "vision_sensor", parent=2, pose=Pose((0.1, y0, -0.015), DOWN),
                    vision_sensor=eye)
        for i, (name, y0) in enumerate((("left", 0.025), ("middle", 0.0), ("right", -0.025)))
    ]  # fmt: skip
    return dataclasses.replace(Scene(objects=tuple(keep + extra)), source="line test scene")


def test_a_cart_follows_a_line_it_sees_only_through_the_floor_texture():
    """The course line tracer's rule: a side sensor on the line slows that side's wheel. Over
    8 s the cart keeps to the circle (measured: within 1.5 cm of it) and goes 106° round it;
    without the texture the sensors see a white floor and the cart drives straight off (0.81 m
    from the circle after 8 s, measured)."""
    base = 4.0  # rad/s: 0.16 m/s on 40 mm wheels
    with World(line_follower_scene()) as w:
        dark = {}
        for name in ("left", "middle", "right"):
            dark[name] = render_sensor(w, name).mean() < 100
        assert dark == {"left": False, "middle": True, "right": False}  # on the line at start
        off, angles = [], []
        for _ in range(160):  # 8 s in 50 ms steps
            left = render_sensor(w, "left").mean() < 100
            right = render_sensor(w, "right").mean() < 100
            w.set_joint_target_velocity("leftMotor", base * (0.3 if left else 1.0))
            w.set_joint_target_velocity("rightMotor", base * (0.3 if right else 1.0))
            w.advance(0.05)
            (x, y, _), _ = w.object_pose("cart")
            dx, dy = x - LINE_CENTRE[0], y - LINE_CENTRE[1]
            off.append(abs(math.hypot(dx, dy) - LINE_RADIUS))
            angles.append(math.atan2(dy, dx))
    assert max(off) < 0.03
    travelled = np.unwrap(angles)[-1] - np.unwrap(angles)[0]
    assert travelled > math.radians(90)  # counter-clockwise, round the centre on its left


@pytest.mark.needs_shared("data", "scenes", "course", "simpleLineFollower_api.ttt")
def test_writing_xml_says_the_textures_are_left_out(tmp_path, capsys):
    from sims.scene.show import main

    path = shared("data", "scenes", "course", "simpleLineFollower_api.ttt")
    assert main(["xml", str(path), "-o", str(tmp_path / "out.simscene.xml")]) == 0
    assert "note: textures not written (garageConcrete3)" in capsys.readouterr().err
    assert main(["xml", "-q", str(path), "-o", str(tmp_path / "out.simscene.xml")]) == 0
    assert capsys.readouterr().err == ""
