"""Benchmark: the first build of this repository's site, cold, beside raw renderer rates.

Run: ``python bench/sims_bench.py`` (``--jobs N`` to set the clip workers, ``--keep DIR`` to
keep the copy). Prints, in one run:

- raw single-process frame rates of ``World.render`` at the site's clip size, EGL and
  TinyRenderer, on the 2w1a and cart scenes (render calls only, the scene stepped between);
- a **true cold build**: the repository copied the way a fresh clone has it (no ``.git``, no
  ``.sitegen-cache``, no ``site/``, no ``../shared`` beside it) into a temporary folder, then
  ``python -m sitegen build`` there with the copy first on ``PYTHONPATH``; wall time, frames
  drawn and frames/s over the whole build;
- the same build again (everything cached), and the load average before and after, since the
  machine is shared: the target (< 60 s on 2 cores) is for a quiet machine.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))

from sims.world import World  # noqa: E402

SKIP = {".git", ".sitegen-cache", "site", "build", ".hypothesis", ".ruff_cache", "__pycache__"}


def raw_rate(renderer: str, scene: str, frames: int, size: tuple[int, int]) -> tuple[str, float]:
    """Frames/s of World.render alone, 10 physics steps (one 20 fps frame) between frames."""
    with World(scene, render_with=renderer) as world:
        for motor in ("left_m", "right_m"):
            if world.handle(motor):
                world.set_joint_target_velocity(motor, 3.0)
        world.render(*size)  # warm-up
        spent = 0.0
        for _ in range(frames):
            world.step(10)
            start = time.perf_counter()
            world.render(*size)
            spent += time.perf_counter() - start
        return world.renderer, frames / spent


def fresh_copy(target: Path) -> Path:
    """The repository as a fresh clone has it: tracked-looking files, no caches or output."""

    def ignore(folder: str, names: list[str]) -> set[str]:
        here = Path(folder).resolve()
        skip = SKIP if here == REPO else {"__pycache__", "_work"} if here.name == "bench" else set()
        return {n for n in names if n in skip or n == "__pycache__"}

    shutil.copytree(REPO, target, ignore=ignore)
    return target


def site_build(root: Path) -> tuple[float, str]:
    env = dict(os.environ, PYTHONPATH=str(root))
    env.pop("CI", None)
    args = [sys.executable, "-m", "sitegen", "build"]
    start = time.perf_counter()
    done = subprocess.run(args, cwd=root, env=env, capture_output=True, text=True, timeout=3600)
    wall = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"build failed ({done.returncode}):\n{done.stderr}")
    return wall, done.stderr


def clip_frames(root: Path) -> tuple[int, list[str]]:
    total, rows = 0, []
    for meta_file in sorted((root / ".sitegen-cache" / "clips").glob("*/meta.json")):
        meta = json.loads(meta_file.read_text(encoding="utf-8"))
        total += meta["frames"]
        rows.append(
            f"  {meta['scenario']:44s} {meta['frames']:4d} frames  speed {meta.get('speed', 1):g}"
            f"  {meta['renderer']}"
        )
    return total, rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--jobs", type=int, default=None, help="clip workers (default: CPUs)")
    parser.add_argument("--keep", type=Path, help="build the copy here and keep it")
    args = parser.parse_args()
    load_before = os.getloadavg()
    print(f"machine: {os.cpu_count()} CPUs; load average {load_before[0]:.2f} before")
    size = (480, 360)
    for renderer in ("egl", "tinyrenderer"):
        for scene in ("2w1a", "cart"):
            ran, rate = raw_rate(renderer, scene, 40, size)
            shown = f"{rate:6.1f} frames/s" if ran == renderer else "unavailable (fell back)"
            print(f"raw {renderer:12s} {scene:4s} {size[0]}x{size[1]}, one process: {shown}")
    with tempfile.TemporaryDirectory(prefix="sims-bench-") as tmp:
        root = fresh_copy((args.keep or Path(tmp)) / "main")
        if args.jobs:
            cfg = root / "sitegen.yml"
            text = cfg.read_text(encoding="utf-8")
            cfg.write_text(text.replace("sims:\n", f"sims:\n  jobs: {args.jobs}\n", 1), "utf-8")
        cold, log = site_build(root)
        frames, rows = clip_frames(root)
        print(
            f"cold first build of this site (fresh copy, empty cache): {cold:.1f} s, "
            f"{frames} clip frames = {frames / cold:.1f} frames/s over the whole build"
        )
        print("\n".join(rows))
        for line in log.splitlines():
            if "warning" in line or line.startswith("sitegen: built"):
                print(f"  build: {line}")
        warm, _ = site_build(root)
        print(f"second build (cached, nothing changed): {warm:.2f} s")
        if args.keep:
            (root / "bench-build.log").write_text(log, encoding="utf-8")
    load_after = os.getloadavg()
    print(
        f"load average after: {load_after[0]:.2f}; target: cold build < 60 s on a quiet "
        f"2-core machine -> {'met' if cold < 60 else 'NOT met'} in this run"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
