"""``sitegen gh-deploy``: publish the built site to the ``gh-pages`` branch, as mkdocs does.

The commit is made with git's plumbing and a temporary index, so the author's working tree,
index and current branch are never touched: the branch gets one new commit whose tree is
exactly the site folder, whose parent is the branch's previous tip (fetched from the remote
first, so history is kept), and whose message names the source commit. Then it is pushed.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from sitegen import __version__
from sitegen.errors import BuildError


class DeployError(RuntimeError):
    """Why the deploy stopped, in one line."""


def _git(repo: Path, *args: str, env: dict | None = None, check: bool = True) -> str:
    try:
        proc = subprocess.run(
            ["git", *args],
            cwd=repo,
            capture_output=True,
            text=True,
            env={**os.environ, **(env or {})},
            timeout=600,
        )
    except FileNotFoundError:
        raise DeployError("git is not installed") from None
    if check and proc.returncode != 0:
        detail = (proc.stderr or proc.stdout).strip().splitlines()
        raise DeployError(f"git {args[0]} failed: {detail[-1] if detail else proc.returncode}")
    return proc.stdout.strip() if proc.returncode == 0 else ""


def _ref(repo: Path, name: str) -> str | None:
    return _git(repo, "rev-parse", "--verify", "--quiet", f"{name}^{{commit}}", check=False) or None


def deploy(
    site: Path,
    repo: Path,
    *,
    remote: str = "origin",
    branch: str = "gh-pages",
    message: str | None = None,
    push: bool = True,
    log=lambda line: None,
) -> str | None:
    """Commit ``site`` as the new tip of ``branch`` and push it; return the new commit (None
    when the site is unchanged since the last deploy)."""
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
    parent = None
    if has_remote:
        fetched = _git(
            repo,
            "fetch",
            "--quiet",
            remote,
            f"+refs/heads/{branch}:refs/remotes/{remote}/{branch}",
            check=False,
        )
        del fetched
        parent = _ref(repo, f"refs/remotes/{remote}/{branch}")
    parent = parent or _ref(repo, f"refs/heads/{branch}")
    with tempfile.TemporaryDirectory(prefix="sitegen-deploy-") as tmp:
        env = {"GIT_INDEX_FILE": str(Path(tmp) / "index")}
        _git(repo, f"--work-tree={site.resolve()}", "add", "--all", "--force", ".", env=env)
        tree = _git(repo, "write-tree", env=env)
    if parent and _git(repo, "rev-parse", f"{parent}^{{tree}}") == tree:
        log(f"sitegen: {branch} already holds this site ({parent[:12]})")
        commit = None
    else:
        short = source[:12] if source else "an uncommitted tree"
        text = (message or "Deployed {sha} with sitegen {version}").format(
            sha=short, version=__version__
        )
        args = ["commit-tree", tree, "-m", text] + (["-p", parent] if parent else [])
        commit = _git(repo, *args)
        _git(repo, "update-ref", f"refs/heads/{branch}", commit, *([parent] if parent else []))
        log(f"sitegen: committed {commit[:12]} to {branch}: {text}")
    if push:
        _git(repo, "push", "--quiet", remote, f"refs/heads/{branch}:refs/heads/{branch}")
        log(f"sitegen: pushed {branch} to {remote}")
    return commit


def gh_deploy(args: argparse.Namespace) -> int:
    quiet = args.verbosity < 0

    def log(line: str) -> None:
        if not quiet:
            print(line, file=sys.stderr)

    from sitegen.build import BuildOptions, build, resolve_paths

    opts = BuildOptions(
        source=args.source, strict=True, log=log if args.verbosity > 0 else (lambda s: None)
    )
    try:
        _config, _content, output, _cache = resolve_paths(opts)
        site = args.site_dir or output
        if not args.no_build and args.site_dir is None:
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
