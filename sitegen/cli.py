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


class _NotHere(argparse.Action):
    """A MkDocs flag with no sitegen equivalent: one line that says what to do instead."""

    def __init__(self, option_strings, dest, why: str = "", nargs=0, **kw) -> None:
        super().__init__(option_strings, argparse.SUPPRESS, nargs=nargs, help=argparse.SUPPRESS)
        self.why = why

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        print(f"{parser.prog}: error: {option_string}: {self.why}", file=sys.stderr)
        raise SystemExit(2)


def _not_here(p: argparse.ArgumentParser, *flags: str, why: str, value: bool = False) -> None:
    p.add_argument(*flags, action=_NotHere, why=why, nargs="?" if value else 0)


def make_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="sitegen", description="Static course-site generator with a simulation gallery."
    )
    parser.add_argument("-V", "--version", action="version", version=f"sitegen {__version__}")
    # -q/-v before the command too (`sitegen -v build`), as after it
    top = parser.add_mutually_exclusive_group()
    top.add_argument("-q", "--quiet", dest="top_verbosity", action="store_const", const=-1)
    top.add_argument("-v", "--verbose", dest="top_verbosity", action="store_const", const=1)
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
        "-a",
        "--dev-addr",
        metavar="HOST:PORT",
        help="loopback address to serve on (default 127.0.0.1:8000; port 0 picks a free one)",
    )
    addr.add_argument("--port", default="8000", help="port on 127.0.0.1 (default 8000)")
    s.add_argument(
        "--livereload",
        action="store_true",
        help="reload the open page after a rebuild (always on: as in MkDocs)",
    )
    s.add_argument(
        "--dirtyreload",
        action="store_true",
        help="rebuild only what changed (always: every sitegen build does)",
    )
    _not_here(
        s,
        "--no-livereload",
        why="sitegen serve always reloads the page; for a plain copy run sitegen build "
        "and open site/index.html",
    )
    _not_here(
        s,
        "-o",
        "--open",
        why="sitegen serve does not open a browser: open the address it prints",
    )
    _not_here(
        s,
        "-w",
        "--watch",
        value=True,
        why="sitegen serve already watches the whole project (sitegen.yml, content, templates, "
        "the clips' scripts and scenes)",
    )
    _not_here(
        s,
        "--watch-theme",
        why="sitegen serve already watches the project's templates/ (templates_dir:)",
    )
    c = sub.add_parser(
        "check",
        help="check a built site offline",
        description="Check a built site offline: internal links, anchors, images, scripts.",
        parents=[loud],
    )
    c.add_argument(
        "dir", nargs="?", default="site", type=Path, help="the built site (default: site)"
    )
    c.set_defaults(loud_help="also print each page checked and what it links to")
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
    n.add_argument(
        "--from",
        dest="install_from",
        metavar="SPEC",
        default=None,
        help="where the site's CI installs sitegen from (requirements.txt): a git URL with "
        "@tag or @commit, a wheel's URL, a path, or a pip requirement (default: this "
        "project's repository at the tag of this version)",
    )
    g = sub.add_parser(
        "gh-deploy",
        help="publish the built site to the gh-pages branch",
        description="Commit the built site to the gh-pages branch of the current repository "
        "(the message names the source commit) and push it, as mkdocs gh-deploy does.",
        parents=[loud],
    )
    _config_args(g)
    g.add_argument(
        "-d",
        "--site-dir",
        type=Path,
        default=None,
        help="where to build the site and deploy it from (default: the config's output_dir)",
    )
    g.add_argument(
        "-r",
        "--remote",
        "--remote-name",
        dest="remote",
        default="origin",
        help="remote to push to (default: origin)",
    )
    g.add_argument(
        "-b",
        "--branch",
        "--remote-branch",
        dest="branch",
        default="gh-pages",
        help="branch to commit to (default: gh-pages)",
    )
    g.add_argument(
        "-m", "--message", default=None, help="commit message ({sha} and {version} are replaced)"
    )
    g.add_argument("--force", action="store_true", help="force the push (replaces the branch)")
    g.add_argument(
        "--no-history",
        action="store_true",
        help="one commit with no parent: the branch keeps no history (pushed with --force)",
    )
    g.add_argument("--no-push", action="store_true", help="commit only, do not push")
    g.add_argument(
        "--no-build",
        action="store_true",
        help="deploy the site folder as it is (default: a strict build first)",
    )
    g.add_argument("-s", "--strict", action="store_true", help="(always: the build is strict)")
    _clean_args(g)
    g.add_argument(
        "--ignore-version",
        action="store_true",
        help="(always: sitegen does not compare the deployed site's sitegen version)",
    )
    g.add_argument("--shell", action="store_true", help="run git through the shell (ghp-import)")
    _theme_flags(g)
    for name, (_mod, help_text) in DELEGATED.items():
        sub.add_parser(name, help=help_text, add_help=False)
    return parser


def _config_args(p: argparse.ArgumentParser) -> None:
    p.add_argument(
        "--source",
        type=Path,
        default=None,
        help="project folder with sitegen.yml, or any folder of Markdown (default: .)",
    )
    p.add_argument(
        "-f",
        "--config-file",
        type=Path,
        default=None,
        metavar="sitegen.yml",
        help="the project's sitegen.yml: its folder is the project (as --source)",
    )


def _clean_args(p: argparse.ArgumentParser) -> None:
    how = p.add_mutually_exclusive_group()
    how.add_argument(
        "-c",
        "--clean",
        action="store_true",
        help="render every page again and write the output folder afresh, removing what the "
        "build did not make (clips come from the clip cache: its keys cover what they are "
        "made of; docs/clips.md)",
    )
    how.add_argument(
        "--dirty",
        action="store_true",
        help="rebuild only what changed (the default: every sitegen build does)",
    )


def _theme_flags(p: argparse.ArgumentParser) -> None:
    _not_here(
        p,
        "-t",
        "--theme",
        value=True,
        why="sitegen has one theme: override any of its files in a templates/ folder beside "
        "sitegen.yml (templates_dir: names another; docs/authoring.md#themes)",
    )
    for flag in ("--use-directory-urls", "--no-directory-urls"):
        _not_here(
            p,
            flag,
            why="sitegen's links always name the file (page.html, dir/index.html), so a site "
            "works from file:// and on GitHub Pages alike; there is no other form",
        )


def _build_args(p: argparse.ArgumentParser) -> None:
    _config_args(p)
    p.add_argument(
        "-d",
        "--output",
        "--site-dir",
        dest="output",
        type=Path,
        default=None,
        help="where to write the site (default: the config's output_dir, site/)",
    )
    p.add_argument(
        "-s",
        "--strict",
        action="store_true",
        help="treat warnings (broken links, failed clips) as errors",
    )
    _clean_args(p)
    p.add_argument(
        "--retry-failed",
        action="store_true",
        help="render again the clips whose failure is remembered in the cache (docs/clips.md)",
    )
    _theme_flags(p)


def project_source(args: argparse.Namespace) -> Path:
    """The project folder the command works on: ``--source``, or the folder of
    ``-f/--config-file``, or the current folder -- or, when that is inside the content folder
    of a project above it (``sitegen build`` typed in ``content/``), that project, as git finds
    its repository from a subfolder. Raises :class:`UsageError`."""
    from sitegen.config import CONFIG_NAME

    source, config_file = args.source, args.config_file
    if config_file is not None:
        if config_file.name != CONFIG_NAME or not config_file.is_file():
            hint = (
                "sitegen reads sitegen.yml, not MkDocs' mkdocs.yml"
                if config_file.name == "mkdocs.yml"
                else f"not a {CONFIG_NAME} file"
            )
            raise UsageError(f"-f/--config-file {config_file}: {hint}; use --source FOLDER")
        if config_file.name != CONFIG_NAME:
            raise UsageError(
                f"-f/--config-file {config_file}: the file must be named {CONFIG_NAME}"
            )
        if source is not None and source.resolve() != config_file.parent.resolve():
            raise UsageError("--source and -f/--config-file name different projects")
        return config_file.parent
    if source is not None:
        return source
    here = Path.cwd()
    if (here / CONFIG_NAME).is_file():
        return Path(".")
    for folder in here.parents:
        if (folder / CONFIG_NAME).is_file():
            from sitegen.config import load_config

            content = load_config(folder).content_path.resolve()
            if here == content or here.is_relative_to(content):
                if args.verbosity >= 0:
                    print(
                        f"sitegen: {here} is in the content folder of the project {folder}: "
                        "building that project",
                        file=sys.stderr,
                    )
                return folder
            break
    return Path(".")


class UsageError(Exception):
    """A command line that cannot be carried out: one line, exit status 2."""


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
    if args.top_verbosity is not None and not args.verbosity:
        args.verbosity = args.top_verbosity
    try:
        if hasattr(args, "config_file"):
            args.source = project_source(args)
    except UsageError as exc:
        print(f"sitegen {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except BuildError as exc:
        for d in exc.diagnostics:
            print(d, file=sys.stderr)
        print(f"sitegen: {exc}", file=sys.stderr)
        return 1
    try:
        if args.command == "build":
            return _build(args)
        if args.command == "serve":
            from sitegen.serve import serve

            return serve(args)
        if args.command == "check":
            from sitegen.check import check_site

            log = (lambda line: print(line, file=sys.stderr)) if args.verbosity > 0 else None
            problems = check_site(args.dir, log=log)
            for p in problems:
                print(p, file=sys.stderr)
            if args.verbosity >= 0 or problems:
                print(f"checked {args.dir}: {len(problems)} problem(s)", file=sys.stderr)
            return 1 if problems else 0
        if args.command == "new":
            from sitegen.scaffold import new_site

            return new_site(args.dir, args.title, args.language, args.verbosity, args.install_from)
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
