"""Run a scene's own scripts on their own: ``python -m sims.lua run SCENE [--seconds S]``.

No remote API client is involved: the World steps for the simulated time given, the host calls
the scripts each pass, and the end of the run lists script errors and the functions the scripts
called that the emulation lacks (scene, script, line). Exit code 1 when a script raised an error,
3 with ``--strict`` when a script called a function the emulation lacks; ``--keys FILE`` plays
key presses to ``sim.getSimulatorMessage``.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from .host import ScriptHost, Unemulated


@dataclass
class SceneRun:
    scene: str
    seconds: float
    scripts: list[str]
    errors: list[str] = field(default_factory=list)
    missing: list[Unemulated] = field(default_factory=list)
    ports: list[int] = field(default_factory=list)
    statusbar: list[str] = field(default_factory=list)
    trace: list[tuple[float, str, tuple[float, float, float]]] = field(default_factory=list)
    stopped_at: float | None = None  # a script stopped the simulation (sim.stopSimulation)


def run_scene(
    scene: str | Path,
    seconds: float = 10.0,
    *,
    follow: tuple[str, ...] = (),
    scripts: bool = True,
    world: Any = None,
) -> SceneRun:
    """Run ``scene`` for ``seconds`` simulated seconds with its scripts (``scripts=False``: the
    same scene without them, for the benchmark); ``follow``: object names whose positions are
    recorded after every simulation pass."""
    from sims.world import World

    own = world is None
    w = World(str(scene)) if own else world
    try:
        host = ScriptHost(w, enabled=scripts)
        result = SceneRun(str(scene), seconds, [r.name for r in host.scripts])

        def sample(world: Any) -> None:
            if world.steps % host.steps_per_pass == 0:
                for name in follow:
                    result.trace.append((world.time, name, world.object_pose(name)[0]))

        if follow:
            w.add_step_hook(sample)
        host.start()
        end = w.steps + max(0, round(seconds / w.timestep))
        while w.steps < end and not host.stop_requested:  # sim.stopSimulation ends the run
            w.step(min(host.steps_per_pass, end - w.steps))
        result.stopped_at = w.time if host.stop_requested else None
        host.stop()
        host.close()
        result.errors, result.missing = list(host.errors), list(host.missing)
        result.ports, result.statusbar = list(host.ports), list(host.statusbar)
        return result
    finally:
        if own:
            w.close()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m sims.lua", description=__doc__)
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser("run", help="run a scene's scripts for some simulated seconds")
    run.add_argument("scene")
    run.add_argument("--seconds", type=float, default=10.0)
    run.add_argument("--keys", help="key presses for sim.getSimulatorMessage (docs/lua.md)")
    run.add_argument(
        "--strict",
        action="store_true",
        help="exit 3 when a script called a function the emulation lacks",
    )
    sub.add_parser("functions", help="print the table of sim functions the course scenes use")
    sub_usage = sub.choices["functions"]
    sub_usage.add_argument("folder", nargs="?", default="../shared/data/scenes")
    args = parser.parse_args(argv)
    if args.command == "functions":
        try:  # a dev tool of the repository (tools/), not part of the installed package
            from tools.lua_usage import markdown_table, scan
        except ImportError:
            print("error: 'functions' runs from a checkout of the repository (tools/)",
                  file=sys.stderr)  # fmt: skip
            return 2
        print(markdown_table(scan(Path(args.folder))))
        return 0
    from sims.scene.resolve import SceneFileError

    from . import keys

    try:
        if args.keys:
            keys.configure(keys.load(args.keys))
        result = run_scene(args.scene, args.seconds)
    except keys.KeysFileError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except (SceneFileError, OSError, ValueError) as exc:
        print(f"error: {args.scene}: {exc}", file=sys.stderr)
        return 2
    finally:
        keys.configure(None)
    print(f"[lua] {args.scene}: {len(result.scripts)} script(s) ran {args.seconds:g} simulated s")
    for line in result.statusbar:
        print(f"[lua status bar] {line}")
    for e in result.errors:
        print(f"[lua] script error: {e}", file=sys.stderr)
    if result.missing:
        print("[lua] functions the scripts called that are not emulated:", file=sys.stderr)
        for m in result.missing:
            print(f"  {m.describe()}", file=sys.stderr)
    if result.stopped_at is not None:
        print(f"[lua] a script stopped the simulation at {result.stopped_at:.2f} s")
    if result.errors:
        return 1
    return 3 if args.strict and result.missing else 0
