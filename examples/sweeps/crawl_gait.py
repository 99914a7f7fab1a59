"""A 2W1A crawling gait with its angles as arguments: what a genetic algorithm searches over.

The 2W1A's wheels roll freely; it moves only by swinging its arm between a reaching pose and a
pulling pose. The six angles of the two poses (degrees) are arguments, ``--reach_shoulder=40``
and so on (``sitegen remote-api sweep --grid`` and ``sims.runs.evaluate`` pass them that way);
the script runs a few strokes in stepping mode (ZeroMQ remote API) and reports how far the body
got from where it started as ``RESULT distance=...``. Written for this project (not course
code); it runs unchanged in CoppeliaSim 4.3+ with the 2W1A scene and the ZeroMQ remote API
add-on.

Run: sitegen remote-api run examples/sweeps/crawl_gait.py --scene 2w1a -- --reach_elbow=220
"""

import argparse
import math

from coppeliasim_zmqremoteapi_client import RemoteAPIClient

DEFAULTS = {
    "reach_shoulder": 40,
    "reach_elbow": 200,
    "reach_wrist": 280,
    "pull_shoulder": 160,
    "pull_elbow": 140,
    "pull_wrist": 160,
}
JOINTS = ("ShoulderMotor", "ElbowMotor", "WristMotor")

parser = argparse.ArgumentParser()
for name, value in DEFAULTS.items():
    parser.add_argument(f"--{name}", type=float, default=value)
parser.add_argument("--strokes", type=int, default=4)
parser.add_argument("--steps", type=int, default=16, help="simulation steps per pose (50 ms)")
args = parser.parse_args()

client = RemoteAPIClient("localhost", 23000)
sim = client.require("sim")
body = sim.getObject("/2W1A")
arm = [sim.getObject(f"/2W1A/{name}") for name in JOINTS]
reach = [args.reach_shoulder, args.reach_elbow, args.reach_wrist]
pull = [args.pull_shoulder, args.pull_elbow, args.pull_wrist]


def hold(pose):
    for joint, degrees in zip(arm, pose, strict=True):
        sim.setJointTargetPosition(joint, math.radians(degrees))
    for _ in range(args.steps):
        sim.step()


sim.setStepping(True)
sim.startSimulation()
x0, y0, _ = sim.getObjectPosition(body, sim.handle_world)
for _ in range(args.strokes):
    hold(reach)
    hold(pull)
x, y, z = sim.getObjectPosition(body, sim.handle_world)
sim.stopSimulation()
print(f"RESULT distance={math.hypot(x - x0, y - y0):.4f} dx={x - x0:.4f} dy={y - y0:.4f}")
