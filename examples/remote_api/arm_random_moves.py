"""The 2W1A robot's arm moved to random angles, a few simulations in a row (legacy remote API).

The same kind of experiment as the course's stage 3 task 2: each simulation sends the shoulder,
elbow and wrist motors to random targets in 0-300 degrees, lets them settle, reads back where
the joints and the body ended up, and stops; the scene resets before the next simulation.
Written for this project (not course code); it runs unchanged in CoppeliaSim with the 2W1A scene
and a continuous remote API server on port 19997.

Run: sitegen remote-api run examples/remote_api/arm_random_moves.py --scene 2w1a
"""

import math
import random
import time

import sim

SIMULATIONS = 2  # simulations in a row, each from the reset scene
MOVES = 5  # random arm poses per simulation
SETTLE = 4.0  # seconds each pose is given to settle
MOTORS = ("ShoulderMotor", "ElbowMotor", "WristMotor")

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
if client == -1:
    raise SystemExit("no remote API server on 127.0.0.1:19997")

blocking = sim.simx_opmode_blocking
handles = {}
for name in (*MOTORS, "2W1A"):
    code, handles[name] = sim.simxGetObjectHandle(client, name, blocking)
    if code != sim.simx_return_ok:
        raise SystemExit(f"the scene has no object called {name}")
body = handles["2W1A"]

random.seed()
for run in range(1, SIMULATIONS + 1):
    sim.simxStartSimulation(client, blocking)
    print(f"simulation {run} started")
    # Streaming: the server sends the body's pose every pass; reads below use the buffer.
    sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_streaming)
    for move in range(1, MOVES + 1):
        targets = {name: random.uniform(0.0, 300.0) for name in MOTORS}
        for name, degrees in targets.items():
            sim.simxSetJointTargetPosition(
                client, handles[name], math.radians(degrees), sim.simx_opmode_oneshot
            )
        time.sleep(SETTLE)
        reached = []
        for name in MOTORS:
            _, angle = sim.simxGetJointPosition(client, handles[name], blocking)
            reached.append(f"{name} {targets[name]:.0f}->{math.degrees(angle):.0f}")
        _, (x, y, _z) = sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_buffer)
        print(f"  move {move}: {', '.join(reached)}; body at x={x:.3f} y={y:.3f} m")
    sim.simxStopSimulation(client, blocking)
    time.sleep(0.5)  # let the stop finish before the next start
    print(f"simulation {run} stopped")

sim.simxFinish(client)
