"""``sitegen new DIR``: a course site that builds at once with ``--strict`` and reads well in
a browser (home, a week page with an image, tabs, admonitions, code and a rendered clip)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest
import yaml
from browser_kit import PHONE, WIDE, chromium, open_page, require_browser, static_server
from sitegen_helpers import REPO, run_cli

from sitegen import DISTRIBUTION, RELEASE_TAG, REPOSITORY
from sitegen.config import _CLIP, _SIMS, _TOP


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("new") / "my-course"
    result = run_cli("new", str(root), "--title", "機械設計: 課程")
    assert result.returncode == 0, result.stderr
    built = run_cli("build", "--strict", "--source", str(root))
    assert built.returncode == 0, built.stderr
    return root


def test_new_site_has_every_part_an_author_needs(made, tmp_path):
    for rel in (
        "sitegen.yml",
        "content/index.md",
        "content/stage-1/index.md",
        "content/stage-1/w1/index.md",
        "content/stage-1/w1/cart.svg",
        ".github/workflows/pages.yml",
        ".github/workflows/check.yml",
        ".gitignore",
        "requirements.txt",
        "scripts/drive.py",
        "scenes/rover.simscene.xml",
        "data/groups.txt",
    ):
        assert (made / rel).is_file(), rel
    config = (made / "sitegen.yml").read_text(encoding="utf-8")
    assert yaml.safe_load(config)["title"] == "機械設計: 課程"  # quoted as YAML
    # every key sitegen reads is in the file, set or commented with an explanation
    for key in [*_TOP, *_SIMS, *_CLIP]:
        assert re.search(rf"\b{key}:", config), key
    assert "site/" in (made / ".gitignore").read_text() and (made / "site/index.html").is_file()
    # what a build leaves in a project (.sitegen-cache/, .sitegen-cache-site/ ...) is ignored
    (tmp_path / ".gitignore").write_bytes((made / ".gitignore").read_bytes())
    subprocess.run(["git", "init", "-q", str(tmp_path)], check=True)
    ignored = subprocess.run(
        ["git", "check-ignore", "--no-index", ".sitegen-cache/x", ".sitegen-cache-site/x"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
    )
    assert ignored.stdout.split() == [".sitegen-cache/x", ".sitegen-cache-site/x"]


def test_the_readme_tour_runs_in_a_new_site(made):
    """Every path the README's tour names is in a new site, and its commands run there."""
    readme = (REPO / "README.md").read_text(encoding="utf-8")
    tour = readme.split("## A five-minute tour", 1)[1].split("\n## Remote API", 1)[0]
    for rel in ("scripts/drive.py", "scenes/rover.simscene.xml", "data/groups.txt"):
        assert rel in tour and (made / rel).is_file(), rel
    for args in (
        ["scene", "show", "scenes/rover.simscene.xml"],
        ["remote-api", "run", "scripts/drive.py", "--scene", "scenes/rover.simscene.xml"],
        ["roster", "check", "data/groups.txt"],
    ):
        assert " ".join(args) in tour, args
        done = run_cli(*args, cwd=made)
        assert done.returncode == 0, done.stderr


def test_requirements_pin_where_sitegen_is(tmp_path, monkeypatch):
    """CI installs sitegen from the project's repository at this version's tag, or from what
    --from names; never the name `sitegen` from PyPI (another project's)."""
    from sitegen import scaffold

    monkeypatch.setattr(scaffold, "_installed_from_git", lambda: None)
    default = scaffold.requirement()
    assert default == f"{DISTRIBUTION} @ git+{REPOSITORY}@{RELEASE_TAG}"
    monkeypatch.setattr(scaffold, "_installed_from_git", lambda: "git+https://h/o/r@abc123")
    assert scaffold.requirement() == f"{DISTRIBUTION} @ git+https://h/o/r@abc123"
    url = "git+https://example.org/me/sitegen@v9"
    assert scaffold.requirement(url) == f"{DISTRIBUTION} @ {url}"
    assert scaffold.requirement(f"{DISTRIBUTION}==0.2") == f"{DISTRIBUTION}==0.2"
    assert scaffold.requirement("git+file:///srv/clone@v1") == "git+file:///srv/clone@v1"
    wheel = tmp_path / "x.whl"
    wheel.write_bytes(b"")
    assert scaffold.requirement(str(wheel)) == f"{DISTRIBUTION} @ {wheel.as_uri()}"
    with pytest.raises(ValueError, match="no such file"):
        scaffold.requirement(str(tmp_path / "missing"))
    made = run_cli("new", str(tmp_path / "n"), "--from", url)
    assert made.returncode == 0, made.stderr
    lines = (tmp_path / "n/requirements.txt").read_text(encoding="utf-8").splitlines()
    assert lines[-1] == f"{DISTRIBUTION} @ {url}" and "warning" not in made.stderr
    bad = run_cli("new", str(tmp_path / "m"), "--from", str(tmp_path / "missing"))
    assert bad.returncode == 2 and len(bad.stderr.strip().splitlines()) == 1


def test_new_site_workflows_build_strictly_with_current_actions(made):
    for name in ("pages.yml", "check.yml"):
        wf = yaml.safe_load((made / ".github/workflows" / name).read_text(encoding="utf-8"))
        steps = [s for job in wf["jobs"].values() for s in job["steps"]]
        runs = " ".join(s.get("run", "") for s in steps)
        assert "sitegen build --strict" in runs and "sitegen check site" in runs, name
        assert "pip install -q -r requirements.txt" in runs
        for s in steps:
            if "uses" in s:
                assert re.match(r"^actions/[\w-]+@v\d+$", s["uses"]), s["uses"]


def test_new_refuses_a_folder_with_files(tmp_path):
    (tmp_path / "x").mkdir()
    (tmp_path / "x" / "keep.md").write_text("mine", encoding="utf-8")
    result = run_cli("new", str(tmp_path / "x"))
    assert result.returncode == 1 and "not an empty folder" in result.stderr
    assert sorted(p.name for p in (tmp_path / "x").iterdir()) == ["keep.md"]


@pytest.mark.parametrize("size", [WIDE, PHONE], ids=["wide", "phone"])
def test_new_site_in_the_browser(made, size):
    require_browser()
    site = made / "site"
    with chromium() as browser, static_server(site) as base:
        for url in (base, site.as_uri() + "/"):
            with open_page(browser, size, site) as page:
                page.goto(url + "index.html")
                assert page.locator("main > h1").inner_text() == "機械設計: 課程"
                page.goto(url + "stage-1/w1/index.html")
                assert page.locator("main > h1").inner_text() == "W1 Getting started"
                img = page.locator(".body p > img")
                assert img.evaluate("i => i.complete && i.naturalWidth > 0")
                assert page.locator(".tabbed-set label").count() == 3
                assert page.locator(".admonition").count() == 2
                assert page.locator(".body .copy").count() >= 4
                replay = page.locator("figure.clip-replay")  # a new site's clips: replays
                replay.scroll_into_view_if_needed()
                page.wait_for_function(
                    "f => f.dataset.state === 'ready' && f.sitegenReplay.frames > 0",
                    arg=replay.element_handle(),
                    timeout=20000,
                )
