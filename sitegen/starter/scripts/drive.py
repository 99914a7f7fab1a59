"""Drive the rover: forward until its proximity sensor sees a wall, then turn on the spot.

A CoppeliaSim legacy remote API script, as a student runs it against the simulator. sitegen runs
it unchanged on scenes/rover.simscene.xml in pybullet and films it (the clip `rover` in
sitegen.yml). Try it alone:

    sitegen remote-api run scripts/drive.py --scene scenes/rover.simscene.xml
"""

import time

import sim

SPEED = 6.0  # rad/s on each wheel
NEAR = 0.3  # m: closer than this, turn

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
if client == -1:
    raise SystemExit("could not connect to the simulator")

B = sim.simx_opmode_blocking
_, left = sim.simxGetObjectHandle(client, "LeftMotor", B)
_, right = sim.simxGetObjectHandle(client, "RightMotor", B)
_, sensor = sim.simxGetObjectHandle(client, "FrontSensor", B)
sim.simxStartSimulation(client, B)
sim.simxReadProximitySensor(client, sensor, sim.simx_opmode_streaming)

turns, turning = 0, 0  # turns begun; control steps of the current turn still to go
began = time.time()
while time.time() - began < 10.0:
    code, seen, point, _obj, _normal = sim.simxReadProximitySensor(
        client, sensor, sim.simx_opmode_buffer
    )
    if turning == 0 and code == 0 and seen and sum(c * c for c in point) ** 0.5 < NEAR:
        turns, turning = turns + 1, 12  # 1.2 s on the spot: about a quarter turn
    sim.simxSetJointTargetVelocity(client, left, -SPEED / 2 if turning else SPEED, B)
    sim.simxSetJointTargetVelocity(client, right, SPEED / 2 if turning else SPEED, B)
    turning = max(0, turning - 1)
    time.sleep(0.1)

print("turns:", turns)
sim.simxStopSimulation(client, B)
sim.simxFinish(client)
