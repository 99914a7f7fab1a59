"""What MkDocs users type works here: each long-form flag of ``mkdocs build/serve/gh-deploy``
means the same in sitegen, or is one line naming what to do instead (exit 2); ``-q``/``-v``
before the command too; ``--clean`` writes the output afresh; a build typed inside
``content/`` builds the project; ``check -v`` says what it checked."""

from __future__ import annotations

from pathlib import Path

import pytest
from sitegen_helpers import run_cli, write_tree

from sitegen.cli import make_parser

PROJECT = {
    "sitegen.yml": "title: Flags\n",
    "content/index.md": "# Home\n\n[A](a.md)\n",
    "content/a.md": "# A\n\ntext\n",
}


@pytest.fixture()
def project(tmp_path: Path) -> Path:
    return write_tree(tmp_path / "p", PROJECT)


def test_mkdocs_build_flags_mean_the_same(project, tmp_path):
    out = tmp_path / "out"
    done = run_cli("build", "-f", str(project / "sitegen.yml"), "-s", "-c", "-d", str(out))
    assert done.returncode == 0, done.stderr
    assert (out / "a.html").is_file() and not (project / "site").exists()
    again = run_cli("build", "--config-file", str(project / "sitegen.yml"), "--site-dir", str(out))
    assert again.returncode == 0 and "up to date" in again.stderr
    dirty = run_cli("build", "--source", str(project), "--dirty", "--strict", "-d", str(out))
    assert dirty.returncode == 0, dirty.stderr


def test_serve_and_deploy_flags_parse_as_mkdocs_does():
    parser = make_parser()
    serve = parser.parse_args(["serve", "-a", "127.0.0.1:8001", "--livereload", "--dirtyreload"])
    assert serve.dev_addr == "127.0.0.1:8001"
    deploy = parser.parse_args(
        ["gh-deploy", "-r", "up", "-b", "pages", "--force", "--no-history", "-d", "out", "-c"]
    )
    assert (deploy.remote, deploy.branch, deploy.force, deploy.no_history) == (
        "up",
        "pages",
        True,
        True,
    )
    assert str(deploy.site_dir) == "out" and deploy.clean
    long = parser.parse_args(["gh-deploy", "--remote-name", "up", "--remote-branch", "pages"])
    assert (long.remote, long.branch) == ("up", "pages")
    assert parser.parse_args(["gh-deploy", "--ignore-version", "--shell", "-s"]).shell


@pytest.mark.parametrize(
    "args, names",
    [
        (["build", "-t", "material"], "templates/"),
        (["build", "--theme", "material"], "templates/"),
        (["build", "--use-directory-urls"], "file://"),
        (["build", "--no-directory-urls"], "file://"),
        (["build", "-f", "mkdocs.yml"], "sitegen.yml"),
        (["serve", "--no-livereload"], "sitegen build"),
        (["serve", "-o"], "address it prints"),
        (["serve", "--open"], "address it prints"),
        (["serve", "-w", "docs"], "already watches"),
        (["serve", "--watch-theme"], "templates/"),
        (["gh-deploy", "--theme", "x"], "templates/"),
    ],
)
def test_mkdocs_flags_without_an_equivalent_are_one_line(project, args, names):
    done = run_cli(*args, cwd=project)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1 and names in lines[0] and args[1] in lines[0], done.stderr


def test_verbosity_before_the_command(project):
    loud = run_cli("-v", "build", cwd=project)
    assert loud.returncode == 0 and "wrote a.html" in loud.stderr, loud.stderr
    quiet = run_cli("-q", "build", "--clean", cwd=project)
    assert quiet.returncode == 0 and quiet.stderr == ""
    assert run_cli("-V").stdout.startswith("sitegen ")


def test_a_build_typed_in_content_builds_the_project(project):
    done = run_cli("build", "--strict", cwd=project / "content")
    assert done.returncode == 0, done.stderr
    assert "content folder of the project" in done.stderr
    assert (project / "site/a.html").is_file()
    assert sorted(p.name for p in (project / "content").iterdir()) == ["a.md", "index.md"]


def test_clean_writes_the_output_afresh(tmp_path):
    """In a site big enough to be updated in place: --clean renders every page again and
    leaves nothing the build did not make, empty folders included."""
    pages = {f"content/p{i}.md": f"# P{i}\n" for i in range(210)}
    src = write_tree(tmp_path / "big", {"sitegen.yml": "title: Big\n", **pages})
    assert run_cli("build", "-q", "--source", str(src)).returncode == 0
    (src / "site/foreign.txt").write_text("not ours", encoding="utf-8")
    (src / "site/old/deeper").mkdir(parents=True)
    (src / "site/empty").mkdir()
    done = run_cli("build", "--source", str(src), "--clean")
    assert done.returncode == 0, done.stderr
    assert "markdown rendered 210" in done.stderr
    site = src / "site"
    assert not (site / "foreign.txt").exists()
    assert not (site / "old").exists() and not (site / "empty").exists()
    assert (site / "p7.html").is_file()


def test_check_verbose_says_what_it_checked(project):
    assert run_cli("build", "-q", cwd=project).returncode == 0
    plain = run_cli("check", "site", cwd=project)
    loud = run_cli("check", "-v", "site", cwd=project)
    assert plain.returncode == loud.returncode == 0
    assert "a.html:" in loud.stderr and "a.html:" not in plain.stderr
    assert len(loud.stderr.splitlines()) > len(plain.stderr.splitlines())
