"""``sitegen gh-deploy``: publish the built site to the ``gh-pages`` branch, as mkdocs does.

The commit is made by ghp-import (what ``mkdocs gh-deploy`` uses): git fast-import writes one
commit whose tree is exactly the site folder straight into the branch, so the author's working
tree, index and current branch are never touched. Around it, what ghp-import leaves to its
caller: the branch's tip is fetched from the remote first (ghp-import builds on the local
remote-tracking branch, so without a fetch a fresh clone would start the branch's history
again and its push would be refused); a commit whose tree equals its parent's is taken back,
so a site unchanged since the last deploy makes no commit; and the push is ours, so that its
failure is one line.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import subprocess
import sys
from pathlib import Path

from sitegen import __version__
from sitegen.errors import BuildError


class DeployError(RuntimeError):
    """Why the deploy stopped, in one line."""


def _git(repo: Path, *args: str, check: bool = True) -> str:
    try:
        proc = subprocess.run(["git", *args], cwd=repo, capture_output=True, text=True, timeout=600)
    except FileNotFoundError:
        raise DeployError("git is not installed") from None
    if check and proc.returncode != 0:
        detail = (proc.stderr or proc.stdout).strip().splitlines()
        raise DeployError(f"git {args[0]} failed: {detail[-1] if detail else proc.returncode}")
    return proc.stdout.strip() if proc.returncode == 0 else ""


def _ref(repo: Path, name: str) -> str | None:
    return _git(repo, "rev-parse", "--verify", "--quiet", f"{name}^{{commit}}", check=False) or None


@contextlib.contextmanager
def _in(folder: Path):
    """ghp-import runs git in the current folder."""
    before = Path.cwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(before)


def deploy(
    site: Path,
    repo: Path,
    *,
    remote: str = "origin",
    branch: str = "gh-pages",
    message: str | None = None,
    push: bool = True,
    force: bool = False,
    no_history: bool = False,
    use_shell: bool = False,
    log=lambda line: None,
) -> str | None:
    """Commit ``site`` as the new tip of ``branch`` and push it; return the new commit (None
    when the site is unchanged since the last deploy)."""
    import ghp_import

    if not (site / "index.html").is_file():
        raise DeployError(f"{site} holds no built site (no index.html): run sitegen build")
    top = _git(repo, "rev-parse", "--show-toplevel", check=False)
    if not top:
        raise DeployError(f"{repo} is not inside a git repository")
    repo = Path(top)
    source = _ref(repo, "HEAD")
    has_remote = remote in _git(repo, "remote").split()
    if push and not has_remote:
        raise DeployError(f"no remote named '{remote}' (see git remote -v, or use --remote)")
    tracking = f"refs/remotes/{remote}/{branch}"
    if has_remote and not no_history:
        _git(repo, "fetch", "--quiet", remote, f"+refs/heads/{branch}:{tracking}", check=False)
    short = source[:12] if source else "an uncommitted tree"
    text = (message or "Deployed {sha} with sitegen {version}").format(
        sha=short, version=__version__
    )
    before = _ref(repo, f"refs/heads/{branch}")
    try:
        with _in(repo):
            ghp_import.ghp_import(
                str(site.resolve()),
                mesg=text,
                remote=remote,
                branch=branch,
                push=False,
                no_history=no_history,
                nojekyll=True,
                use_shell=use_shell,
            )
    except ghp_import.GhpError as exc:
        raise DeployError(f"ghp-import: {exc.message}") from None
    commit = _ref(repo, f"refs/heads/{branch}")
    if commit is None or commit == before:
        raise DeployError(f"ghp-import made no commit on {branch}")
    parent = _ref(repo, f"{commit}^")
    if parent and _git(repo, "rev-parse", f"{parent}^{{tree}}") == _git(
        repo, "rev-parse", f"{commit}^{{tree}}"
    ):
        _git(repo, "update-ref", f"refs/heads/{branch}", parent, commit)
        log(f"sitegen: {branch} already holds this site ({parent[:12]})")
        commit = None
    else:
        log(f"sitegen: committed {commit[:12]} to {branch}: {text}")
    if push:
        forced = ["--force"] if force or no_history else []
        _git(repo, "push", "--quiet", *forced, remote, f"refs/heads/{branch}:refs/heads/{branch}")
        log(f"sitegen: pushed {branch} to {remote}")
    return commit


def gh_deploy(args: argparse.Namespace) -> int:
    quiet = args.verbosity < 0

    def log(line: str) -> None:
        if not quiet:
            print(line, file=sys.stderr)

    from sitegen.build import BuildOptions, build, resolve_paths

    opts = BuildOptions(
        source=args.source,
        output=args.site_dir,
        strict=True,
        clean=args.clean,
        log=log if args.verbosity > 0 else (lambda s: None),
    )
    try:
        _config, _content, site, _cache = resolve_paths(opts)
        if not args.no_build:
            report = build(opts)
            for d in report.diagnostics:
                print(d, file=sys.stderr)
            log(f"sitegen: built {report.pages} pages into {site}")
        deploy(
            site,
            args.source,
            remote=args.remote,
            branch=args.branch,
            message=args.message,
            push=not args.no_push,
            force=args.force,
            no_history=args.no_history,
            use_shell=args.shell,
            log=log,
        )
    except BuildError as exc:
        for d in exc.diagnostics:
            print(d, file=sys.stderr)
        print(f"sitegen gh-deploy: {exc}; nothing was deployed", file=sys.stderr)
        return 1
    except DeployError as exc:
        print(f"sitegen gh-deploy: error: {exc}", file=sys.stderr)
        return 1
    return 0
