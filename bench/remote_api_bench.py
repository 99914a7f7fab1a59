"""Benchmark: the course's 2W1A remote API script on the emulation, against real time.

    python bench/remote_api_bench.py [--runs N] [--min-ratio R] [--script PATH]

Runs the script (virtual clock, seed = run index) N times with its output silenced and prints,
per run and as a median: simulated seconds, wall seconds and their ratio (how many times
faster than real time). For scale it also times the bare physics of the same number of steps.
Exits 1 when the median ratio is below ``--min-ratio`` (default 30).
"""

from __future__ import annotations

import argparse
import contextlib
import io
import statistics
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))
DEFAULT_SCRIPT = REPO.parent / "shared" / "seeds" / "scripts" / "task2_2w1a_random.py"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--min-ratio", type=float, default=30.0)
    parser.add_argument("--script", type=Path, default=DEFAULT_SCRIPT)
    parser.add_argument("--scene", default="2w1a")
    args = parser.parse_args(argv)

    from sims.remote_api.runner import run_script
    from sims.world import World

    if not args.script.is_file():
        print(f"no script at {args.script}", file=sys.stderr)
        return 2
    ratios, sims, walls = [], [], []
    print(
        f"{'run':>3}  {'simulated s':>11}  {'script clock s':>14}  "
        f"{'wall s':>7}  {'x real time':>11}"
    )
    for i in range(args.runs):
        sink = io.StringIO()
        with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
            result = run_script(args.script, args.scene, seed=i, trace=False)
        if not result.ok:
            print(f"run {i} failed: {result.message}", file=sys.stderr)
            return 1
        ratio = result.sim_time / result.wall_time
        ratios.append(ratio)
        sims.append(result.sim_time)
        walls.append(result.wall_time)
        print(
            f"{i:>3}  {result.sim_time:>11.2f}  {result.clock_time:>14.2f}  "
            f"{result.wall_time:>7.2f}  {ratio:>11.1f}"
        )

    steps = round(statistics.median(sims) / 0.005)
    with World(args.scene) as world:
        t0 = time.perf_counter()
        world.step(steps)
        physics = time.perf_counter() - t0
    median = statistics.median(ratios)
    print(
        f"median: simulated {statistics.median(sims):.2f} s in {statistics.median(walls):.2f} s "
        f"wall = {median:.1f}x real time (required: {args.min_ratio:g}x)"
    )
    print(
        f"bare physics of {steps} steps: {physics:.2f} s "
        f"({statistics.median(sims) / physics:.0f}x real time)"
    )
    return 0 if median >= args.min_ratio else 1


if __name__ == "__main__":
    sys.exit(main())
