"""``sitegen remote-api``: run CoppeliaSim legacy remote API scripts on the pybullet scenes.

    sitegen remote-api run SCRIPT [--scene 2w1a|cart] [--record OUT.webm] [--realtime]
                           [--after SECONDS] [--seed N] [--timeout S] [--server KIND] [-- ARGS]
    sitegen remote-api functions        # which simx* functions are emulated

The script's own output goes to stdout; diagnostics and the summary go to stderr. The exit code
is the script's (``sys.exit(n)``), 1 when it raised, 124 when it ran past its time limit.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from pathlib import Path

from .runner import DEFAULT_TIMEOUT, run_script
from .server import SERVER_KINDS

SCENES = ("2w1a", "cart")


def _parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Run CoppeliaSim legacy remote API scripts (import sim / vrep) "
        "unchanged on sitegen's pybullet scenes. No network: addresses are only recorded.",
    )
    sub = parser.add_subparsers(dest="command", required=True)
    run = sub.add_parser(
        "run",
        help="run a script",
        description="Run a script as __main__ with "
        "`import sim` resolving to the emulation, on a virtual clock by default.",
    )
    run.add_argument("script", help="the Python script to run")
    run.add_argument(
        "script_args",
        nargs="*",
        metavar="ARG",
        help="arguments for the script (sys.argv[1:]); put them after --",
    )
    run.add_argument(
        "--scene",
        choices=SCENES,
        help="scene to load (default: guessed from the object names in the script)",
    )
    run.add_argument(
        "--server",
        choices=SERVER_KINDS,
        help="remote API server kind: continuous (simulation starts stopped; the "
        "script starts it) or temporary (simulation already running). Default: "
        "continuous for 2w1a, temporary for cart",
    )
    run.add_argument(
        "--seed",
        type=int,
        default=0,
        help="seed for the scene and for Python's random in the script (default 0; "
        "random.seed() without an argument reuses it)",
    )
    run.add_argument(
        "--after",
        type=float,
        default=0.0,
        metavar="SECONDS",
        help="keep the world running this long after the script ends",
    )
    run.add_argument(
        "--realtime", action="store_true", help="pace by the wall clock instead of virtual time"
    )
    run.add_argument(
        "--timeout",
        type=float,
        default=DEFAULT_TIMEOUT,
        metavar="S",
        help=f"stop the script after S seconds of script time or of wall time "
        f"(default {DEFAULT_TIMEOUT:g})",
    )
    run.add_argument(
        "--record",
        metavar="OUT.webm",
        help="also render a clip: OUT.webm plus OUT.png (poster), OUT.csv, OUT.json "
        "and OUT.svg (path), like the gallery's",
    )
    run.add_argument("--size", default="480x360", help="clip size WxH (default 480x360)")
    run.add_argument("--fps", type=int, default=20, help="clip frames per second (default 20)")
    run.add_argument("-q", "--quiet", action="store_true", help="no summary line")
    sub.add_parser("functions", help="list the emulated and the unsupported simx functions")
    return parser


def main(argv: list[str] | None = None, prog: str = "sitegen remote-api") -> int:
    args = _parser(prog).parse_args(argv)
    if args.command == "functions":
        return _functions()
    return _run(args)


def _functions() -> int:
    from . import api, extras

    unsupported = set(extras.UNSUPPORTED)
    names = sorted(n for n in api.__all__ if n.startswith("simx") and not n.startswith("simx_"))
    supported = [n for n in names if n not in unsupported]
    print(f"emulated ({len(supported)}):")
    for n in supported:
        print(f"  {n}")
    print(f"not supported: return simx_return_local_error_flag ({len(unsupported)}):")
    for n in sorted(unsupported):
        print(f"  {n}")
    return 0


def _scene_for(args: argparse.Namespace) -> str | None:
    if args.scene:
        return args.scene
    from .record import guess_scene

    try:
        return guess_scene(Path(args.script).read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return None


def _run(args: argparse.Namespace) -> int:
    scene = _scene_for(args)
    if scene is None:
        if not Path(args.script).is_file():
            print(f"error: {args.script}: no such script file", file=sys.stderr)
            return 2
        print(
            f"error: {args.script}: cannot tell the scene from the script; "
            f"pass --scene {'|'.join(SCENES)}",
            file=sys.stderr,
        )
        return 2
    result = run_script(
        args.script,
        scene,
        seed=args.seed,
        server=args.server,
        realtime=args.realtime,
        after=args.after,
        timeout=args.timeout,
        argv=args.script_args,
    )
    sys.stdout.flush()
    if result.message and result.exit_code != 0 and not result.message_printed:
        print(f"error: {result.message}", file=sys.stderr)
    if not args.quiet:
        print(f"[remote-api] {result.summary()}", file=sys.stderr)
    if args.record and result.exit_code == 0:
        try:
            # a real-time run's length is not reproducible: let the recorder measure its own
            files = record_clip(args, scene, None if args.realtime else result.sim_time)
        except Exception as exc:  # a recording failure is reported, the run's result stands
            print(f"error: recording {args.record} failed: {exc}", file=sys.stderr)
            return 1
        print(f"[remote-api] recorded: {', '.join(str(f) for f in files)}", file=sys.stderr)
    elif args.record:
        print("[remote-api] not recorded: the script did not end cleanly", file=sys.stderr)
    return result.exit_code


def record_clip(args: argparse.Namespace, scene: str, seconds: float | None) -> list[Path]:
    """Render the run as a clip with the gallery's machinery; returns the files written.

    ``seconds``: the simulated length of the run (None: measured by a silent dry run)."""
    from dataclasses import asdict

    from sims.cache import FILES
    from sims.clip_worker import render_job
    from sims.clips import ClipSpec

    from .record import MARGIN, TARGET

    width, _, height = args.size.partition("x")
    out = Path(args.record)
    stem = out.with_suffix("") if out.suffix == ".webm" else out
    params = {"scene": scene, "after": args.after, "server": args.server, "timeout": args.timeout}
    spec = ClipSpec(
        name=stem.name,
        scenario=str(Path(args.script).resolve()),
        kind="script",
        width=int(width),
        height=int(height or 0),
        fps=args.fps,
        seconds=None if seconds is None else round(seconds + MARGIN, 3),
        seed=args.seed,
        params=params,
    )
    suffix = {"video": ".webm", "poster": ".png", "csv": ".csv", "json": ".json", "plot": ".svg"}
    stem.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="remote-api-clip-") as tmp:
        render_job(
            {
                "spec": asdict(spec),
                "target": TARGET,
                "out_dir": tmp,
                "time_limit": max(args.timeout, 60.0) * 4,
            }
        )
        written = []
        for kind, name in FILES.items():
            target = stem.parent / (stem.name + suffix[kind])
            shutil.copyfile(Path(tmp) / name, target)
            written.append(target)
    return written


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
