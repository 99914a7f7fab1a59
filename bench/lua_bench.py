"""What the scenes' Lua scripts cost: the same scene run with its scripts and without, in one run.

    python bench/lua_bench.py [SCENE ...] [--seconds 10] [--repeat 3] [--cpu]

Default scenes: every course scene with child or customization scripts (../shared/data/scenes)
plus the project's data/scenes/lua_arm.simscene.xml. For each scene the World (built once per
run, outside the timing) is stepped ``--seconds`` simulated seconds with its ScriptHost and
without one; the best of ``--repeat`` runs of each is kept. The share of the simulation time
the scripts take is (with - without) / with.

Each scene is measured twice, the four runs interleaved so that they see the same machine load:

- ``main-script``: the World's ``sensors="main-script"``, as CoppeliaSim runs a scene. Its main
  script handles every proximity sensor without explicit handling in every pass, child scripts
  or not (sims/proximity.py); the child (and customization) scripts are the only difference
  between the two runs. This is the issue's definition ("the same scene with scripts off"), and
  the goal is judged on it. The goal (issue 14): "child scripts cost under 20% of the
  simulation time of the scene that uses them most", taken as the scene whose scripts take the
  most seconds (with - without); the other scenes over 20% are listed under it (scenes whose whole
  10 s run costs a few ms, where the scripts' start is most of it).
- ``lazy``: the default World, where a sensor is cast only when something reads it, so the
  scripts' run also pays for the sensors they read and the run without scripts casts nothing.
  Printed beside it, not hidden: it is what the scripts cost a World used without CoppeliaSim's
  main-script handling.

Both clocks are measured in every run: wall time (``time.perf_counter``) and this process's CPU
time (``time.process_time``, steadier on a machine shared with other jobs; pybullet steps in
this process). The goal is judged on wall time, or on CPU time with ``--cpu``. The ``in sensors``
column: the share of the with-scripts run (judged clock) spent casting proximity sensors and
rendering vision sensors. Prints a table; exit code 1 when the goal is missed.
"""

from __future__ import annotations

import argparse
import gc
import sys
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from sims.lua.host import ScriptHost  # noqa: E402
from sims.world import World  # noqa: E402

GOAL = 0.20
GOAL_MODE = "main-script"  # the definition: child scripts are the only difference
MODES = (GOAL_MODE, "lazy")


def default_scenes() -> list[Path]:
    from sims.scene.resolve import open_scene
    from tools.lua_usage import scene_files

    out = [REPO / "data" / "scenes" / "lua_arm.simscene.xml"]
    shared = REPO.parent / "shared" / "data" / "scenes"
    if shared.is_dir():
        for path in scene_files(shared):
            scene = open_scene(path)
            if any(s.kind != "main" and s.text.strip() for s in scene.scripts):
                out.append(path)
    return out


SENSING = [0.0]  # seconds spent in the sensors the scripts read (ray casts, renders)
CLOCK = [time.perf_counter]  # the clock of the table: perf_counter, or process_time (--cpu)


def _timing(fn):
    def timed_call(*args, **kwargs):
        start = CLOCK[0]()
        try:
            return fn(*args, **kwargs)
        finally:
            SENSING[0] += CLOCK[0]() - start

    return timed_call


def _instrument() -> None:
    from sims import proximity
    from sims.simapi import vision

    proximity.ProximitySensors._cast = _timing(proximity.ProximitySensors._cast)  # type: ignore[method-assign]
    vision.read_vision_sensor = _timing(vision.read_vision_sensor)


def timed(path: Path, seconds: float, scripts: bool, sensors: str) -> tuple[float, float, int]:
    """(wall seconds, CPU seconds, number of scripts) of one run."""
    with World(str(path), sensors=sensors) as world:
        host = ScriptHost(world, enabled=scripts)
        gc.collect()  # the previous runs' Lua states are freed here, not inside this timing
        wall, cpu = time.perf_counter(), time.process_time()
        host.start()
        world.advance(seconds)
        host.stop()
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        host.close()
        return wall, cpu, len(host.scripts)


def share(on: list[float], off: list[float]) -> tuple[float, float, float]:
    """(best with, best without, share of the scripts) from interleaved runs."""
    with_s, without = min(on), min(off)
    return with_s, without, (max(0.0, with_s - without) / with_s if with_s > 0 else 0.0)


@dataclass
class Row:
    scene: str
    mode: str
    scripts: int
    wall: tuple[float, float, float]  # with, without, share
    cpu: tuple[float, float, float]
    sensors: float  # share of the judged with-scripts run spent in sensors


def measure(path: Path, seconds: float, repeat: int, cpu_clock: bool) -> list[Row]:
    """Both sensor modes of one scene, their runs interleaved."""
    runs: dict[tuple[str, bool], list[tuple[float, float]]] = {}
    sensing: dict[str, list[float]] = {m: [] for m in MODES}
    n = 0
    for _ in range(repeat):  # interleaved: every run sees the same machine load
        for mode in MODES:
            for scripts in (True, False):
                SENSING[0] = 0.0
                wall, cpu, count = timed(path, seconds, scripts, mode)
                runs.setdefault((mode, scripts), []).append((wall, cpu))
                if scripts:
                    sensing[mode].append(SENSING[0])
                    n = count
    rows = []
    for mode in MODES:
        on, off = runs[(mode, True)], runs[(mode, False)]
        wall = share([r[0] for r in on], [r[0] for r in off])
        cpu = share([r[1] for r in on], [r[1] for r in off])
        judged = [r[1] if cpu_clock else r[0] for r in on]
        best = judged.index(min(judged))
        sens = sensing[mode][best] / judged[best] if judged[best] > 0 else 0.0
        rows.append(Row(path.name, mode, n, wall, cpu, sens))
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="*", type=Path)
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument(
        "--cpu", action="store_true", help="judge the goal on CPU time (process_time)"
    )
    args = parser.parse_args(argv)
    CLOCK[0] = time.process_time if args.cpu else time.perf_counter
    _instrument()
    rows: list[Row] = []
    for path in args.scenes or default_scenes():
        rows += measure(path, args.seconds, args.repeat, args.cpu)
    clock = "CPU" if args.cpu else "wall"
    print(
        f"{'scene':40} {'sensors':11} {'scripts':>7} {'with s':>7} {'without s':>9} "
        f"{'share':>6} {'CPU with':>8} {'CPU w/o':>7} {'CPU share':>9} "
        f"{'in sensors (' + clock + ')':>18}"
    )
    for r in rows:
        print(
            f"{r.scene:40} {r.mode:11} {r.scripts:7d} {r.wall[0]:7.3f} {r.wall[1]:9.3f} "
            f"{r.wall[2]:6.1%} {r.cpu[0]:8.3f} {r.cpu[1]:7.3f} {r.cpu[2]:9.1%} {r.sensors:18.1%}"
        )
    judged = [r for r in rows if r.mode == GOAL_MODE]
    pick = (lambda r: r.cpu) if args.cpu else (lambda r: r.wall)
    worst = max(judged, key=lambda r: pick(r)[0] - pick(r)[1])  # most seconds in scripts
    value = pick(worst)[2]
    lazy = next(r for r in rows if r.scene == worst.scene and r.mode == "lazy")
    ok = value < GOAL
    print(
        f"scene using its scripts most ({GOAL_MODE} sensors, as CoppeliaSim): {worst.scene}: "
        f"scripts {pick(worst)[0] - pick(worst)[1]:.3f} s, {value:.1%} of its simulation time "
        f"({clock} time; {'under' if ok else 'NOT under'} the {GOAL:.0%} goal); "
        f"with lazy sensors: {pick(lazy)[2]:.1%}"
    )
    over = [r for r in judged if pick(r)[2] >= GOAL and r is not worst]
    for r in over:
        print(
            f"  also over {GOAL:.0%}: {r.scene}: {pick(r)[2]:.1%}, scripts "
            f"{pick(r)[0] - pick(r)[1]:.3f} s of a {pick(r)[0]:.3f} s run"
        )
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
