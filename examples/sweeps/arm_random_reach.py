"""One random-target experiment on the 2W1A, made to be swept over seeds (legacy remote API).

Each run sends the arm (shoulder, elbow, wrist) to a few random targets in 0-300 degrees, lets
each settle, and reports how far the body was pushed from where it started, as lines
``RESULT key=value`` that ``sitegen remote-api sweep`` collects into results.csv. Python's
``random`` is seeded by the sweep (each run its own seed), so a run is reproducible and the
seeds give different targets. Written for this project (not course code); it runs unchanged in
CoppeliaSim with the 2W1A scene and a continuous remote API server on port 19997.

Run: sitegen remote-api sweep examples/sweeps/arm_random_reach.py --scene 2w1a --seeds 0:50
"""

import math
import random
import time

import sim

MOVES = 3  # random arm poses
SETTLE = 2.0  # seconds each pose is given
MOTORS = ("ShoulderMotor", "ElbowMotor", "WristMotor")

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
if client == -1:
    raise SystemExit("no remote API server on 127.0.0.1:19997")
blocking = sim.simx_opmode_blocking
handles = {name: sim.simxGetObjectHandle(client, name, blocking)[1] for name in (*MOTORS, "2W1A")}

sim.simxStartSimulation(client, blocking)
_, (x0, y0, _) = sim.simxGetObjectPosition(client, handles["2W1A"], -1, blocking)
path = 0.0
x, y = x0, y0
for move in range(MOVES):
    targets = [random.randint(0, 300) for _ in MOTORS]
    for name, degrees in zip(MOTORS, targets, strict=True):
        sim.simxSetJointTargetPosition(client, handles[name], math.radians(degrees), blocking)
    time.sleep(SETTLE)
    _, (nx, ny, _) = sim.simxGetObjectPosition(client, handles["2W1A"], -1, blocking)
    path += math.hypot(nx - x, ny - y)
    x, y = nx, ny
    print(f"move {move + 1}: targets {targets} deg, body at x={x:+.3f} m y={y:+.3f} m")
sim.simxStopSimulation(client, blocking)
sim.simxFinish(client)

print(f"RESULT distance={math.hypot(x - x0, y - y0):.4f} path={path:.4f}")
