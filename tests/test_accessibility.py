"""Accessibility, checked with axe-core (the engine Lighthouse's accessibility audit runs) in
Chromium: a week page, the gallery, a deck, the blog index and the header search's results, at
desktop and phone width, in light and dark. No serious or critical violation, and none at all
of colour contrast or of landmarks told apart.

axe-core comes from npm (``tests/a11y/package.json``, installed by .ci/setup). The Lighthouse
score itself is a bench: ``python bench/a11y_bench.py`` (docs/authoring.md, Accessibility).
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from browser_kit import PHONE, WIDE, chromium, open_page, require_browser, static_server
from reader_site import build_reader_site

AXE = Path(__file__).resolve().parent / "a11y" / "node_modules" / "axe-core" / "axe.min.js"
PAGES = {
    "week": "stage-1/w1/index.html",
    "gallery": "gallery/index.html",
    "deck": "slides/w1-report.slides.html",
    "blog": "blog/index.html",
}
ALWAYS = {"color-contrast", "landmark-unique", "landmark-no-duplicate-banner"}


def require_axe() -> str:
    if not AXE.is_file():
        message = f"axe-core is not installed ({AXE}): npm ci --prefix tests/a11y (.ci/setup)"
        if os.environ.get("CI"):
            pytest.fail(message)
        pytest.skip(message)
    return AXE.read_text(encoding="utf-8")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    return build_reader_site(tmp_path_factory.mktemp("a11y") / "course") / "site"


@pytest.fixture(scope="module")
def served(site):
    """Over http, as GitHub Pages serves it (axe reads the stylesheets, which file:// forbids)."""
    require_browser()
    with chromium() as browser, static_server(site) as base:
        yield browser, base


def problems(page, axe: str) -> list[str]:
    page.add_script_tag(content=axe)
    found = page.evaluate("axe.run(document, {resultTypes: ['violations']})")
    return [
        f"{v['id']} ({v['impact']}): {v['nodes'][0]['target']} {v['help']}"
        for v in found["violations"]
        if v["impact"] in ("serious", "critical") or v["id"] in ALWAYS
    ]


@pytest.mark.parametrize("scheme", ["light", "dark"])
@pytest.mark.parametrize("size", [WIDE, PHONE], ids=["wide", "phone"])
def test_pages_have_no_serious_accessibility_problem(site, served, size, scheme):
    axe = require_axe()
    browser, base = served
    found = {}
    for name, rel in PAGES.items():
        with open_page(browser, size, site, scheme=scheme) as page:
            page.goto(base + rel)
            found[name] = problems(page, axe)
    with open_page(browser, size, site, scheme=scheme) as page:
        page.goto(base + "index.html")
        page.fill(".search-box input", "rover")
        page.wait_for_selector("#search-panel mark")
        found["search"] = problems(page, axe)
    assert not any(found.values()), found
