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
import resource
import time
from pathlib import Path

from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
SCRIPT = SHARED / "seeds" / "scripts" / "task2_2w1a_random.py"
TTT = SHARED / "data" / "scenes" / "vrep_remoteapi_ex" / "2w1a" / "2w1a.ttt"


ISOLATE = True


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the isolated script runs in
    one): steadier than wall time on a shared machine."""
    me, kids = (
        resource.getrusage(resource.RUSAGE_SELF),
        resource.getrusage(resource.RUSAGE_CHILDREN),
    )
    return me.ru_utime + me.ru_stime + kids.ru_utime + kids.ru_stime


def one(scene: str) -> tuple[float, float, float]:
    sink = io.StringIO()
    cpu = _cpu()
    started = time.perf_counter()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        result = run_script(SCRIPT, scene, seed=2021, trace=False, stderr=sink, isolate=ISOLATE)
    wall = time.perf_counter() - started
    cpu = _cpu() - cpu
    if not result.ok:
        raise SystemExit(f"{scene}: {result.message}")
    return result.sim_time, wall, cpu


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
    best: dict[str, tuple[float, float, float]] = {}
    for _ in range(args.repeat):
        for scene in scenes:
            sim, wall, cpu = one(scene)
            old = best.get(scene)
            best[scene] = (
                sim,
                min(wall, old[1]) if old else wall,
                min(cpu, old[2]) if old else cpu,
            )
    hand_wall = best["2w1a-hand"][0] / best["2w1a-hand"][1]
    hand_cpu = best["2w1a-hand"][0] / best["2w1a-hand"][2]
    print(
        f"{'scene':<26} {'sim s':>6} {'wall s':>7} {'x real':>7} {'vs hand':>8}"
        f" {'cpu s':>7} {'x real':>7} {'vs hand':>8}"
    )
    for scene, (sim, wall, cpu) in best.items():
        label = "2w1a.ttt (course file)" if scene.endswith(".ttt") else scene
        print(
            f"{label:<26} {sim:>6.1f} {wall:>7.2f} {sim / wall:>7.0f}"
            f" {sim / wall / hand_wall:>8.2f}"
            f" {cpu:>7.2f} {sim / cpu:>7.0f} {sim / cpu / hand_cpu:>8.2f}"
        )
    print("(best of --repeat runs; wall = elapsed, cpu = CPU time of the run, its child included)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
