"""``sitegen gh-deploy`` against a local bare repository (never the network): the branch holds
exactly the built site, the message names the source commit, history is kept, and the author's
working tree, index and branch are left alone."""

from __future__ import annotations

import os
import subprocess
from pathlib import Path

import pytest
from sitegen_helpers import run_cli, write_tree

IDENTITY = {
    "GIT_AUTHOR_NAME": "Tester",
    "GIT_AUTHOR_EMAIL": "tester@example.invalid",
    "GIT_COMMITTER_NAME": "Tester",
    "GIT_COMMITTER_EMAIL": "tester@example.invalid",
}


def git(cwd: Path, *args: str) -> str:
    out = subprocess.run(
        ["git", *args], cwd=cwd, capture_output=True, text=True, env={**os.environ, **IDENTITY}
    )
    assert out.returncode == 0, out.stderr
    return out.stdout.strip()


@pytest.fixture()
def project(tmp_path: Path, monkeypatch) -> tuple[Path, Path]:
    for k, v in IDENTITY.items():
        monkeypatch.setenv(k, v)
    bare = tmp_path / "remote.git"
    git(tmp_path, "init", "-q", "--bare", str(bare))
    src = write_tree(
        tmp_path / "proj",
        {
            "sitegen.yml": "title: Deploy test\n",
            "content/index.md": "# Home\n\nfirst\n",
            "content/a.md": "# A\n",
            ".gitignore": "site/\n.sitegen-cache/\n",
        },
    )
    git(src, "init", "-q", "-b", "main")
    git(src, "add", "-A")
    git(src, "commit", "-q", "-m", "first")
    git(src, "remote", "add", "origin", str(bare))
    return src, bare


def test_gh_deploy_publishes_the_site_to_gh_pages(project):
    src, bare = project
    head = git(src, "rev-parse", "HEAD")
    result = run_cli("gh-deploy", "--source", str(src))
    assert result.returncode == 0, result.stderr
    files = set(git(bare, "ls-tree", "-r", "--name-only", "gh-pages").splitlines())
    built = {
        p.relative_to(src / "site").as_posix() for p in (src / "site").rglob("*") if p.is_file()
    }
    assert files == built and {"index.html", "a.html", ".nojekyll", "404.html"} <= files
    assert (
        git(bare, "log", "-1", "--format=%s", "gh-pages")
        == f"Deployed {head[:12]} with sitegen 0.1.0"
    )
    # the author's checkout is as it was: same branch, nothing staged, site/ still ignored
    assert git(src, "rev-parse", "--abbrev-ref", "HEAD") == "main"
    assert git(src, "status", "--porcelain") == ""

    # a second deploy after an edit adds one commit on top (history kept)
    (src / "content/index.md").write_text("# Home\n\nsecond\n", encoding="utf-8")
    git(src, "commit", "-q", "-am", "second")
    assert run_cli("gh-deploy", "--source", str(src), "-q").returncode == 0
    log = git(bare, "log", "--format=%s", "gh-pages").splitlines()
    assert len(log) == 2 and git(src, "rev-parse", "HEAD")[:12] in log[0]
    assert "second" in git(bare, "show", "gh-pages:index.html")

    # nothing changed: no new commit
    again = run_cli("gh-deploy", "--source", str(src))
    assert again.returncode == 0 and "already holds this site" in again.stderr
    assert len(git(bare, "log", "--format=%s", "gh-pages").splitlines()) == 2


def test_gh_deploy_to_another_remote_and_branch_with_a_message(project, tmp_path):
    src, _bare = project
    other = tmp_path / "other.git"
    git(tmp_path, "init", "-q", "--bare", str(other))
    git(src, "remote", "add", "mirror", str(other))
    result = run_cli(
        "gh-deploy",
        "--source",
        str(src),
        "--remote",
        "mirror",
        "--branch",
        "pages",
        "-m",
        "site for {sha}",
    )
    assert result.returncode == 0, result.stderr
    assert git(other, "log", "-1", "--format=%s", "pages").startswith("site for ")


def test_gh_deploy_errors_are_one_line(project, tmp_path):
    src, _bare = project
    result = run_cli("gh-deploy", "--source", str(src), "--remote", "nowhere")
    assert result.returncode == 1 and "no remote named 'nowhere'" in result.stderr
    assert "Traceback" not in result.stderr
    outside = write_tree(
        tmp_path / "loose", {"content/index.md": "# x\n", "sitegen.yml": "title: x\n"}
    )
    result = run_cli("gh-deploy", "--source", str(outside))
    assert result.returncode == 1 and "not inside a git repository" in result.stderr
    # a strict build that fails deploys nothing
    (src / "content/index.md").write_text("# Home\n\n[x](missing.md)\n", encoding="utf-8")
    result = run_cli("gh-deploy", "--source", str(src))
    assert result.returncode == 1 and "nothing was deployed" in result.stderr
    assert (
        subprocess.run(["git", "rev-parse", "--verify", "-q", "gh-pages"], cwd=_bare).returncode
        != 0
    )


def test_gh_deploy_takes_mkdocs_flags(project, tmp_path):
    """MkDocs' gh-deploy flags mean the same here: -r/--remote-name, -b/--remote-branch,
    --no-history (one parentless commit, force-pushed), --force, -d/--site-dir (build there)."""
    src, bare = project
    first = run_cli("gh-deploy", "--source", str(src), "-r", "origin", "-b", "pages", "-q")
    assert first.returncode == 0, first.stderr
    (src / "content/a.md").write_text("# A\n\nchanged\n", encoding="utf-8")
    second = run_cli(
        "gh-deploy",
        "--source",
        str(src),
        "--remote-name",
        "origin",
        "--remote-branch",
        "pages",
        "-d",
        str(tmp_path / "elsewhere"),
    )
    assert second.returncode == 0, second.stderr
    assert (tmp_path / "elsewhere/index.html").is_file()
    assert len(git(bare, "log", "--format=%H", "pages").splitlines()) == 2
    # --no-history: the branch is one commit without a parent, pushed over the old one
    again = run_cli("gh-deploy", "--source", str(src), "-b", "pages", "--no-history")
    assert again.returncode == 0, again.stderr
    assert len(git(bare, "log", "--format=%H", "pages").splitlines()) == 1
    # --force (git push --force) and --dirty (the default incremental build) are taken
    (src / "content/a.md").write_text("# A\n\nthird\n", encoding="utf-8")
    forced = run_cli("gh-deploy", "--source", str(src), "-b", "pages", "--force", "--dirty")
    assert forced.returncode == 0, forced.stderr
    assert "third" in git(bare, "show", "pages:a.html")
