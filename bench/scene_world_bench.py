"""The course's 80 s 2W1A experiment on the scene-built and on the hand-built robot, side by side.

    python bench/scene_world_bench.py [--repeat N]

Runs ``../shared/seeds/scripts/task2_2w1a_random.py`` (3 simulations of 5 random arm moves, 5 s
each) unchanged through the legacy remote API emulation, on a virtual clock, once per scene per
repeat, alternating the scenes so both see the same machine load: ``2w1a`` (built from
sims/scene/bundled/2w1a.scene.json, derived from the course's 2w1a.ttt), ``2w1a-hand`` (the model
written in Python) and, when the course data is there, ``2w1a.ttt`` read from the file. Prints
simulated seconds, wall seconds and the speed (simulated / wall) of each, the best of the
repeats, and the ratio of each to the hand model. Figures depend on the machine; compare the
ratio, measured in one run.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import time
from pathlib import Path

from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
SCRIPT = SHARED / "seeds" / "scripts" / "task2_2w1a_random.py"
TTT = SHARED / "data" / "scenes" / "vrep_remoteapi_ex" / "2w1a" / "2w1a.ttt"


def one(scene: str) -> tuple[float, float]:
    sink = io.StringIO()
    started = time.perf_counter()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        result = run_script(SCRIPT, scene, seed=2021, trace=False, stderr=sink)
    wall = time.perf_counter() - started
    if not result.ok:
        raise SystemExit(f"{scene}: {result.message}")
    return result.sim_time, wall


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    if not SCRIPT.is_file():
        print(f"skipped: {SCRIPT} is not there (the course's shared folder)")
        return 0
    scenes = ["2w1a-hand", "2w1a"] + ([str(TTT)] if TTT.is_file() else [])
    for scene in scenes:  # warm up: imports, scene files read once
        one(scene)
    best: dict[str, tuple[float, float]] = {}
    for _ in range(args.repeat):
        for scene in scenes:
            sim, wall = one(scene)
            if scene not in best or wall < best[scene][1]:
                best[scene] = (sim, wall)
    hand = best["2w1a-hand"][0] / best["2w1a-hand"][1]
    print(f"{'scene':<28} {'simulated s':>12} {'wall s':>8} {'x real time':>12} {'vs hand':>8}")
    for scene, (sim, wall) in best.items():
        label = "2w1a.ttt (course file)" if scene.endswith(".ttt") else scene
        speed = sim / wall
        print(f"{label:<28} {sim:>12.1f} {wall:>8.2f} {speed:>12.0f} {speed / hand:>8.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
