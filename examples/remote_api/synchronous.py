"""Synchronous (lock-step) operation, pausing, timing helpers and message info.

Run: sitegen remote-api run examples/remote_api/synchronous.py --scene 2w1a
"""

import math

import sim

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
print("connection id:", sim.simxGetConnectionId(client))
code, ping = sim.simxGetPingTime(client)
print("ping:", code, ping >= 0)

code, step = sim.simxGetFloatingParameter(
    client, sim.sim_floatparam_simulation_time_step, sim.simx_opmode_blocking
)
print("simulation step (s):", round(step, 3))

_, wrist = sim.simxGetObjectHandle(client, "WristMotor", sim.simx_opmode_blocking)
_, elbow = sim.simxGetObjectHandle(client, "ElbowMotor", sim.simx_opmode_blocking)

# Lock-step: the simulation advances one step per trigger.
print("synchronous:", sim.simxSynchronous(client, True))
print("start:", sim.simxStartSimulation(client, sim.simx_opmode_blocking))
sim.simxGetJointPosition(client, wrist, sim.simx_opmode_streaming)
sim.simxSetJointTargetPosition(client, wrist, math.radians(200), sim.simx_opmode_oneshot)
times = []
for _ in range(5):
    sim.simxSynchronousTrigger(client)
    sim.simxGetPingTime(client)  # waits until the triggered step is done
    times.append(sim.simxGetLastCmdTime(client))
print("simulation time after each trigger (ms):", times)
code, angle = sim.simxGetJointPosition(client, wrist, sim.simx_opmode_buffer)
print("wrist moved from 250 towards 200:", code, 200 <= round(math.degrees(angle)) < 250)
print("asynchronous again:", sim.simxSynchronous(client, False))

# Pause communication: commands sent together, applied in the same simulation pass.
sim.simxPauseCommunication(client, True)
sim.simxSetJointTargetPosition(client, wrist, math.radians(180), sim.simx_opmode_oneshot)
sim.simxSetJointTargetPosition(client, elbow, math.radians(90), sim.simx_opmode_oneshot)
sim.simxPauseCommunication(client, False)

# Pause and resume the simulation; the server state shows it.
print("pause:", sim.simxPauseSimulation(client, sim.simx_opmode_blocking))
code, state = sim.simxGetInMessageInfo(client, sim.simx_headeroffset_server_state)
print("server state running/paused bits:", code, state & 1, (state >> 1) & 1)
print("resume:", sim.simxStartSimulation(client, sim.simx_opmode_blocking))
code, state = sim.simxGetInMessageInfo(client, sim.simx_headeroffset_server_state)
print("paused bit after resume:", (state >> 1) & 1)
code, out_id = sim.simxGetOutMessageInfo(client, sim.simx_headeroffset_message_id)
print("messages sent so far > 10:", code, out_id > 10)

print("stop:", sim.simxStopSimulation(client, sim.simx_opmode_blocking))
code, state = sim.simxGetInMessageInfo(client, sim.simx_headeroffset_server_state)
print("running bit after stop:", state & 1)
sim.simxFinish(client)
