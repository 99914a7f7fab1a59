"""IK from the scene's scripts (issue 28, kinematics): CoppeliaSim 4.x's ``simIK`` plug-in
(4.2-4.5 names and 4.6's) on IK groups a script builds from the scene, and the 3.x ``sim.*``
IK calls on the group saved with the scene, on the UR5 of course2/ur5WithRg2Grasping.ttt,
checked by where the tip ends up against its target (within a millimetre)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
from shared_data import shared

from sims.lua.host import ScriptHost
from sims.quiet import pybullet as p
from sims.scene.load import load_scene
from sims.scene.model import Script
from sims.world import World

# the arm bent over the belt (the scene's own pick configuration), its joints put in hybrid IK
# mode as the scene's own script does (IK sets the targets their motors drive to), the target
# moved 5 cm out and 10 cm up from the tip (clear of the belt below: 10 cm down, the gripper
# presses on the belt and the shoulder stops 1.5 deg short, 2 cm off, as it would in CoppeliaSim)
SETUP = """
    base = sim.getObjectHandle('UR5')
    tip = sim.getObjectHandle('UR5_ikTip')
    target = sim.getObjectHandle('UR5_ikTarget')
    joints = {}
    local bent = {-70.1, 18.85, 93.18, 68.02, 109.9, 90}
    for i = 1, 6 do
        joints[i] = sim.getObjectHandle('UR5_joint' .. i)
        sim.setJointMode(joints[i], sim.jointmode_ik, 1)
        sim.setJointPosition(joints[i], bent[i] * math.pi / 180)
        sim.setJointTargetPosition(joints[i], bent[i] * math.pi / 180)
    end
    local at = sim.getObjectPosition(tip, -1)
    sim.setObjectPosition(target, -1, {at[1] + 0.05, at[2], at[3] + 0.1})
    sim.setObjectQuaternion(target, -1, sim.getObjectQuaternion(tip, -1))
    local function scene()
        local q = {}
        for i = 1, 6 do q[i] = sim.getJointPosition(joints[i]) end
        return q
    end
    start = scene()
    function sceneMoved()
        local q, d = scene(), 0
        for i = 1, 6 do d = d + math.abs(q[i] - start[i]) end
        return d
    end
"""

SIMIK_42 = (
    "function sysCall_init()\n"
    + SETUP
    + """
    env = simIK.createEnvironment()
    group = simIK.createIkGroup(env)
    simIK.setIkGroupCalculation(env, group, simIK.method_damped_least_squares, 0.01, 20)
    local element, map = simIK.addIkElementFromScene(env, group, base, tip, target,
                                                     simIK.constraint_pose)
    simIK.setIkElementPrecision(env, group, element, {0.0002, 0.001})
    ikJoints = {}
    for i = 1, 6 do ikJoints[i] = map[joints[i]] end
    -- inside the environment only: the scene's joints stay
    sim.setIntegerSignal('envResult', simIK.handleIkGroup(env, group))
    local d = 0
    for i = 1, 6 do d = d + math.abs(simIK.getJointPosition(env, ikJoints[i]) - start[i]) end
    sim.setFloatSignal('envMoved', d)
    sim.setFloatSignal('sceneMovedByEnv', sceneMoved())
end

function sysCall_actuation()
    sim.setIntegerSignal('result', simIK.applyIkEnvironmentToScene(env, group))
end
"""
)

SIMIK_46 = (
    "function sysCall_init()\n"
    + SETUP
    + """
    env = simIK.createEnvironment()
    group = simIK.createGroup(env)
    simIK.setGroupCalculation(env, group, simIK.method_damped_least_squares, 0.01, 20)
    local element, toIk, toSim = simIK.addElementFromScene(env, group, base, tip, target,
                                                           simIK.constraint_position)
    ikJoints = {}
    for i = 1, 6 do ikJoints[i] = toIk[joints[i]] end
    sim.setIntegerSignal('mapsAgree', toSim[ikJoints[3]] == joints[3] and 1 or 0)
    -- a configuration for the target; the validation callback turns the first one down
    local tried, first = 0, nil
    local config = simIK.findConfig(env, group, ikJoints, 0.65, 0.5, {1, 1, 1, 0.1},
        function(c)
            tried = tried + 1
            if tried == 1 then first = c[1] end
            return tried > 1
        end)
    sim.setFloatSignal('rejectedFirst', first)
    sim.setIntegerSignal('found', config and 1 or 0)
    sim.setIntegerSignal('tried', tried)
    sim.setFloatSignal('sceneMovedByFind', sceneMoved())
    if config then
        for i = 1, 6 do sim.setJointPosition(joints[i], config[i]) end
        local a, b = sim.getObjectPosition(tip, -1), sim.getObjectPosition(target, -1)
        sim.setFloatSignal('configDistance',
            math.sqrt((a[1] - b[1])^2 + (a[2] - b[2])^2 + (a[3] - b[3])^2))
        sim.setFloatSignal('configFirst', config[1])
    end
    -- then the target 8 cm along y, followed by handleGroup with the wrist roll passive
    for i = 1, 6 do sim.setJointPosition(joints[i], start[i]) end
    simIK.setJointMode(env, ikJoints[6], simIK.jointmode_passive)
    local at = sim.getObjectPosition(target, -1)
    sim.setObjectPosition(target, -1, {at[1], at[2] + 0.08, at[3]})
end

function sysCall_actuation()
    local wrist = sim.getJointPosition(joints[6])
    local result, flags, precision = simIK.handleGroup(env, group, {syncWorlds = true})
    if sim.getJointPosition(joints[6]) ~= wrist then sim.setIntegerSignal('wristWritten', 1) end
    sim.setIntegerSignal('result', result)
    sim.setIntegerSignal('flags', flags)
    sim.setFloatSignal('linear', precision[1])
end
"""
)

SIM_3X = (
    "function sysCall_init()\n"
    + SETUP
    + """
    group = sim.getIkGroupHandle('UR5')
    sim.setIkGroupProperties(group, sim.ik_damped_least_squares_method, 20, 0.01)
    sim.setIkElementProperties(group, tip, sim.ik_x_constraint + sim.ik_y_constraint
        + sim.ik_z_constraint + sim.ik_alpha_beta_constraint + sim.ik_gamma_constraint,
        {0.0002, 0.001})
    local config = sim.getConfigForTipPose(group, joints, 0.65, 100)
    if config then
        for i = 1, 6 do sim.setJointPosition(joints[i], config[i]) end
        local a, b = sim.getObjectPosition(tip, -1), sim.getObjectPosition(target, -1)
        sim.setFloatSignal('configDistance',
            math.sqrt((a[1] - b[1])^2 + (a[2] - b[2])^2 + (a[3] - b[3])^2))
        for i = 1, 6 do sim.setJointPosition(joints[i], start[i]) end
    end
end

function sysCall_actuation()
    sim.setIntegerSignal('result', sim.handleIkGroup(group))
end
"""
)


def _run(text: str, seconds: float = 1.0):
    scene = load_scene(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt"))
    base = scene.objects[[o.name for o in scene.objects].index("UR5")].handle
    world = World(dataclasses.replace(scene, scripts=(Script("child", text, base),)))
    host = ScriptHost(world)
    try:
        host.start()
        world.advance(seconds)
        tip, target = world.object_pose("UR5_ikTip"), world.object_pose("UR5_ikTarget")
        ints, floats = dict(host.signals["int"]), dict(host.signals["float"])
        return list(host.errors), ints, floats, (tip, target)
    finally:
        host.close()
        world.close()


def _angle(a, b) -> float:
    ra = np.array(p.getMatrixFromQuaternion(a)).reshape(3, 3)
    rb = np.array(p.getMatrixFromQuaternion(b)).reshape(3, 3)
    return math.acos(max(-1.0, min(1.0, (np.trace(ra @ rb.T) - 1) / 2)))


def test_simik_42_environment_solves_apart_and_applies_the_pose_to_the_scene():
    errors, ints, floats, (tip, target) = _run(SIMIK_42)
    assert errors == []
    # handleIkGroup moved the environment's joints, not the scene's
    assert ints["envResult"] in (1, 2) and floats["envMoved"] > 0.05
    assert floats["sceneMovedByEnv"] == 0.0
    # applyIkEnvironmentToScene each pass: the tip on the target, pose within 1 mm / 0.1 deg
    assert ints["result"] == 1
    assert math.dist(tip[0], target[0]) < 0.001
    assert _angle(tip[1], target[1]) < math.radians(0.1)


def test_simik_46_find_config_and_handle_group_with_a_passive_joint():
    errors, ints, floats, (tip, target) = _run(SIMIK_46)
    assert errors == []
    assert ints["mapsAgree"] == 1
    # findConfig: the second configuration (the callback turned the first down), its tip on
    # the target
    assert ints["found"] == 1 and ints["tried"] == 2
    assert floats["configFirst"] != floats["rejectedFirst"]
    assert floats["configDistance"] < 0.001
    assert floats["sceneMovedByFind"] == 0.0
    # handleGroup (syncWorlds): the tip's position on the moved target; the wrist roll, passive
    # in the environment, is never written to the scene
    assert ints["result"] == 1 and ints["flags"] == 0 and floats["linear"] < 0.001
    assert math.dist(tip[0], target[0]) < 0.001
    assert "wristWritten" not in ints


def test_sim_3x_ik_group_of_the_scene_with_its_properties_set_by_the_script():
    errors, ints, floats, (tip, target) = _run(SIM_3X)
    assert errors == []
    assert floats["configDistance"] < 0.001  # sim.getConfigForTipPose
    assert ints["result"] == 1  # sim.handleIkGroup each pass
    assert math.dist(tip[0], target[0]) < 0.001
    assert _angle(tip[1], target[1]) < math.radians(0.1)
