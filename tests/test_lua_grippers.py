"""A gripper's own Lua keeps its part while the arm moves (issue 28, grippers): the pattern of
the course's grippers (a part re-parented onto the gripper's attach point, a force sensor; the
part let go by re-parenting it away or by breaking the sensor), run by a threaded script on the
UR5 + RG2 of course2/ur5WithRg2Grasping.ttt, checked by positions over simulated time.

CoppeliaSim links two dynamic bodies only through a joint or a force sensor: a dynamic part
re-parented onto the attach point is held rigidly; on anything else it stays free."""

from __future__ import annotations

import dataclasses
import math

import pytest
from shared_data import shared

from sims.lua.host import ScriptHost
from sims.quiet import pybullet as p
from sims.scene.load import load_scene
from sims.scene.model import Script
from sims.world import World

# our own threaded script: hang a block 0.3 m out along the attach point's axis, swing the arm
# (Ruckig profile, blocking), let go by re-parenting; then a second block, let go by breaking
# the sensor, and hung again on the broken sensor (it holds nothing now)
ARM = """
function sysCall_threadmain()
    local joints = {}
    for i = 1, 6 do joints[i] = sim.getObjectHandle('UR5_joint' .. i) end
    local attach = sim.getObjectHandle('RG2_attachPoint')
    local zeros = {0, 0, 0, 0, 0, 0}
    local v, a, j = {}, {}, {}
    for i = 1, 6 do v[i], a[i], j[i] = 2, 3, 6 end
    local function swing(config)
        sim.rmlMoveToJointPositions(joints, -1, zeros, zeros, v, a, j, config, zeros)
    end
    local function hang(name)
        local part = sim.getObjectHandle(name)
        sim.setObjectPosition(part, attach, {0, 0, 0.3})
        sim.setObjectOrientation(part, attach, {0, 0, 0})
        sim.setObjectParent(part, attach, true)
        return part
    end
    local first = hang('Cuboid')
    sim.wait(0.5)
    local state, force = sim.readForceSensor(attach)
    sim.setFloatSignal('heldForce', math.sqrt(force[1]^2 + force[2]^2 + force[3]^2))
    sim.setIntegerSignal('phase', 1)
    swing({-1.5, 0.4, 0.6, 0, 1.2, 0})
    sim.setIntegerSignal('phase', 2)
    sim.setObjectParent(first, -1, true)
    sim.wait(1.5)
    local second = hang('Cuboid0')
    sim.wait(0.5)
    sim.setIntegerSignal('phase', 3)
    swing({0, 0, 0, 0, 0, 0})
    sim.setIntegerSignal('phase', 4)
    sim.breakForceSensor(attach)
    local broken = sim.readForceSensor(attach)
    sim.setIntegerSignal('brokenState', broken)
    sim.wait(1.5)
    sim.setObjectParent(second, attach, true)
    sim.setIntegerSignal('phase', 5)
end
"""


def _relative(world: World, a: int, b: int):
    pa, qa = world.object_pose(a)
    pb, qb = world.object_pose(b)
    return p.multiplyTransforms(*p.invertTransform(pa, qa), pb, qb)


def test_part_hung_on_the_attach_point_rides_the_arm_and_falls_when_let_go():
    scene = load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    base = scene.objects[[o.name for o in scene.objects].index("UR5")].handle
    world = World(dataclasses.replace(scene, scripts=(Script("child", ARM, base, True),)))
    host = ScriptHost(world)
    attach, first, second = (world.find(n) for n in ("RG2_attachPoint", "Cuboid", "Cuboid0"))
    trace: list[tuple[float, int, tuple, tuple, tuple]] = []  # t, phase, rel1, pos1, pos2
    try:
        host.start()
        for _ in range(200):  # up to 20 simulated seconds
            world.advance(0.1)
            phase = host.signals["int"].get("phase", 0)
            rel = _relative(world, attach, first if phase < 3 else second)
            trace.append(
                (
                    world.time,
                    phase,
                    rel[0],
                    world.object_pose(first)[0],
                    world.object_pose(second)[0],
                )
            )
            if phase == 5:
                break
        errors = list(host.errors)
        held_force = host.signals["float"].get("heldForce")
        broken_state = host.signals["int"].get("brokenState")
        still_held = world.held_by(second)
    finally:
        host.close()
        world.close()
    assert errors == []
    assert trace[-1][1] == 5, "the script reached its end"
    # the attach point's sensor carries the block's weight (0.3 m out: force and the torque)
    assert held_force is not None and held_force > 0.5
    assert broken_state is not None and broken_state & 2  # bit 1: broken
    assert still_held is None  # a broken sensor holds nothing
    # while held (phases 1 and 3), the block keeps its place on the attach point within 2 mm
    # while the arm swings it through the air
    for wanted, index in ((1, 3), (3, 4)):
        rows = [r for r in trace if r[1] == wanted]
        assert len(rows) >= 10
        for r in rows:
            assert math.dist(r[2], (0.0, 0.0, 0.3)) < 0.002, r
        travel = math.dist(rows[0][index], rows[-1][index])
        assert travel > 0.3, travel
    # let go (re-parented to the world, then the sensor broken): each block falls to the floor
    for wanted, index in ((2, 3), (4, 4)):
        rows = [r for r in trace if r[1] == wanted]
        assert rows[0][index][2] - rows[-1][index][2] > 0.2
        assert rows[-1][index][2] < 0.1


# twice its weight upward on a block for half a second: it rises with g net, 1.23 m
PUSH = """
function sysCall_init()
    block = sim.getObjectHandle('Cuboid0')
    mass = sim.getShapeMass(block)
    sim.setFloatSignal('mass', mass)
    sim.setFloatSignal('z0', sim.getObjectPosition(block, -1)[3])
end

function sysCall_actuation()
    if sim.getSimulationTime() < 0.5 - 1e-6 then
        sim.addForceAndTorque(block, {0, 0, 2 * mass * 9.81}, {0, 0, 0})
    elseif not done then
        done = true
        sim.setFloatSignal('z', sim.getObjectPosition(block, -1)[3])
    end
end
"""


def test_add_force_and_torque_lifts_a_block_for_the_passes_it_is_given():
    scene = load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    world = World(dataclasses.replace(scene, scripts=(Script("child", PUSH, 1),)))
    host = ScriptHost(world)
    try:
        host.start()
        world.advance(0.6)
        errors, floats = list(host.errors), dict(host.signals["float"])
    finally:
        host.close()
        world.close()
    assert errors == []
    assert floats["mass"] > 0
    # each pass's force acts over that pass only (CoppeliaSim clears added forces after the
    # dynamics): 0.5 s at g net upward, z0 + g t^2 / 2
    assert floats["z"] - floats["z0"] == pytest.approx(9.81 * 0.5**2 / 2, rel=0.05)


# a suction pad's pattern: a dummy on the part linked to the pad's dummy by a dynamics
# ("overlap constraint") link holds the part; undoing the link lets it go
SUCTION = """
function sysCall_threadmain()
    local joints = {}
    for i = 1, 6 do joints[i] = sim.getObjectHandle('UR5_joint' .. i) end
    local attach = sim.getObjectHandle('RG2_attachPoint')
    local part = sim.getObjectHandle('Cuboid1')
    local zeros = {0, 0, 0, 0, 0, 0}
    local v, a, j = {2, 2, 2, 2, 2, 2}, {3, 3, 3, 3, 3, 3}, {6, 6, 6, 6, 6, 6}
    sim.setObjectPosition(part, attach, {0, 0, 0.3})
    sim.setObjectOrientation(part, attach, {0, 0, 0})
    local pad = sim.createDummy(0.01)
    sim.setObjectPosition(pad, part, {0, 0, 0})
    sim.setObjectOrientation(pad, part, {0, 0, 0})
    sim.setObjectParent(pad, attach, true)
    local grip = sim.createDummy(0.01)
    sim.setObjectPosition(grip, part, {0, 0, 0})
    sim.setObjectOrientation(grip, part, {0, 0, 0})
    sim.setObjectParent(grip, part, true)
    sim.setIntegerSignal('defaultType', sim.getObjectInt32Parameter(grip,
                                                                    sim.dummyintparam_link_type))
    sim.setObjectInt32Parameter(grip, sim.dummyintparam_link_type,
                                sim.dummy_linktype_dynamics_loop_closure)
    sim.setLinkDummy(grip, pad)
    sim.setIntegerSignal('linked', sim.getLinkDummy(pad) == grip and 1 or 0)
    sim.wait(0.5)
    sim.setIntegerSignal('phase', 1)
    sim.rmlMoveToJointPositions(joints, -1, zeros, zeros, v, a, j, {-1.5, 0.4, 0.6, 0, 1.2, 0},
                                zeros)
    sim.setIntegerSignal('phase', 2)
    sim.setLinkDummy(grip, -1)
    sim.setIntegerSignal('unlinked', sim.getLinkDummy(pad))
    sim.wait(1.5)
    sim.setIntegerSignal('phase', 3)
end
"""


def test_suction_pad_link_holds_the_part_while_the_arm_swings_and_undone_lets_it_fall():
    scene = load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    base = scene.objects[[o.name for o in scene.objects].index("UR5")].handle
    world = World(dataclasses.replace(scene, scripts=(Script("child", SUCTION, base, True),)))
    host = ScriptHost(world)
    attach, part = world.find("RG2_attachPoint"), world.find("Cuboid1")
    trace = []
    try:
        host.start()
        for _ in range(120):
            world.advance(0.1)
            phase = host.signals["int"].get("phase", 0)
            trace.append((phase, _relative(world, attach, part)[0], world.object_pose(part)[0]))
            if phase == 3:
                break
        errors, ints = list(host.errors), dict(host.signals["int"])
    finally:
        host.close()
        world.close()
    assert errors == []
    assert ints["defaultType"] == 5  # a new dummy's link: IK tip-target (CoppeliaSim's default)
    assert ints["linked"] == 1 and ints["unlinked"] == -1
    held = [r for r in trace if r[0] == 1]
    assert len(held) >= 10
    assert all(math.dist(r[1], (0.0, 0.0, 0.3)) < 0.002 for r in held)
    assert math.dist(held[0][2], held[-1][2]) > 0.3
    fell = [r for r in trace if r[0] == 2]
    assert fell[0][2][2] - fell[-1][2][2] > 0.2 and fell[-1][2][2] < 0.1


# the other fake grasp: the part made static rides its new parent (here the RG2's body, a
# shape); static on the world it stays where it is; made dynamic again it falls
STATIC = """
function sysCall_threadmain()
    local joints = {}
    for i = 1, 6 do joints[i] = sim.getObjectHandle('UR5_joint' .. i) end
    local attach = sim.getObjectHandle('RG2_attachPoint')
    local part = sim.getObjectHandle('Cuboid2')
    local zeros = {0, 0, 0, 0, 0, 0}
    local v, a, j = {2, 2, 2, 2, 2, 2}, {3, 3, 3, 3, 3, 3}, {6, 6, 6, 6, 6, 6}
    sim.setObjectPosition(part, attach, {0, 0, 0.3})
    sim.setObjectOrientation(part, attach, {0, 0, 0})
    sim.setObjectInt32Parameter(part, sim.shapeintparam_static, 1)
    sim.setObjectParent(part, sim.getObjectHandle('RG2'), true)
    sim.wait(0.5)
    sim.setIntegerSignal('phase', 1)
    sim.rmlMoveToJointPositions(joints, -1, zeros, zeros, v, a, j, {-1.5, 0.4, 0.6, 0, 1.2, 0},
                                zeros)
    sim.setObjectParent(part, -1, true)
    sim.setIntegerSignal('phase', 2)
    sim.wait(1.0)
    sim.setObjectInt32Parameter(part, sim.shapeintparam_static, 0)
    sim.resetDynamicObject(part)
    sim.setIntegerSignal('phase', 3)
    sim.wait(1.5)
    sim.setIntegerSignal('phase', 4)
end
"""


def test_part_made_static_rides_its_parent_stays_put_on_the_world_and_falls_when_dynamic():
    scene = load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    base = scene.objects[[o.name for o in scene.objects].index("UR5")].handle
    world = World(dataclasses.replace(scene, scripts=(Script("child", STATIC, base, True),)))
    host = ScriptHost(world)
    attach, part = world.find("RG2_attachPoint"), world.find("Cuboid2")
    trace = []
    try:
        host.start()
        for _ in range(120):
            world.advance(0.1)
            phase = host.signals["int"].get("phase", 0)
            trace.append((phase, _relative(world, attach, part)[0], world.object_pose(part)[0]))
            if phase == 4:
                break
        errors = list(host.errors)
    finally:
        host.close()
        world.close()
    assert errors == []
    held = [r for r in trace if r[0] == 1]
    assert len(held) >= 10 and all(math.dist(r[1], (0.0, 0.0, 0.3)) < 0.002 for r in held)
    assert math.dist(held[0][2], held[-1][2]) > 0.3
    still = [r[2] for r in trace if r[0] == 2]
    assert still[0][2] > 0.3 and all(math.dist(z, still[0]) < 0.002 for z in still)
    fell = [r[2] for r in trace if r[0] == 3]
    assert fell[0][2] - fell[-1][2] > 0.2 and fell[-1][2] < 0.1


def test_breaking_a_sensor_inside_one_body_is_said_not_dropped():
    """A force sensor between two links of one pybullet body (the UR5's wrist and the RG2)
    cannot come apart here: breaking it is noted in the scene's notes; an attach point (nothing
    dynamic beyond it) breaks without a note."""
    world = World(str(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt")))
    try:
        assert world.break_force_sensor("RG2_attachPoint") == []
        assert not [n for n in world.model.notes if "broken" in n]
        world.break_force_sensor("UR5_connection")
        assert [n for n in world.model.notes if n.startswith("UR5_connection: broken")]
        assert world.force_sensor_broken("UR5_connection")
        world.reset()  # the scene rebuilt: no sensor is broken (CoppeliaSim restores them)
        assert not world.force_sensor_broken("UR5_connection")
    finally:
        world.close()
