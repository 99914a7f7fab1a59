"""``sitegen remote-api sweep``: run one script many times, each run isolated.

    sitegen remote-api sweep SCRIPT --scene SCENE [--seeds 0:1000] [--grid NAME=a,b,c ...]
                             [--args-file runs.csv] [--seed N] [--seconds S] [--timeout S]
                             [--after S] [--server KIND] [--workers N] [--ray [ADDRESS]]
                             [--out DIR]

Writes DIR/results.csv and DIR/results.jsonl (default DIR: ``sweep-<script name>``), shows
progress on stderr, prints one line per failed run and a summary. Exit code: 0 when every run
ended well, 1 when some failed (every row is still written), 2 for bad input (one line naming
the option, file, line and field). Without ``--ray``, ``sims: executor: ray`` in a
``sitegen.yml`` of the current folder asks for Ray too. docs/sweeps.md has the details.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from located.diagnostics import LocatedError
from located.verbosity import add_verbosity


def _parser(prog: str) -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog=prog,
        description="Run a remote API script many times (over seeds, argument grids or an "
        "argument file), each run isolated as `remote-api run` isolates one, on local worker "
        "processes or a Ray cluster. Writes results.csv and results.jsonl.",
    )
    p.add_argument("script", help="the Python script to run")
    p.add_argument("--scene", required=True, metavar="NAME|PATH", help="bundled name or file")
    p.add_argument("--seeds", metavar="A:B", help="one run per seed: A:B (B excluded), A:B:STEP "
                   "or 1,5,9")  # fmt: skip
    p.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="NAME=a,b,c",
        help="one run per value (repeat: every combination); the script gets --NAME=VALUE "
        "and $SWEEP_NAME",
    )
    p.add_argument("--args-file", metavar="CSV", help="a header of names, one row a run")
    p.add_argument(
        "--seed", type=int, default=0, help="the sweep's seed: runs without a seed of their "
        "own get one derived from it and their index (default 0)"
    )  # fmt: skip
    p.add_argument(
        "--seconds",
        type=float,
        metavar="S",
        help="end each run after S simulated seconds (status 'cut', not a failure)",
    )
    p.add_argument(
        "--timeout", type=float, default=300.0, metavar="S",
        help="each run's limit on its script clock and on the wall clock (default 300)",
    )  # fmt: skip
    p.add_argument("--after", type=float, default=0.0, metavar="S", help="as remote-api run")
    p.add_argument("--server", choices=("continuous", "temporary"), help="as remote-api run")
    p.add_argument("--workers", type=int, metavar="N", help="local workers (default: every core)")
    p.add_argument(
        "--ray",
        nargs="?",
        const="auto",
        metavar="ADDRESS",
        help="run on Ray: the running cluster (auto, the default) or ADDRESS; 'local' starts "
        "one on this machine",
    )
    p.add_argument("--out", metavar="DIR", help="where results go (default sweep-SCRIPTNAME)")
    add_verbosity(p, "no progress, only failures and the summary", "also each run as it ends")
    return p


def configured_executor(folder: Path) -> str | None:
    """``sims: executor:`` of ``folder/sitegen.yml``, if any (sims does not import sitegen:
    only this key is read, through the same checked YAML reader)."""
    path = folder / "sitegen.yml"
    if not path.is_file():
        return None
    from located.yaml import YamlError, compose, to_python

    try:
        data = to_python(compose(path.read_text(encoding="utf-8"), str(path))) or {}
    except (YamlError, OSError, UnicodeDecodeError):
        return None  # the build reports a broken sitegen.yml; a sweep does not need it
    sims = data.get("sims") if isinstance(data, dict) else None
    value = sims.get("executor") if isinstance(sims, dict) else None
    return value if isinstance(value, str) else None


def main(argv: list[str] | None = None, prog: str = "sitegen remote-api sweep") -> int:
    args = _parser(prog).parse_args(argv)
    import sims.quiet  # noqa: F401 (pybullet's banner kept off the terminal)
    from sims import runs
    from sims.sweeps.plan import parse_grid, parse_seeds, plan_runs

    try:
        problem = _check(args)
        if problem:
            print(f"error: {problem}", file=sys.stderr)
            return 2
        planned = plan_runs(
            parse_seeds(args.seeds) if args.seeds else None,
            parse_grid(args.grid),
            args.args_file,
            args.seed,
        )
    except LocatedError as exc:  # file:line: error: field: message
        print(exc, file=sys.stderr)
        return 2
    executor, address = _executor(args)
    settings = runs.settings_for(
        args.script,
        args.scene,
        seconds=args.seconds,
        timeout=args.timeout,
        after=args.after,
        server=args.server,
    )
    out = Path(args.out or f"sweep-{Path(args.script).stem}")
    from sims.sweeps.progress import SweepProgress

    try:
        chosen = runs.make_executor(executor, args.workers, address)
        described = chosen.describe()
    except (RuntimeError, ValueError) as exc:  # Ray missing or unreachable: one line
        print(f"error: {exc}", file=sys.stderr)
        return 2
    if args.verbosity >= 0:
        print(f"[sweep] {len(planned)} runs of {args.script} on {described}", file=sys.stderr)
    shown = SweepProgress(len(planned), quiet=args.verbosity < 0)
    try:
        with chosen:
            outcome = runs.sweep(settings, planned, out, chosen, progress=shown)
    except KeyboardInterrupt:
        shown.close()
        print(f"[sweep] interrupted: the rows of the {shown.done} runs that ended are in {out}",
              file=sys.stderr)  # fmt: skip
        return 130
    finally:
        shown.close()
    failed = outcome.failed
    print(
        f"[sweep] {len(outcome.records)} runs, {len(failed)} failed, on {outcome.executor}, "
        f"in {outcome.wall_seconds:.1f} s: {outcome.csv}, {outcome.jsonl}",
        file=sys.stderr,
    )
    return 1 if failed else 0


def _check(args: argparse.Namespace) -> str | None:
    if not Path(args.script).is_file():
        return f"{args.script}: no such script file"
    for name in ("seconds", "timeout"):
        value = getattr(args, name)
        if value is not None and not 0 < value < float("inf"):
            return f"--{name}: must be a positive number of seconds, not {value:g}"
    if args.workers is not None and args.workers < 1:
        return f"--workers: must be at least 1, not {args.workers}"
    from sims.scene.resolve import SceneFileError, is_bundled, open_scene

    if not is_bundled(args.scene):
        try:
            open_scene(args.scene)
        except SceneFileError as exc:
            return str(exc)
        except Exception as exc:  # a reader's own error: one line
            return f"{args.scene}: cannot load the scene: {exc}"
    return None


def _executor(args: argparse.Namespace) -> tuple[str, str | None]:
    """("ray", address) or ("local", None): --ray, else sitegen.yml's sims.executor."""
    if args.ray is not None:
        return "ray", None if args.ray == "local" else args.ray
    if configured_executor(Path.cwd()) == "ray":
        return "ray", "auto"
    return "local", None


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
