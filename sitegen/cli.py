"""The ``sitegen`` command line.

Exit codes: 0 success, 1 build or input errors, 2 usage errors. Every problem is one line
(``file:line: severity: field: message``); a traceback is never what a user sees, except
for a bug in sitegen itself, which is reported as such.
"""

from __future__ import annotations

import argparse
import gc
import sys
from pathlib import Path

from located.verbosity import add_verbosity
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
    "scene": ("sims.scene.show", "CoppeliaSim scene files: show the object tree"),
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
    loud = _Parser(add_help=False)
    add_verbosity(loud, "print only warnings and errors", "also print each file written")
    b = sub.add_parser(
        "build",
        help="build the static site",
        description="Build content/ (or any folder of Markdown) into a static site.",
        parents=[loud],
    )
    _build_args(b)
    s = sub.add_parser(
        "serve",
        help="build, serve on 127.0.0.1, rebuild on change",
        description="Serve the site on this machine, rebuild when a source changes and reload the "
        "open page. The address is checked before the first build.",
        parents=[loud],
    )
    _build_args(s)
    addr = s.add_mutually_exclusive_group()
    addr.add_argument(
        "--dev-addr",
        metavar="HOST:PORT",
        help="loopback address to serve on (default 127.0.0.1:8000; port 0 picks a free one)",
    )
    addr.add_argument("--port", default="8000", help="port on 127.0.0.1 (default 8000)")
    c = sub.add_parser(
        "check",
        help="check a built site offline",
        description="Check a built site offline: internal links, anchors, images, scripts.",
        parents=[loud],
    )
    c.add_argument(
        "dir", nargs="?", default="site", type=Path, help="the built site (default: site)"
    )
    n = sub.add_parser(
        "new",
        help="create a new course site that builds at once",
        description="Create a course site in DIR: sitegen.yml (every key explained), a home "
        "page, one stage with one week page, an image, a simulation clip, and GitHub Actions "
        "workflows. DIR must not exist or be empty.",
        parents=[loud],
    )
    n.add_argument("dir", type=Path, help="folder to create")
    n.add_argument("--title", default=None, help="the site's title (default: the folder's name)")
    n.add_argument(
        "--language", choices=["zh-TW", "en"], default="zh-TW", help="interface language"
    )
    g = sub.add_parser(
        "gh-deploy",
        help="publish the built site to the gh-pages branch",
        description="Commit the built site to the gh-pages branch of the current repository "
        "(the message names the source commit) and push it, as mkdocs gh-deploy does.",
        parents=[loud],
    )
    g.add_argument(
        "--site-dir", type=Path, default=None, help="the built site (default: the config's output)"
    )
    g.add_argument("--source", type=Path, default=Path("."), help="project folder (default: .)")
    g.add_argument("--remote", default="origin", help="remote to push to (default: origin)")
    g.add_argument("--branch", default="gh-pages", help="branch to commit to (default: gh-pages)")
    g.add_argument("-m", "--message", default=None, help="commit message ({sha} is replaced)")
    g.add_argument("--no-push", action="store_true", help="commit only, do not push")
    g.add_argument(
        "--no-build",
        action="store_true",
        help="deploy the site as it is (default: a strict build first)",
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
    p.add_argument(
        "--retry-failed",
        action="store_true",
        help="render again the clips whose failure is remembered in the cache (docs/clips.md)",
    )


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
            if args.verbosity >= 0 or problems:
                print(f"checked {args.dir}: {len(problems)} problem(s)", file=sys.stderr)
            return 1 if problems else 0
        if args.command == "new":
            from sitegen.scaffold import new_site

            return new_site(args.dir, args.title, args.language, args.verbosity)
        if args.command == "gh-deploy":
            from sitegen.deploy import gh_deploy

            return gh_deploy(args)
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

    # the process ends with the build: the collector, paused during it anyway
    # (sitegen.build.collector_paused), would only walk what the build leaves behind
    gc.disable()
    quiet, verbose = args.verbosity < 0, args.verbosity > 0
    opts = BuildOptions(
        source=args.source,
        output=args.output,
        strict=args.strict,
        clean=args.clean,
        is_tty=sys.stderr.isatty() and not quiet,
        retry_failed=getattr(args, "retry_failed", False),
    )
    if quiet:
        opts.log = lambda line: None
    report = build(opts)
    for d in report.diagnostics:
        print(d, file=sys.stderr)
    if quiet:
        return 0
    for note in report.notes:
        print(note, file=sys.stderr)
    if verbose:
        for rel in report.changed:
            print(f"  wrote {rel}", file=sys.stderr)
    if report.up_to_date:
        print(f"sitegen: {report.output} is up to date ({report.seconds:.2f}s)", file=sys.stderr)
    else:
        print(
            f"sitegen: built {report.pages} pages into {report.output} in {report.seconds:.2f}s "
            f"(markdown rendered {report.markdown_rendered}, "
            f"pages rendered {report.pages_rendered}, "
            f"files changed {len(report.changed)}, warnings {len(report.diagnostics)})",
            file=sys.stderr,
        )
    return 0
