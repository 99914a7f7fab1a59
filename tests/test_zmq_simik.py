"""``client.require('simIK')`` over the ZeroMQ remote API: the same simIK functions scene
scripts get (sims/simapi/ik.py), called by a Python client, on the UR5 of
course2/ur5WithRg2Grasping.ttt, checked by where the tip ends up against its target once the
joints' motors have driven the arm there (the joints in hybrid IK mode, as the scene's own
script sets them)."""

from __future__ import annotations

import pytest
from test_zmq_scripts import _run

BODY = """
simIK = client.require('simIK')
base, tip, target = (sim.getObject(p) for p in ('/UR5', '/UR5_ikTip', '/UR5_ikTarget'))
joints = [sim.getObject(f'/UR5_joint{i}') for i in range(1, 7)]
bent = [-70.1, 18.85, 93.18, 68.02, 109.9, 90]
for j, a in zip(joints, bent):
    sim.setJointMode(j, sim.jointmode_ik, 1)
    sim.setJointPosition(j, math.radians(a))
    sim.setJointTargetPosition(j, math.radians(a))
at = sim.getObjectPosition(tip, sim.handle_world)
sim.setObjectPosition(target, sim.handle_world, [at[0] + 0.05, at[1], at[2] + 0.1])
sim.setObjectQuaternion(target, sim.handle_world, sim.getObjectQuaternion(tip, sim.handle_world))
env = simIK.createEnvironment()
group = simIK.createGroup(env)
simIK.setGroupCalculation(env, group, simIK.method_damped_least_squares, 0.01, 20)
element, to_ik, to_sim = simIK.addElementFromScene(env, group, base, tip, target,
                                                   simIK.constraint_pose)
simIK.setElementPrecision(env, group, element, [0.0002, 0.001])
sim.setStepping(True)
sim.startSimulation()
# the joints' motors drive to what IK writes (0.4 s); from 0.85 s the scene's own threaded
# script starts moving the IK target itself
while sim.getSimulationTime() < 0.6:
    result, *_ = simIK.handleGroup(env, group, {'syncWorlds': True})
    sim.step()
a = sim.getObjectPosition(tip, sim.handle_world)
b = sim.getObjectPosition(target, sim.handle_world)
show(result=result, success=simIK.result_success, distance=math.dist(a, b),
     mapped=len(to_ik), moved=sum(abs(sim.getJointPosition(j) - math.radians(q))
                                  for j, q in zip(joints, bent)))
sim.stopSimulation()
"""


@pytest.mark.needs_shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt")
def test_a_zeromq_client_solves_ik_with_simik(tmp_path):
    from shared_data import shared

    scene = shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt")
    result, lines, err = _run(tmp_path, BODY, scene=str(scene))
    assert result.ok, (result.message, err)
    got = lines[0]
    assert got["result"] == got["success"]
    assert got["distance"] < 0.001  # the tip on its target, within a millimetre
    assert got["moved"] > 0.05 and got["mapped"] >= 6  # the scene's joints were written


def test_a_module_the_emulation_lacks_is_refused_naming_it(tmp_path):
    result, _, err = _run(tmp_path, "simOMPL = client.require('simOMPL')\n")
    assert not result.ok and "simOMPL" in (result.message or "") + err
