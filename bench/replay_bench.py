"""Benchmark: replays against videos, in size, in build time and in time to the first frame.

Run: ``python bench/replay_bench.py`` (``--skip-size``, ``--skip-build``, ``--skip-frame`` to
leave a part out; ``--runs N`` browser loads per page). Prints, in one run:

- **size**: one 20 s run of the 2W1A robot (``2w1a-random``, 480x360, 20 samples/s) as a
  replay (``replay.glb``, its gzipped size: what a server sends) beside the same run as the
  video clips of today (WebM VP8, and the H.264 MP4 when ffmpeg has libx264), at speed 1 and at
  the site's speed 8; target: the replay at most 150 KB gzipped;
- **cold build**: this repository copied as a fresh clone has it (no .git, caches, output or
  node_modules; an empty scene cache), built with its own sitegen.yml (replays only), and a
  second fresh copy with ``formats: [video]`` (the site as it was) for comparison: wall time
  and the CPU time of all its processes (steadier on a shared machine: on a quiet 2-core
  machine the wall time is about half of it, or less); target: replays only in at most 30 s
  on this machine;
- **first frame**: the replay build served on 127.0.0.1 and opened in Chromium (WebGL through
  SwiftShader) on a phone-class profile: a 390x844 viewport at device pixel ratio 2 and the CPU
  throttled 4x (DevTools' ``Emulation.setCPUThrottlingRate``); the time from the page's
  DOMContentLoaded (and from navigation start) to the first frame the viewer draws
  (``performance.mark("sitegen-replay-first-frame")``), median of the runs; target: within 1 s
  of the page's load.
The load average before and after is printed: the machine is shared.
"""

from __future__ import annotations

import argparse
import gzip
import os
import resource
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(REPO))
sys.path.insert(0, str(REPO / "bench"))
sys.path.insert(0, str(REPO / "tests"))

from sims_bench import SKIP, site_build  # noqa: E402

# pages whose first replay is in view at load on a phone: the longest 2W1A run (75 s, 260 KB)
# and a cart run in a blog post
PAGES = ("gallery/index.html", "blog/在-pybullet-重現-cart-避障.html")


def kb(n: int) -> str:
    return f"{n / 1024:7.1f} KB"


def sizes() -> None:
    from sims.clips import ClipSpec, render_clips

    with tempfile.TemporaryDirectory(prefix="replay-bench-") as tmp:
        for speed in (1, 8):
            spec = ClipSpec(
                f"s{speed}", "2w1a-random", seconds=20, speed=speed, formats=("replay", "video")
            )
            (r,) = render_clips([spec], tmp, jobs=2)
            if not r.ok:
                raise SystemExit(f"render failed: {r.error}")
            if speed == 1:
                glb = r.files["replay"].read_bytes()
                js = r.files["replay_js"].read_bytes()
                packed = len(gzip.compress(glb, 9))
                print(
                    f"size  2W1A 20 s replay.glb {kb(len(glb))} raw, {kb(packed)} gzipped "
                    f"(replay.js {kb(len(gzip.compress(js, 9)))} gzipped) -> target <= 150 KB: "
                    f"{'met' if packed <= 150 * 1024 else 'NOT met'}"
                )
            for kind, label in (("video", "WebM VP8"), ("mp4", "MP4 H.264")):
                if kind in r.files:
                    data = r.files[kind].read_bytes()
                    packed = kb(len(gzip.compress(data)))
                    print(
                        f"size  2W1A 20 s {label:9s} speed {speed}: {kb(len(data))} "
                        f"({r.meta['frames']} frames 480x360; gzipped {packed})"
                    )


def fresh_copy(target: Path) -> Path:
    """As bench/sims_bench.py, and without the npm tools' node_modules (not in a clone)."""

    def ignore(folder: str, names: list[str]) -> set[str]:
        here = Path(folder).resolve()
        skip = SKIP if here == REPO else {"_work"} if here.name == "bench" else set()
        return {n for n in names if n in skip or n in ("__pycache__", "node_modules")}

    shutil.copytree(REPO, target, ignore=ignore)
    return target


def builds(keep: Path | None) -> Path:
    base = keep or Path(tempfile.mkdtemp(prefix="replay-bench-"))
    results = {}
    for label, formats in (("replays only", None), ("videos (formats: [video])", "[video]")):
        root = fresh_copy(base / label.split()[0])
        if formats:
            cfg = root / "sitegen.yml"
            text = cfg.read_text(encoding="utf-8").replace(
                "formats: [replay]", f"formats: {formats}"
            )
            cfg.write_text(text, encoding="utf-8")
        os.environ["SITEGEN_SCENE_CACHE"] = str(root / ".scene-cache")  # a fresh machine's
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall, log = site_build(root)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
        results[label] = wall
        clips = sum(f.stat().st_size for f in (root / "site" / "clips").rglob("*") if f.is_file())
        built = next((line for line in log.splitlines() if line.startswith("sitegen: built")), "")
        print(
            f"build cold, {label}: {wall:.1f} s wall, {cpu:.1f} s CPU (all processes); "
            f"clips {clips / 1e6:.1f} MB in site/clips"
        )
        print(f"      {built}")
    os.environ.pop("SITEGEN_SCENE_CACHE", None)
    cold = results["replays only"]
    print(
        f"build target: replays only <= 30 s -> {'met' if cold <= 30 else 'NOT met'} "
        f"({results['videos (formats: [video])'] / cold:.1f}x faster than with videos)"
    )
    return base / "replays" / "site"


def first_frames(site: Path, runs: int) -> None:
    from browser_kit import ARGS, CHROMIUM, static_server
    from playwright.sync_api import sync_playwright

    with static_server(site) as base, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=ARGS, headless=True)
        try:
            for rel in PAGES:
                after_dcl, after_start = [], []
                for _ in range(runs):
                    context = browser.new_context(
                        viewport={"width": 390, "height": 844},
                        device_scale_factor=2,
                        is_mobile=True,
                        has_touch=True,
                    )
                    page = context.new_page()
                    cdp = context.new_cdp_session(page)
                    cdp.send("Emulation.setCPUThrottlingRate", {"rate": 4})
                    page.goto(base + rel)
                    page.wait_for_function(
                        "() => performance.getEntriesByName('sitegen-replay-first-frame').length",
                        timeout=60000,
                    )
                    first, dcl = page.evaluate(
                        "() => [performance.getEntriesByName('sitegen-replay-first-frame')[0]"
                        ".startTime, performance.getEntriesByType('navigation')[0]"
                        ".domContentLoadedEventEnd]"
                    )
                    after_dcl.append(first - dcl)
                    after_start.append(first)
                    context.close()
                med = statistics.median(after_dcl)
                print(
                    f"first frame {rel} (phone 390x844 @2x, CPU 4x slower, {runs} loads): "
                    f"{med:.0f} ms after DOMContentLoaded (min {min(after_dcl):.0f}, max "
                    f"{max(after_dcl):.0f}); {statistics.median(after_start):.0f} ms after "
                    f"navigation start -> target <= 1000 ms after load: "
                    f"{'met' if med <= 1000 else 'NOT met'}"
                )
        finally:
            browser.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--skip-size", action="store_true")
    parser.add_argument("--skip-build", action="store_true")
    parser.add_argument("--skip-frame", action="store_true")
    parser.add_argument("--runs", type=int, default=5, help="browser loads per page")
    parser.add_argument("--keep", type=Path, help="build the copies here and keep them")
    parser.add_argument("--site", type=Path, help="time the first frame on this built site")
    args = parser.parse_args()
    print(f"machine: {os.cpu_count()} CPUs; load average {os.getloadavg()[0]:.2f} before")
    start = time.perf_counter()
    if not args.skip_size:
        sizes()
    site = args.site
    if not args.skip_build:
        site = builds(args.keep)
    if not args.skip_frame and site is not None:
        first_frames(site, args.runs)
    if not args.skip_build and args.keep is None and site is not None:
        shutil.rmtree(site.parent.parent, ignore_errors=True)
    took = time.perf_counter() - start
    print(f"load average after: {os.getloadavg()[0]:.2f}; bench took {took:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
