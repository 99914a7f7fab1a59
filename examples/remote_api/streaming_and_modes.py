"""Operation modes of the legacy remote API, shown on the 2W1A scene.

Run: sitegen remote-api run examples/remote_api/streaming_and_modes.py --scene 2w1a
(CoppeliaSim would behave the same way with this script.)
"""

import math
import time

import sim

sim.simxFinish(-1)
client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
print("client id:", client)

_, body = sim.simxGetObjectHandle(client, "2W1A", sim.simx_opmode_blocking)
_, shoulder = sim.simxGetObjectHandle(client, "ShoulderMotor", sim.simx_opmode_blocking)

# Streaming: the first call has no reply yet -> novalue (1) and zeroed outputs.
code, pos = sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_streaming)
print("streaming first call:", code, pos)
time.sleep(0.1)
code, pos = sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_buffer)
print("buffer after streaming:", code, [round(v, 4) for v in pos])

# Buffer on a command that never streamed: novalue.
code, angle = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_buffer)
print("buffer without stream:", code, angle)

# Blocking: the reply comes back at once, and is not kept for later buffer reads.
code, angle = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_blocking)
print("blocking joint position:", code, round(math.degrees(angle), 1))
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_buffer)
print("buffer after blocking:", code)

# Oneshot setters: the first call returns novalue, later calls the previous reply (ok).
print(
    "oneshot status bar 1:", sim.simxAddStatusbarMessage(client, "hello", sim.simx_opmode_oneshot)
)
print(
    "oneshot status bar 2:", sim.simxAddStatusbarMessage(client, "again", sim.simx_opmode_oneshot)
)

# Oneshot getters return the previous reply to the same command.
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_oneshot)
print("oneshot getter first:", code)
code, angle = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_oneshot)
print("oneshot getter second:", code, round(math.degrees(angle), 1))

# The simulation runs only after simxStartSimulation (continuous server); streamed values follow.
print("start:", sim.simxStartSimulation(client, sim.simx_opmode_blocking))
sim.simxSetJointTargetPosition(client, shoulder, math.radians(60), sim.simx_opmode_blocking)
# A reply to this command is already in the buffer (from the oneshot calls above), so the
# first streaming call returns it at once (code 0) instead of novalue.
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_streaming)
print("joint streaming first call:", code)
for _ in range(3):
    time.sleep(1.0)
    code, angle = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_buffer)
    print("shoulder (buffer):", code, round(math.degrees(angle)))
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_streaming + 100)
print("streaming again (with delay):", code)

# Discontinue stops the stream; the last reply stays until removed.
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_discontinue)
print("discontinue:", code)
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_remove)
print("remove:", code)
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_remove)
print("remove again:", code)
code, _ = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_buffer)
print("buffer after remove:", code)

# Stopping resets the scene, as CoppeliaSim restores the initial state.
print("stop:", sim.simxStopSimulation(client, sim.simx_opmode_blocking))
code, angle = sim.simxGetJointPosition(client, shoulder, sim.simx_opmode_blocking)
print("shoulder after stop:", round(math.degrees(angle)))
sim.simxFinish(client)
print("connection id after finish:", sim.simxGetConnectionId(client))
