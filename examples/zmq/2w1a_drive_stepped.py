"""The 2W1A robot crawls by its arm, driven through CoppeliaSim's ZeroMQ remote API (stepping).

The 2W1A's two wheels roll freely; only its arm (shoulder, elbow, wrist motors) is driven. The
script swings the arm between a reaching pose and a pulling pose, a few times over, and prints
where the body is after each stroke. Stepping mode (``sim.setStepping(True)``) makes the
simulation advance only on ``sim.step()``, one 50 ms step at a time, so each pose gets exactly
the same simulated time however slow the script is. Written for this project (not course code);
it runs unchanged in CoppeliaSim 4.3 or later with the 2W1A scene loaded and the ZeroMQ remote
API add-on running.

Run: sitegen remote-api run examples/zmq/2w1a_drive_stepped.py --scene 2w1a
"""

import math

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

REACH = {"ShoulderMotor": 40, "ElbowMotor": 200, "WristMotor": 280}  # degrees
PULL = {"ShoulderMotor": 160, "ElbowMotor": 140, "WristMotor": 160}
STROKES = 8
STEPS_PER_POSE = 16  # 0.8 s of simulated time

client = RemoteAPIClient("localhost", 23000)
sim = client.require("sim")

body = sim.getObject("/2W1A")
arm = {name: sim.getObject(f"/2W1A/{name}") for name in REACH}


def hold(pose, steps):
    """Send the arm to ``pose`` and let ``steps`` simulation steps pass."""
    for name, degrees in pose.items():
        sim.setJointTargetPosition(arm[name], math.radians(degrees))
    for _ in range(steps):
        sim.step()


sim.setStepping(True)
sim.startSimulation()
x0, y0, _ = sim.getObjectPosition(body, sim.handle_world)
print(f"simulation started, stepping; body at x={x0:+.3f} m y={y0:+.3f} m")

for stroke in range(1, STROKES + 1):
    hold(REACH, STEPS_PER_POSE)
    hold(PULL, STEPS_PER_POSE)
    x, y, _ = sim.getObjectPosition(body, sim.handle_world)
    t = sim.getSimulationTime()
    moved = math.hypot(x - x0, y - y0)
    print(f"stroke {stroke}: t={t:4.1f} s  x={x:+.3f} m  y={y:+.3f} m  ({moved:.3f} m from start)")

hold(PULL, 20)  # rest
angles = [round(math.degrees(sim.getJointPosition(arm[name]))) for name in REACH]
x, y, _ = sim.getObjectPosition(body, sim.handle_world)
print(f"end: x={x:+.3f} m y={y:+.3f} m, arm at {angles} deg")
sim.stopSimulation()
print("simulation stopped")
