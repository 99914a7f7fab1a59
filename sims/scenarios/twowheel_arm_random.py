"""2w1a-random: the course experiment (shared/seeds/scripts/task2_2w1a_random.py) in pybullet.

Three runs; each starts from the saved scene, then five times commands random targets in
0..300 degrees to the three arm motors and waits 5 s. As in the course script the targets are
drawn wrist, elbow, shoulder with ``randint(0, 300)``, from ``random.Random(seed)`` instead of
an unseeded generator, so a seed fixes the run.
"""

from __future__ import annotations

import math
import random

from sims.recording import Recorder
from sims.scenarios import Scenario
from sims.world import World

ARM = ("ShoulderMotor", "ElbowMotor", "WristMotor")


def run(world: World, params: dict, record: Recorder) -> None:
    rng = random.Random(world.seed)
    for run_index in range(params["runs"]):
        if run_index:
            world.reset()  # CoppeliaSim's stop + start: back to the saved scene
        record.note(f"run {run_index + 1} started")
        for move in range(params["moves"]):
            wrist, elbow, shoulder = (rng.randint(0, 300) for _ in range(3))
            targets = {"ShoulderMotor": shoulder, "ElbowMotor": elbow, "WristMotor": wrist}
            for joint, deg in targets.items():
                world.set_joint_target_position(joint, math.radians(deg))
            record.note(
                f"run {run_index + 1} move {move + 1}: targets {shoulder} {elbow} {wrist}",
                targets_deg=[shoulder, elbow, wrist],
            )
            world.advance(params["move_seconds"])
            reached = [round(math.degrees(world.joint_position(j)), 2) for j in ARM]
            (x, y, _), _ = world.object_pose("2W1A")
            record.note(
                f"run {run_index + 1} move {move + 1}: reached",
                reached_deg=reached,
                position=[round(x, 4), round(y, 4)],
            )


SCENARIO = Scenario(
    name="2w1a-random",
    description="2W1A robot: 3 runs of 5 random arm moves (0-300 deg, 5 s each); the hand "
    "pushes on the floor and the body rolls and drags its tail.",
    scene="2w1a",
    run=run,
    duration=lambda p: p["runs"] * p["moves"] * p["move_seconds"],
    seed=2021,
    params={"runs": 3, "moves": 5, "move_seconds": 5.0},
    joints=ARM,
    joint_quantity="angle",
)
