"""``sitegen new DIR``: a course site that builds at once with ``--strict`` and reads well in
a browser (home, a week page with an image, tabs, admonitions, code and a rendered clip)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml
from browser_kit import PHONE, WIDE, chromium, open_page, require_browser, static_server
from sitegen_helpers import run_cli

from sitegen.config import _CLIP, _SIMS, _TOP


@pytest.fixture(scope="module")
def made(tmp_path_factory) -> Path:
    root = tmp_path_factory.mktemp("new") / "my-course"
    result = run_cli("new", str(root), "--title", "機械設計: 課程")
    assert result.returncode == 0, result.stderr
    built = run_cli("build", "--strict", "--source", str(root))
    assert built.returncode == 0, built.stderr
    return root


def test_new_site_has_every_part_an_author_needs(made):
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
    ):
        assert (made / rel).is_file(), rel
    config = (made / "sitegen.yml").read_text(encoding="utf-8")
    assert yaml.safe_load(config)["title"] == "機械設計: 課程"  # quoted as YAML
    # every key sitegen reads is in the file, set or commented with an explanation
    for key in [*_TOP, *_SIMS, *_CLIP]:
        assert re.search(rf"\b{key}:", config), key
    assert "site/" in (made / ".gitignore").read_text() and (made / "site/index.html").is_file()


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
