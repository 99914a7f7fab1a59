"""Path objects and the conveyor of the UR5 course scene (issue 28): the path's curve is
CoppeliaSim's (its pads sit where the scene saved them), its position moves the pads, and the
belt carries every block along without one falling through it."""

from __future__ import annotations

import math

import pytest

from sims.quiet import pybullet as p
from sims.scene.load import load_scene
from sims.world import World
from tests.shared_data import shared

BLOCKS = ["Cuboid", *(f"Cuboid{i}" for i in range(5))]


@pytest.fixture(scope="module")
def scene():
    return load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))


@pytest.fixture()
def world(scene):
    w = World(scene)
    yield w
    w.close()


def pads(scene) -> list[tuple[str, float]]:
    return [
        (o.name, o.dummy.path_offset)
        for o in scene.objects
        if o.dummy is not None and o.dummy.follows_path
    ]


def test_path_is_read_closed_with_its_control_points(scene):
    (path,) = [o for o in scene.objects if o.path is not None]
    assert path.name == "ConveyorBeltPath" and path.path.closed
    assert len(path.path.points) == 18
    assert len(pads(scene)) == 74


def test_the_curve_puts_every_pad_where_the_scene_saved_it(scene, world):
    """74 pads saved at offsets along the closed path: the Bézier curve computed here lands
    each within 0.5 mm of where CoppeliaSim put it."""
    path = world.handle("ConveyorBeltPath")
    assert world.paths.length(path) == pytest.approx(74 * 0.0443096, rel=1e-3)
    for name, offset in pads(scene):
        saved = world.object_pose(name)[0]
        assert math.dist(saved, world.paths.pose_at(path, offset)[0]) < 0.0005, name


def test_path_position_moves_the_pads_and_wraps_round(scene, world):
    path = world.handle("ConveyorBeltPath")
    length = world.paths.length(path)
    start = {name: world.object_pose(name)[0] for name, _ in pads(scene)}
    world.paths.set_position(path, 0.0443096)  # one pad pitch
    assert world.paths.position(path) == pytest.approx(0.0443096)
    (first, _), (second, _) = pads(scene)[:2]
    assert math.dist(world.object_pose(first)[0], start[second]) < 0.0005
    world.paths.set_position(path, length + 0.01)  # a closed path wraps
    assert world.paths.position(path) == pytest.approx(0.01, abs=1e-9)
    with pytest.raises(KeyError):
        world.paths.position("ConveyorBelt")


def test_belt_carries_every_block_to_the_sensor_and_none_falls_through(world):
    """The conveyor script's physics: the forwarder (a static box) moves its surface at
    0.08 m/s until the belt's proximity sensor sees a block; every block stays on the belt."""
    frame = world.object_pose("ConveyorBelt_forwarder")
    top = frame[0][2] + 0.13 / 2  # the forwarder box is 13 cm high
    axis = p.getMatrixFromQuaternion(frame[1])[0::3]  # its x axis: the belt's direction
    start = {b: world.object_pose(b)[0] for b in BLOCKS}
    stopped_at = None
    for _ in range(160):  # 8 s of 50 ms passes
        moving = world.proximity("conveyorBelt_sensor") is None
        speed = 0.08 if moving else 0.0
        if not moving and stopped_at is None:
            stopped_at = world.time
        world.reset_dynamic_object("ConveyorBelt_forwarder")
        world.set_initial_velocity("ConveyorBelt_forwarder", [a * speed for a in axis])
        world.step(10)
        for b in BLOCKS if world.steps % 40 == 0 else ():
            lowest = p.getAABB(*_body(world, b), physicsClientId=world.client_id)[0][2]
            assert lowest > top - 0.002, f"{b} sank into the belt at t={world.time:.2f}"
    assert stopped_at is not None  # the first block reached the sensor and the belt stopped
    moved = [math.dist(world.object_pose(b)[0], start[b]) for b in BLOCKS]
    assert all(m == pytest.approx(moved[0], abs=0.01) for m in moved)  # carried together
    assert moved[0] == pytest.approx(0.08 * stopped_at, rel=0.1)


def _body(world: World, name: str) -> tuple[int, int]:
    ref = next(o for o in world.model.objects if o.name == name)
    return ref.body, ref.link
