"""Command line for the simulation gallery: ``sitegen sims list|render``.

``main`` returns an exit code instead of exiting: 0 fine, 1 a clip failed, 2 usage error.
Errors are single lines; no tracebacks reach the user.
"""

from __future__ import annotations

import argparse
import re
import shutil
import sys
from pathlib import Path

from located.verbosity import add_verbosity

DEFAULT_CACHE = ".sitegen-cache/clips"
DEFAULT_OUT = "clips"


class UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # argparse would print usage and sys.exit(2)
        raise UsageError(message)


def _size(text: str) -> tuple[int, int]:
    m = re.fullmatch(r"(\d+)[xX](\d+)", text.strip())
    if not m:
        raise argparse.ArgumentTypeError(f"size must look like 480x360, not {text!r}")
    return int(m.group(1)), int(m.group(2))


def _positive(kind: type):
    def parse(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"not a number: {text!r}") from None
        if value <= 0:
            raise argparse.ArgumentTypeError(f"must be positive: {text!r}")
        return value

    return parse


def _add_verbosity(p: argparse.ArgumentParser) -> None:
    add_verbosity(
        p,
        "list: names only; render: failures only",
        "list: also parameters; render: also each file written",
    )


def build_parser(prog: str) -> argparse.ArgumentParser:
    parser = _Parser(prog=prog, description="Headless robot simulations and their clips.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    _add_verbosity(sub.add_parser("list", help="list the scenarios"))
    render = sub.add_parser("render", help="render clips of scenarios (NAME or 'all')")
    render.add_argument("names", nargs="+", metavar="NAME")
    _add_verbosity(render)
    render.add_argument("--out", default=DEFAULT_OUT, help=f"output folder (default {DEFAULT_OUT})")
    render.add_argument("--size", type=_size, default=(480, 360), help="WxH (default 480x360)")
    render.add_argument("--fps", type=_positive(int), default=20, help="frames per second")
    render.add_argument(
        "--seconds", type=_positive(float), help="clip length (default: scenario's)"
    )
    render.add_argument("--seed", type=int, help="seed (default: scenario's)")
    render.add_argument(
        "--speed", type=_positive(float), default=1.0, help="time-lapse factor, >= 1 (default 1)"
    )
    render.add_argument("--jobs", type=_positive(int), help="parallel workers (default: CPUs)")
    render.add_argument(
        "--cache", default=DEFAULT_CACHE, help=f"cache folder (default {DEFAULT_CACHE})"
    )
    return parser


def main(argv: list[str] | None = None, prog: str = "sitegen sims") -> int:
    parser = build_parser(prog)
    try:
        args = parser.parse_args(argv)
        if args.command is None:
            raise UsageError("a command is required: list or render")
        if args.command == "list":
            return _list(args.verbosity)
        return _render(args, prog)
    except UsageError as exc:
        print(f"{prog}: {exc}", file=sys.stderr)
        print(
            f"usage: {prog} list | render NAME... [--out DIR] [--size WxH] [--fps N] "
            "[--seconds S] [--speed X] [--jobs N]",
            file=sys.stderr,
        )
        return 2
    except SystemExit as exc:  # --help
        return int(exc.code or 0)
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # an unexpected error is still one line
        print(f"{prog}: error: {type(exc).__name__}: {exc}", file=sys.stderr)
        return 1


def _list(verbosity: int = 0) -> int:
    from sims.scenarios import list_scenarios

    scenarios = list_scenarios()
    width = max(len(s.name) for s in scenarios)
    for s in scenarios:
        if verbosity < 0:
            print(s.name)
            continue
        duration = f"{s.duration_for(s.params):g} s"
        print(f"{s.name:<{width}}  {s.scene:<5} {duration:>6}  {s.description}")
        if verbosity > 0:
            for key, value in sorted(s.params.items()):
                print(f"{'':<{width}}    {key} = {value!r}")
    return 0


def _render(args: argparse.Namespace, prog: str) -> int:
    from sims.clips import ClipSpec, render_clips
    from sims.render import fallback_note
    from sims.scenarios import list_scenarios

    known = [s.name for s in list_scenarios()]
    names = known if args.names == ["all"] else list(dict.fromkeys(args.names))
    unknown = [n for n in names if n not in known]
    if args.speed < 1:
        raise UsageError(f"--speed must be at least 1, not {args.speed:g}")
    if unknown:
        raise UsageError(f"unknown scenario {', '.join(unknown)} (known: {', '.join(known)})")
    width, height = args.size
    specs = [
        ClipSpec(
            name=n,
            scenario=n,
            width=width,
            height=height,
            fps=args.fps,
            seconds=args.seconds,
            seed=args.seed,
            speed=args.speed,
        )
        for n in names
    ]
    results = render_clips(specs, Path(args.cache), jobs=args.jobs)
    out = Path(args.out)
    failed = 0
    for r in results:
        target = out / r.name
        if r.files:
            target.mkdir(parents=True, exist_ok=True)
            for path in r.files.values():
                shutil.copyfile(path, target / path.name)
        if r.ok and args.verbosity < 0:
            continue
        if r.ok:
            how = f"rendered in {r.seconds:.1f} s" if r.rendered else "cached"
            print(
                f"ok      {r.name}: {r.meta.get('frames')} frames "
                f"{r.meta.get('width')}x{r.meta.get('height')}, {how} -> {target}/"
            )
            if args.verbosity > 0:
                for path in sorted(r.files.values()):
                    print(f"          wrote {target / path.name}")
        else:
            failed += 1
            kept = f" (kept the previous clip in {target}/)" if r.stale else ""
            print(f"FAILED  {r.name}: {r.error}{kept}")
    note = fallback_note(r.fallback for r in results)
    if note and args.verbosity >= 0:
        print(f"{prog}: {note}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(prog="python -m sims.cli"))
