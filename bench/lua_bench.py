"""What the scenes' Lua scripts cost: the same scene run with its scripts and without, in one run.

    python bench/lua_bench.py [SCENE ...] [--seconds 10] [--repeat 3]

Default scenes: every course scene with child or customization scripts (../shared/data/scenes)
plus the project's data/scenes/lua_arm.simscene.xml. For each scene the World (built once per
run, outside the timing) is stepped ``--seconds`` simulated seconds with its ScriptHost and
without one; the best of ``--repeat`` runs of each is kept. The share of the simulation time
the scripts take is (with - without) / with; the goal (issue 14) is under 20% for the scene
whose scripts cost the most. Prints a table; exit code 1 when the goal is missed.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sims.lua.host import ScriptHost  # noqa: E402
from sims.world import World  # noqa: E402

GOAL = 0.20


def default_scenes() -> list[Path]:
    from sims.lua.usage import scene_files
    from sims.scene.resolve import open_scene

    out = [REPO / "data" / "scenes" / "lua_arm.simscene.xml"]
    shared = REPO.parent / "shared" / "data" / "scenes"
    if shared.is_dir():
        for path in scene_files(shared):
            scene = open_scene(path)
            if any(s.kind != "main" and s.text.strip() for s in scene.scripts):
                out.append(path)
    return out


SENSING = [0.0]  # seconds spent in the sensors the scripts read (ray casts, renders)


def _timing(fn):
    def timed_call(*args, **kwargs):
        start = time.perf_counter()
        try:
            return fn(*args, **kwargs)
        finally:
            SENSING[0] += time.perf_counter() - start

    return timed_call


def _instrument() -> None:
    from sims.lua import vision
    from sims.remote_api import commands

    commands.read_proximity_sensor = _timing(commands.read_proximity_sensor)
    vision.read_vision_sensor = _timing(vision.read_vision_sensor)


def timed(path: Path, seconds: float, scripts: bool) -> tuple[float, int]:
    with World(str(path)) as world:
        host = ScriptHost(world, enabled=scripts)
        start = time.perf_counter()
        host.start()
        world.advance(seconds)
        host.stop()
        elapsed = time.perf_counter() - start
        host.close()
        return elapsed, len(host.scripts)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", type=Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    _instrument()
    rows = []
    for path in args.scenes or default_scenes():
        on, off, sensing = [], [], []
        for _ in range(args.repeat):  # interleaved: both see the same machine load
            SENSING[0] = 0.0
            t, n = timed(path, args.seconds, True)
            on.append(t)
            sensing.append(SENSING[0])
            off.append(timed(path, args.seconds, False)[0])
        best = on.index(min(on))
        with_s, without = on[best], min(off)
        share = max(0.0, with_s - without) / with_s if with_s > 0 else 0.0
        rows.append((path.name, n, with_s, without, share, sensing[best] / with_s))
    print(
        f"{'scene':46} {'scripts':>7} {'with s':>7} {'without s':>9} {'scripts share':>13} "
        f"{'of it sensors':>13}"
    )
    for name, n, w, wo, share, sens in rows:
        print(f"{name:46} {n:7d} {w:7.3f} {wo:9.3f} {share:12.1%} {sens:12.1%}")
    worst = max(rows, key=lambda r: r[4])
    ok = worst[4] < GOAL
    print(
        f"most costly scripts: {worst[0]}: {worst[4]:.1%} of its simulation time "
        f"({'under' if ok else 'NOT under'} the {GOAL:.0%} goal)"
    )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
