"""A rover roams its arena: a scene file of this repository driven through the legacy remote API.

Run:
    sitegen remote-api run examples/remote_api/rover_scene.py \
        --scene data/scenes/rover.simscene.xml

The scene (data/scenes/rover.simscene.xml, CoppeliaSim's XML format) holds a walled arena with a
crate, a drum and a ball, and the rover: two wheel motors in velocity mode, a cone-shaped
proximity sensor looking ahead and a 64x48 camera (a vision sensor). The script drives forward,
turns left on the spot whenever the sensor sees something closer than 0.3 m, and reports what it
saw.
Objects are looked up both by name and by CoppeliaSim 4.x path.
"""

import math
import time

import sim

B = sim.simx_opmode_blocking
SPEED = 6.0  # rad/s: 0.24 m/s on 40 mm wheels
NEAR = 0.3  # m
DRIVE_SECONDS = 20.0

sim.simxFinish(-1)
client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
if client == -1:
    raise SystemExit("no connection")

_, rover = sim.simxGetObjectHandle(client, "Rover", B)
_, left = sim.simxGetObjectHandle(client, "/Rover/LeftMotor", B)
_, right = sim.simxGetObjectHandle(client, "RightMotor", B)
_, sensor = sim.simxGetObjectHandle(client, "/Rover/FrontSensor", B)
_, camera = sim.simxGetObjectHandle(client, "/Rover/Camera", B)
print("handles found:", all(h > 0 for h in (rover, left, right, sensor, camera)))

# motors: the saved torque limit, raised a little (simxSetJointForce is the 3.x name)
sim.simxSetJointForce(client, left, 0.4, B)
sim.simxSetJointMaxForce(client, right, 0.4, B)
print("max torque (N*m):", round(sim.simxGetJointMaxForce(client, left, B)[1], 2))

# a spherical-joint call on a revolute joint is refused by the server
print("spherical matrix on a wheel:", sim.simxSetSphericalJointMatrix(client, left, [0] * 12, B))

sim.simxStartSimulation(client, B)
_, start = sim.simxGetObjectPosition(client, rover, -1, B)
sim.simxReadProximitySensor(client, sensor, sim.simx_opmode_streaming)
sim.simxGetObjectPosition(client, rover, -1, sim.simx_opmode_streaming)
turns, nearest, farthest, began = 0, None, 0.0, time.time()
turn_left = 0  # control steps of turning still to do
while time.time() - began < DRIVE_SECONDS:
    code, seen, point, _obj, _normal = sim.simxReadProximitySensor(
        client, sensor, sim.simx_opmode_buffer
    )
    distance = math.dist(point, (0, 0, 0)) if code == 0 and seen else None
    if distance is not None:
        nearest = distance if nearest is None else min(nearest, distance)
    if distance is not None and distance < NEAR and turn_left == 0:
        turns += 1
        turn_left = 12  # turn on the spot for 1.2 s, about 80 degrees
    turning = turn_left > 0
    turn_left = max(0, turn_left - 1)
    sim.simxSetJointTargetVelocity(client, left, -SPEED / 2 if turning else SPEED, B)
    sim.simxSetJointTargetVelocity(client, right, SPEED / 2 if turning else SPEED, B)
    time.sleep(0.1)
    _, here = sim.simxGetObjectPosition(client, rover, -1, sim.simx_opmode_buffer)
    farthest = max(farthest, math.dist(start[:2], here[:2]))

_, end = sim.simxGetObjectPosition(client, rover, -1, B)
code, resolution, image = sim.simxGetVisionSensorImage(client, camera, 0, B)
brightness = sum(v & 0xFF for v in image) / max(1, len(image))
print("camera image:", code, resolution, len(image) == resolution[0] * resolution[1] * 3)
print("camera mean brightness > 30:", brightness > 30)
code, detection, packets = sim.simxReadVisionSensor(client, camera, B)
print("vision sensor read:", code)
reply = sim.simxCallScriptFunction(
    client, "Rover", sim.sim_scripttype_childscript, "hello", [], [], [], bytearray(), B
)
print("script function of a scene without scripts:", reply[0])
code, matrix = sim.simxGetJointMatrix(client, left, B)
print("wheel joint matrix is a rotation about z:", code == 0 and abs(matrix[10] - 1) < 1e-6)
print("went more than 1.5 m away from the start:", farthest > 1.5)
print("moved since the start:", math.dist(start[:2], end[:2]) > 0.1)
print("turns:", turns)
print("nearest seen (m) below 0.3:", nearest is not None and nearest < NEAR)
sim.simxStopSimulation(client, B)
sim.simxFinish(client)
