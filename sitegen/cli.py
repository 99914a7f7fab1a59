"""The ``sitegen`` command line.

Exit codes: 0 success, 1 build or input errors, 2 usage errors. Every problem is one line
(``file:line: severity: field: message``); a traceback is never what a user sees, except
for a bug in sitegen itself, which is reported as such.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from sitegen import __version__
from sitegen.errors import BuildError

# Sub-commands owned by the other packages: the rest of argv is handed to their own CLI.
DELEGATED = {
    "roster": ("roster.cli", "rosters: check a roster, print its links"),
    "sims": ("sims.cli", "simulations: list scenarios, render clips"),
    "remote-api": (
        "sims.remote_api.cli",
        "run a CoppeliaSim remote API script on a pybullet scene",
    ),
    "import": ("sitegen.importers.cli", "import an existing site (cmsimde)"),
}


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # usage errors: one line, exit 2
        self.print_usage(sys.stderr)
        print(f"{self.prog}: error: {message}", file=sys.stderr)
        raise SystemExit(2)


def make_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="sitegen", description="Static course-site generator with a simulation gallery."
    )
    parser.add_argument("--version", action="version", version=f"sitegen {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    b = sub.add_parser(
        "build",
        help="build the static site",
        description="Build content/ (or any folder of Markdown) into a static site.",
    )
    _build_args(b)
    s = sub.add_parser(
        "serve",
        help="build, serve on 127.0.0.1, rebuild on change",
        description="Build, serve the site on 127.0.0.1, rebuild when a source changes and reload the open page.",
    )
    _build_args(s)
    s.add_argument(
        "--port",
        type=int,
        default=8000,
        help="port on 127.0.0.1 (default 8000; 0 picks a free one)",
    )
    c = sub.add_parser(
        "check",
        help="check a built site offline",
        description="Check a built site offline: internal links, anchors, images, scripts.",
    )
    c.add_argument(
        "dir", nargs="?", default="site", type=Path, help="the built site (default: site)"
    )
    for name, (_mod, help_text) in DELEGATED.items():
        sub.add_parser(name, help=help_text, add_help=False)
    return parser


def _build_args(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--source",
        type=Path,
        default=Path("."),
        help="project folder with sitegen.yml, or any folder of Markdown (default: .)",
    )
    p.add_argument(
        "--output", type=Path, default=None, help="where to write the site (default: site/)"
    )
    p.add_argument(
        "--strict",
        action="store_true",
        help="treat warnings (broken links, failed clips) as errors",
    )
    p.add_argument("--clean", action="store_true", help="ignore the cache and rebuild everything")


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in DELEGATED:
        import importlib

        module = importlib.import_module(DELEGATED[argv[0]][0])
        return int(module.main(argv[1:], prog=f"sitegen {argv[0]}") or 0)
    parser = make_parser()
    args = parser.parse_args(argv)
    if args.command is None:
        parser.print_help()
        return 2
    try:
        if args.command == "build":
            return _build(args)
        if args.command == "serve":
            from sitegen.serve import serve

            return serve(args)
        if args.command == "check":
            from sitegen.check import check_site

            problems = check_site(args.dir)
            for p in problems:
                print(p, file=sys.stderr)
            print(f"checked {args.dir}: {len(problems)} problem(s)", file=sys.stderr)
            return 1 if problems else 0
    except BuildError as exc:
        for d in exc.diagnostics:
            print(d, file=sys.stderr)
        print(f"sitegen: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130
    return 2


def _build(args: argparse.Namespace) -> int:
    from sitegen.build import BuildOptions, build

    opts = BuildOptions(
        source=args.source,
        output=args.output,
        strict=args.strict,
        clean=args.clean,
        is_tty=sys.stderr.isatty(),
    )
    report = build(opts)
    for d in report.diagnostics:
        print(d, file=sys.stderr)
    for note in report.notes:
        print(note, file=sys.stderr)
    if report.up_to_date:
        print(f"sitegen: {report.output} is up to date ({report.seconds:.2f}s)", file=sys.stderr)
    else:
        print(
            f"sitegen: built {report.pages} pages into {report.output} in {report.seconds:.2f}s "
            f"(markdown rendered {report.markdown_rendered}, pages rendered {report.pages_rendered}, "
            f"files changed {len(report.changed)}, warnings {len(report.diagnostics)})",
            file=sys.stderr,
        )
    return 0
