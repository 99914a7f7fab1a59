"""The course's cart, driven by its front proximity sensor through the legacy remote API.

The cart scene's server is a temporary one (CoppeliaSim's child script starts it with
simRemoteApi.start(19999)): the simulation is already running when the script connects, and
the script cannot start or stop it.

Run: sitegen remote-api run examples/remote_api/cart_obstacles.py --scene cart
"""

import math
import time

import sim

client = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
if client == -1:
    raise SystemExit("Could not connect")

code, state = sim.simxGetInMessageInfo(client, sim.simx_headeroffset_server_state)
print("simulation running:", bool(state & 1))
print("start refused:", sim.simxStartSimulation(client, sim.simx_opmode_blocking))

_, left = sim.simxGetObjectHandle(client, "left_m", sim.simx_opmode_blocking)
_, right = sim.simxGetObjectHandle(client, "right_m", sim.simx_opmode_blocking)
_, cart = sim.simxGetObjectHandle(client, "cart", sim.simx_opmode_blocking)
_, sensor = sim.simxGetObjectHandle(client, "Proximity_sensor", sim.simx_opmode_blocking)

code, joints = sim.simxGetObjects(client, sim.sim_object_joint_type, sim.simx_opmode_blocking)
print("joints:", len(joints))
code, handles, _, _, names = sim.simxGetObjectGroupData(
    client, sim.sim_appobj_object_type, 0, sim.simx_opmode_blocking
)
print("objects:", ", ".join(names))
code, handles, _, floats, _ = sim.simxGetObjectGroupData(
    client, sim.sim_object_joint_type, 15, sim.simx_opmode_blocking
)
print("joint states:", code, len(floats))

# Stream the sensor and the pose; the first streaming calls return novalue.
sim.simxReadProximitySensor(client, sensor, sim.simx_opmode_streaming)
sim.simxGetObjectPosition(client, cart, -1, sim.simx_opmode_streaming)
start = time.time()
turns = 0
mode = None
while time.time() - start < 20:
    code, detected, point, obj, normal = sim.simxReadProximitySensor(
        client, sensor, sim.simx_opmode_buffer
    )
    near = code == sim.simx_return_ok and detected and math.dist(point, (0, 0, 0)) < 0.3
    wanted = "turn" if near else "forward"
    if wanted != mode:
        mode = wanted
        turns += mode == "turn"
        speeds = (-1.0, 1.0) if mode == "turn" else (2.0, 2.0)
        sim.simxPauseCommunication(client, True)  # both wheels change in the same pass
        sim.simxSetJointTargetVelocity(client, left, speeds[0], sim.simx_opmode_oneshot)
        sim.simxSetJointTargetVelocity(client, right, speeds[1], sim.simx_opmode_oneshot)
        sim.simxPauseCommunication(client, False)
    time.sleep(0.05)

code, pos = sim.simxGetObjectPosition(client, cart, -1, sim.simx_opmode_buffer)
code, lin, ang = sim.simxGetObjectVelocity(client, cart, sim.simx_opmode_blocking)
code, torque = sim.simxGetJointForce(client, left, sim.simx_opmode_blocking)
code, euler = sim.simxGetObjectOrientation(client, cart, -1, sim.simx_opmode_blocking)
print("turns:", turns)
print("travelled:", round(math.hypot(pos[0], pos[1]), 2) > 0.5)
print("speed:", round(math.hypot(lin[0], lin[1]), 2))
print("heading (deg):", round(math.degrees(euler[2])))
print("left wheel torque reported:", code == sim.simx_return_ok)

for wheel in (left, right):
    sim.simxSetJointTargetVelocity(client, wheel, 0, sim.simx_opmode_blocking)
print("stop refused:", sim.simxStopSimulation(client, sim.simx_opmode_blocking))
sim.simxFinish(client)
