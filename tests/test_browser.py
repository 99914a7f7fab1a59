"""The built course site in a real browser: Debian's Chromium driven by Playwright.

The repo's own site is built once (clips come from the build cache after the first run) and
served on 127.0.0.1. Any request that leaves 127.0.0.1 is blocked and counted as a failure.
Under CI these tests fail, never skip, when Chromium or Playwright is missing.
"""

from __future__ import annotations

import re
from urllib.parse import unquote

import pytest
from browser_kit import Watch, chromium, require_browser, static_server
from sitegen_helpers import REPO, run_build

ARTIFACTS = REPO / "test-artifacts"


@pytest.fixture(scope="module")
def repo_site(tmp_path_factory):
    require_browser()
    out = tmp_path_factory.mktemp("browser") / "site"
    run_build(REPO, out)
    return out


@pytest.fixture(scope="module")
def site_url(repo_site):
    with static_server(repo_site) as url:
        yield url


@pytest.fixture(scope="module")
def browser(site_url):
    with chromium() as b:
        yield b


@pytest.fixture()
def page(browser):
    context = browser.new_context(viewport={"width": 1280, "height": 900})
    pg = context.new_page()
    watch = Watch(pg)
    pg.watch = watch
    yield pg
    assert watch.outside == [], f"requests left 127.0.0.1: {watch.outside}"
    assert watch.errors == [], f"console errors: {watch.errors}"
    context.close()


def shot(page, name: str) -> None:
    ARTIFACTS.mkdir(exist_ok=True)
    page.screenshot(path=str(ARTIFACTS / f"{name}.png"), full_page=False)


def test_menu_navigation_to_a_week_page_and_prev_next(page, site_url):
    page.goto(site_url + "index.html")
    page.locator("#nav a", has_text=re.compile(r"^Stage 1")).first.click()
    page.locator("#nav a", has_text=re.compile(r"^W1\b")).first.click()
    assert re.search(r"/stage-1/w1/index\.html$", page.url)
    title = page.locator("main > h1").inner_text()
    assert title.startswith("W1")
    shot(page, "week-page")
    page.locator(".pager a.next").first.click()
    next_title = page.locator("main > h1").inner_text()
    assert next_title != title
    page.locator(".pager a.prev").first.click()
    assert page.locator("main > h1").inner_text() == title


def test_site_map_lists_every_page(page, site_url):
    page.goto(site_url + "index.html")
    page.locator(".topbar a.sitemap-link").click()
    links = page.locator(".sitemap a")
    assert links.count() > 40
    hrefs = {links.nth(i).get_attribute("href") for i in range(links.count())}
    assert any("w12" in h for h in hrefs)


def test_search_finds_chinese_word_in_running_text(page, site_url):
    page.goto(site_url + "index.html")
    page.fill(".topbar input[name=q]", "齒輪")
    page.press(".topbar input[name=q]", "Enter")
    page.wait_for_selector("#search-results .sr-page")
    results = page.locator("#search-results a.sr-title")
    assert results.count() >= 1
    first = results.first.get_attribute("href")
    shot(page, "search")
    results.first.click()
    assert "齒輪" in page.locator("article").inner_text(), first


def test_roster_page_shows_every_group_and_anchors_work(page, site_url):
    page.goto(site_url + "sitemap.html")
    page.locator(".sitemap a", has_text="分組名單").first.click()
    groups = page.locator("section.roster-group")
    assert groups.count() == 6
    page.locator(".toc a", has_text="stage3-ag4").click()
    assert page.url.endswith("#group-stage3-ag4")
    box = page.locator("#group-stage3-ag4").bounding_box()
    assert box is not None and 0 <= box["y"] < 400  # scrolled to the group
    shot(page, "roster")


def _pages_with_clips(page, site_url) -> list[str]:
    page.goto(site_url + "sitemap.html")
    hrefs = [a.get_attribute("href") for a in page.locator(".sitemap a").all()]
    return hrefs


def test_every_embedded_clip_plays(page, site_url):
    hrefs = _pages_with_clips(page, site_url)
    played = 0
    for href in hrefs:
        page.goto(site_url + href)
        replays = page.locator("figure.clip-replay")  # this site's clips are replays
        for i in range(replays.count()):
            handle = replays.nth(i)
            handle.scroll_into_view_if_needed()
            page.wait_for_function(
                "f => f.dataset.state === 'ready' && f.sitegenReplay.frames > 1",
                arg=handle.element_handle(),
                timeout=20000,
            )
            played += 1
    assert played >= 10  # W7, W8, W11, W12 embeds plus the gallery
    shot(page, "clip")


def test_phone_viewport_never_scrolls_sideways(browser, site_url):
    context = browser.new_context(
        viewport={"width": 375, "height": 740}, is_mobile=True, has_touch=True
    )
    pg = context.new_page()
    Watch(pg)
    pg.goto(site_url + "sitemap.html")
    hrefs = [a.get_attribute("href") for a in pg.locator(".sitemap a").all()]
    for href in hrefs[:: max(1, len(hrefs) // 15)] + ["search.html?q=齒輪", "gallery/index.html"]:
        pg.goto(site_url + href)
        wide = pg.evaluate(
            "document.documentElement.scrollWidth - document.documentElement.clientWidth"
        )
        assert wide <= 0, f"{href} scrolls sideways by {wide}px"
    pg.goto(site_url + "index.html")
    pg.locator(".menu-toggle").click()
    assert pg.locator("#nav").is_visible()
    shot(pg, "phone")
    context.close()


@pytest.mark.parametrize("size", ["wide", "phone"])
def test_gallery_from_file_has_no_gap_above_the_first_clip_and_plays(browser, repo_site, size):
    """Opened from disk: the gallery's contents box no longer pushes the first clip down."""
    from browser_kit import SIZES, open_page

    with open_page(browser, SIZES[size], repo_site) as pg:
        pg.goto((repo_site / "gallery/index.html").as_uri())
        heading = pg.locator(".gallery-item h2").first.bounding_box()
        replay = pg.locator(".gallery-item figure.clip-replay").first
        box = replay.locator(".replay-stage").bounding_box()
        assert box["y"] - (heading["y"] + heading["height"]) < 48, (heading, box)
        pg.wait_for_function(
            "f => f.dataset.state === 'ready' && f.sitegenReplay.frames > 1",
            arg=replay.element_handle(),
            timeout=20000,
        )
        wide = pg.evaluate("document.documentElement.scrollWidth - innerWidth")
        assert wide <= 0


@pytest.mark.parametrize("size", ["wide", "phone"])
def test_week_page_with_a_clip_from_file(browser, repo_site, size):
    from browser_kit import SIZES, open_page

    with open_page(browser, SIZES[size], repo_site) as pg:
        pg.goto((repo_site / "index.html").as_uri())
        assert pg.locator("#nav li.current").count() == 1
        pg.goto((repo_site / "sitemap.html").as_uri())
        hrefs = [a.get_attribute("href") for a in pg.locator(".sitemap a").all()]
        with_clip = 0
        for href in (h for h in hrefs if h.startswith("stage-2/w7/")):
            pg.goto((repo_site / unquote(href)).as_uri())
            with_clip += pg.locator("figure.clip-replay .replay-stage").count()
            assert pg.locator('#nav [aria-current="page"]').count() == 1
        assert with_clip >= 1


def test_roster_page_speaks_the_site_language(page, site_url):
    page.goto(site_url + "sitemap.html")
    page.locator(".sitemap a", has_text="分組名單").first.click()
    summary = page.locator(".roster-summary").inner_text()
    assert re.fullmatch(r"\d+ 組, \d+ 位組員", summary), summary
    assert page.locator(".roster-leader").first.inner_text() == "(組長)"
    assert "倉儲" in page.locator(".roster-group-links").first.inner_text()
    assert "members" not in page.locator("main").inner_text()
