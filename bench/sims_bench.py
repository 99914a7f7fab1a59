"""Benchmark of the simulation gallery: raw renderer rates, cold parallel build, cached rebuild.

Run: ``python bench/sims_bench.py [--quick]``. Prints, in one run:
- raw single-process TinyRenderer frames/s at 480x360 (render calls only, scene stepping between);
- the same for EGL when it loads;
- the whole gallery (every scenario, default size and length) rendered cold with the parallel
  renderer (frames/s overall, wall time), then again from the cache (frames rendered, wall time);
- ratio of the cold gallery rate to the raw TinyRenderer rate.
Targets: cold >= 1.5x raw on 2 cores; cached rebuild renders 0 frames in < 0.5 s.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from sims.clips import ClipSpec, render_clips  # noqa: E402
from sims.render import requested_renderer  # noqa: E402
from sims.scenarios import list_scenarios  # noqa: E402
from sims.world import World  # noqa: E402

WIDTH, HEIGHT = 480, 360


def raw_rate(renderer: str, scene: str, frames: int) -> tuple[str, float]:
    """Frames/s of World.render alone, 10 physics steps (one 20 fps frame) between frames."""
    with World(scene, render_with=renderer) as world:
        for motor in ("left_m", "right_m"):
            if world.handle(motor):
                world.set_joint_target_velocity(motor, 3.0)
        world.render(WIDTH, HEIGHT)  # warm-up
        spent = 0.0
        for _ in range(frames):
            world.step(10)
            start = time.perf_counter()
            world.render(WIDTH, HEIGHT)
            spent += time.perf_counter() - start
        return world.renderer, frames / spent


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="5 s clips instead of full length")
    parser.add_argument("--jobs", type=int, default=None)
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} CPUs; clip renderer requested: {requested_renderer()}")
    rates = {}
    for renderer in ("tinyrenderer", "egl"):
        for scene in ("2w1a", "cart"):
            ran, rate = raw_rate(renderer, scene, 40)
            rates[(renderer, scene)] = rate if ran == renderer else None
            shown = f"{rate:6.1f} frames/s" if ran == renderer else "unavailable (fell back)"
            print(f"raw {renderer:12s} {scene:4s} {WIDTH}x{HEIGHT}: {shown}")
    raw = (rates[("tinyrenderer", "2w1a")] + rates[("tinyrenderer", "cart")]) / 2
    print(f"raw TinyRenderer rate (mean of scenes): {raw:.1f} frames/s")

    seconds = 5.0 if args.quick else None
    specs = [ClipSpec(name=s.name, scenario=s.name, seconds=seconds) for s in list_scenarios()]
    with tempfile.TemporaryDirectory(prefix="sims-bench-") as cache:
        start = time.perf_counter()
        cold = render_clips(specs, cache, jobs=args.jobs)
        cold_wall = time.perf_counter() - start
        failed = [r for r in cold if not r.ok]
        for r in failed:
            print(f"FAILED {r.name}: {r.error}")
        frames = sum(r.meta.get("frames", 0) for r in cold if r.rendered)
        used = sorted({r.meta.get("renderer", "?") for r in cold if r.ok})
        print(
            f"gallery cold: {len(cold)} clips, {frames} frames in {cold_wall:.1f} s = "
            f"{frames / cold_wall:.1f} frames/s (renderer: {', '.join(used)})"
        )
        for r in cold:
            print(f"  {r.name:14s} {r.meta.get('frames', 0):5d} frames  {r.seconds:6.1f} s")
        start = time.perf_counter()
        warm = render_clips(specs, cache, jobs=args.jobs)
        warm_wall = time.perf_counter() - start
        again = sum(r.meta.get("frames", 0) for r in warm if r.rendered)
        print(f"gallery cached: {again} frames rendered in {warm_wall:.3f} s")
    ratio = frames / cold_wall / raw
    print(
        f"ratio cold gallery / raw TinyRenderer: {ratio:.2f}x (target >= 1.5x); "
        f"cached: {'OK' if again == 0 and warm_wall < 0.5 else 'MISSED'} (target 0 frames, < 0.5 s)"
    )
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
