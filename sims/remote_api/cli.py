"""``sitegen remote-api``: run CoppeliaSim legacy remote API scripts on the pybullet scenes.

    sitegen remote-api run SCRIPT [--scene 2w1a|cart|PATH] [--record OUT.webm|OUT.glb] [--realtime]
                           [--after SECONDS] [--seed N] [--timeout S] [--server KIND]
                           [--stdin FILE] [--strict] [-- ARGS]
    sitegen remote-api functions        # which simx* functions are emulated

``--scene`` takes a bundled scene name or a scene file (``.ttt``, ``.simscene.xml``). The
script's own output goes to stdout; diagnostics and the summary go to stderr, ending with the
objects the script asked for that the scene lacks and the functions it called that the emulation
does not implement (script line and nearest names). The exit code is the script's
(``sys.exit(n)``), 1 when it raised, 124 when it ran past its time limit; with ``--strict`` a
run that asked for anything missing exits 3 when the script itself ended with 0.
"""

from __future__ import annotations

import argparse
import io
import shutil
import sys
import tempfile
from pathlib import Path

import sims.quiet  # noqa: F401  (pybullet imported silently before anything imports it)
from located.verbosity import add_verbosity

from .client import missing_report
from .runner import DEFAULT_TIMEOUT, run_script
from .server import SERVER_KINDS

SCENES = ("2w1a", "cart")
STRICT_EXIT = 3


def _parser(prog: str) -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog=prog,
        description="Run CoppeliaSim remote API scripts, legacy (import sim / vrep) or ZeroMQ "
        "(RemoteAPIClient), unchanged on sitegen's pybullet scenes. No network: addresses are "
        "only recorded.",
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
        metavar="NAME|PATH",
        help=f"scene to load: {' or '.join(SCENES)}, or a CoppeliaSim scene file (.ttt, "
        ".simscene.xml) (default: guessed from the object names in the script)",
    )
    run.add_argument(
        "--stdin",
        metavar="FILE",
        help="feed this file to the script's standard input (input() calls); without it an "
        "input() call ends the script (EOF)",
    )
    run.add_argument(
        "--keys",
        metavar="FILE",
        help="key presses for scripts that import keyboard: lines 'SECONDS DURATION KEY' on "
        "the script's clock (docs/lua.md); without it no key is pressed",
    )
    run.add_argument(
        "--strict",
        action="store_true",
        help=f"exit {STRICT_EXIT} when the script asked for objects the scene lacks or "
        "called functions the emulation does not implement",
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
        "--python",
        metavar="PATH",
        help="run the script in this Python interpreter (its own packages, e.g. an older "
        "numpy) against a served scene, over loopback sockets, on the wall clock",
    )
    run.add_argument(
        "--speed",
        type=_positive,
        default=1.0,
        metavar="X",
        help="with --python: the simulation's clock runs X times the wall clock (default 1)",
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
        metavar="OUT.webm|OUT.glb",
        help="also render a clip: OUT.webm plus OUT.png (poster), OUT.csv, OUT.json "
        "and OUT.svg (path), like the gallery's; OUT.glb records a 3D replay (glTF) instead "
        "of a video",
    )
    run.add_argument("--size", default="480x360", help="clip size WxH (default 480x360)")
    run.add_argument("--fps", type=int, default=20, help="clip frames per second (default 20)")
    add_verbosity(run, "no summary line", "also the scene and seed before the run")
    serve = sub.add_parser(
        "serve",
        help="serve a scene to real remote API clients (ZeroMQ and legacy) on 127.0.0.1",
        description="Hold SCENE and serve CoppeliaSim's ZeroMQ remote API (port 23000) and "
        "legacy remote API (ports 19997 and 19999) on 127.0.0.1 until interrupted. Stepping "
        "clients are deterministic; a free-running simulation follows the wall clock.",
    )
    serve.add_argument("scene", metavar="SCENE", help="a bundled scene name or a scene file")
    serve.add_argument("--seed", type=int, default=0, help="the scene's seed (default 0)")
    serve.add_argument(
        "--speed", type=_positive, default=1.0, metavar="X", help="clock speed (default 1)"
    )
    serve.add_argument("--server", choices=SERVER_KINDS, help="legacy server kind")
    serve.add_argument("--zmq-port", type=int, default=23000, metavar="PORT")
    serve.add_argument(
        "--legacy-port",
        type=int,
        action="append",
        metavar="PORT",
        help="legacy remote API port (repeatable; default 19997 and 19999)",
    )
    serve.add_argument(
        "--for", dest="duration", type=_positive, metavar="S", help="stop after S wall seconds"
    )
    add_verbosity(serve, "nothing but errors", "also each client")
    sub.add_parser("sweep", help="run a script many times: seeds, grids (sims/sweeps/cli.py)")
    add_verbosity(
        sub.add_parser("functions", help="list the emulated and the unsupported simx functions"),
        "accepted as on every command; the lists are always printed",
        "accepted as on every command; the lists are always printed",
    )
    return parser


def split_script_args(argv: list[str]) -> tuple[list[str], list[str]]:
    """The command's own arguments and the script's: everything after the first ``--`` is the
    script's, wherever the options stand (``run S --scene X --timeout 20 -- a b``)."""
    if "--" in argv:
        at = argv.index("--")
        return argv[:at], argv[at + 1 :]
    return argv, []


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
    if not 0 < value < float("inf"):
        raise argparse.ArgumentTypeError(f"must be a positive number, not {text}")
    return value


def main(argv: list[str] | None = None, prog: str = "sitegen remote-api") -> int:
    given = list(sys.argv[1:] if argv is None else argv)
    if given[:1] == ["sweep"]:
        from sims.sweeps.cli import main as sweep  # its own parser: sims/sweeps/cli.py

        return sweep(given[1:], f"{prog} sweep")
    own, extra = split_script_args(given)
    args = _parser(prog).parse_args(own)
    if args.command == "run":
        args.script_args = [*args.script_args, *extra]
    elif extra:
        _parser(prog).error(f"unexpected arguments after --: {' '.join(extra)}")
    if args.command == "functions":
        return _functions()  # -q/-v: the lists are the command's data, printed either way
    if args.command == "serve":
        from .serve import serve_command

        return serve_command(args, _check_scene(args.scene), is_bundled_name(args.scene))
    return _run(args)


def _functions() -> int:
    from .functions import main as list_functions

    return list_functions([])


def _scene_for(args: argparse.Namespace) -> str | None:
    if args.scene:
        return args.scene
    from .script_clips import guess_scene

    try:
        return guess_scene(Path(args.script).read_text(encoding="utf-8", errors="replace"))
    except OSError:
        return None


def _check_scene(scene: str) -> str | None:
    """An error message when ``scene`` is neither a bundled name nor a readable scene file."""
    from sims.scene.resolve import SceneFileError, is_bundled, open_scene

    if is_bundled(scene):
        return None
    try:
        open_scene(scene)
    except SceneFileError as exc:
        return str(exc)
    except Exception as exc:  # a reader's own error: one line, never a traceback
        return f"{scene}: cannot load the scene: {exc}"
    return None


def _run(args: argparse.Namespace) -> int:
    scene = _scene_for(args)
    if scene is not None:
        problem = _check_scene(scene)
        if problem:
            print(f"error: {problem}", file=sys.stderr)
            return 2
        if not is_bundled_name(scene):
            scene = str(Path(scene).resolve())
    if scene is None:
        if not Path(args.script).is_file():
            print(f"error: {args.script}: no such script file", file=sys.stderr)
            return 2
        print(
            f"error: {args.script}: cannot tell the scene from the script; "
            f"pass --scene {'|'.join(SCENES)} or --scene PATH (a .ttt or .simscene.xml file)",
            file=sys.stderr,
        )
        return 2
    if args.verbosity > 0:
        print(f"[remote-api] scene {scene}, seed {args.seed}", file=sys.stderr)
    from sims.lua import keys

    try:
        keys.configure(keys.load(args.keys) if args.keys else None)
    except keys.KeysFileError as exc:
        print(f"error: --keys {exc}", file=sys.stderr)
        return 2
    try:
        feed = open(args.stdin, encoding="utf-8") if args.stdin else io.StringIO("")
    except OSError as exc:
        print(f"error: --stdin {args.stdin}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    saved_stdin = sys.stdin
    sys.stdin = feed
    try:
        result = run_script(
            args.script,
            scene,
            seed=args.seed,
            server=args.server,
            realtime=args.realtime,
            after=args.after,
            timeout=args.timeout,
            argv=args.script_args,
            python=args.python,
            speed=args.speed,
        )
    finally:
        sys.stdin = saved_stdin
        feed.close()
    sys.stdout.flush()
    if result.message and result.exit_code != 0 and not result.message_printed:
        print(f"error: {result.message}", file=sys.stderr)
    for line in missing_report(result.missing):
        print(line, file=sys.stderr)
    if args.verbosity >= 0:
        print(f"[remote-api] {result.summary()}", file=sys.stderr)
    if args.strict and result.missing and result.exit_code == 0:
        print(
            f"error: {args.script}: the script asked for what this run lacks (--strict)",
            file=sys.stderr,
        )
        return STRICT_EXIT
    if args.record and result.exit_code == 0:
        try:
            # a real-time run's length is not reproducible: let the recorder measure its own
            files, note = record_clip(args, scene, None if args.realtime else result.sim_time)
        except Exception as exc:  # a recording failure is reported, the run's result stands
            print(f"error: recording {args.record} failed: {exc}", file=sys.stderr)
            return 1
        if note and args.verbosity >= 0:
            print(f"[remote-api] {note}", file=sys.stderr)
        print(f"[remote-api] recorded: {', '.join(str(f) for f in files)}", file=sys.stderr)
    elif args.record:
        print("[remote-api] not recorded: the script did not end cleanly", file=sys.stderr)
    return result.exit_code


def is_bundled_name(scene: str) -> bool:
    from sims.scene.resolve import is_bundled

    return is_bundled(scene)


def record_clip(
    args: argparse.Namespace, scene: str, seconds: float | None
) -> tuple[list[Path], str | None]:
    """Render the run as a clip with the gallery's machinery; returns the files written and
    the line saying why EGL fell back (None: it did not).

    ``seconds``: the simulated length of the run (None: measured by a silent dry run)."""
    from sims.clip_cache import FILES
    from sims.clip_worker import ClipJob, render_job
    from sims.clips import ClipSpec
    from sims.render import fallback_note

    from .script_clips import MARGIN, TARGET

    width, _, height = args.size.partition("x")
    out = Path(args.record)
    stem = out.with_suffix("") if out.suffix in (".webm", ".glb") else out
    formats = ("replay",) if out.suffix == ".glb" else ("video",)  # OUT.glb: a 3D replay
    params = {
        "scene": scene,
        "after": args.after,
        "server": args.server,
        "timeout": args.timeout,
        "args": list(args.script_args),  # the recorded run is the same run: same arguments,
        "keys": args.keys,  # same key presses and the same standard input
        "stdin": args.stdin,
        "python": getattr(args, "python", None),
    }
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
        formats=formats,
    )
    suffix = {"video": ".webm", "poster": ".png", "csv": ".csv", "json": ".json", "plot": ".svg"}
    suffix |= {"mp4": ".mp4", "series": ".series.svg", "replay": ".glb", "replay_js": ".glb.js"}
    stem.parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(prefix="remote-api-clip-") as tmp:
        meta, fallback = render_job(
            ClipJob("simulate", spec, TARGET, tmp, time_limit=max(args.timeout, 60.0) * 4)
        )
        written = []
        for kind, name in FILES.items():
            if kind not in meta["files"] or kind == "replay_js":  # asked for; pages only
                continue
            target = stem.parent / (stem.name + suffix[kind])
            shutil.copyfile(Path(tmp) / name, target)
            written.append(target)
    return written, fallback_note([fallback])


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
