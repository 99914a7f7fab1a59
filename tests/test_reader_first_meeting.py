"""What a reader meets in a new site (issue 26), in Chromium: search finds pages whose words are
names of Object.prototype; decks follow light/dark and show that sub-slides lie below; speaker
notes stay off the page; a YouTube frame keeps 16:9; the copy button leaves one-line code
readable; the table of contents marks the section jumped to; the two pagers are told apart; a
deep 404 asks nothing of the missing folder."""

from __future__ import annotations

import contextlib
import functools
import threading
from collections.abc import Iterator
from http.server import SimpleHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest
from browser_kit import PHONE, WIDE, chromium, open_page, require_browser, static_server
from reader_site import WORDS, build_reader_site


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    return build_reader_site(tmp_path_factory.mktemp("reader") / "course") / "site"


@pytest.fixture(scope="module")
def browser():
    require_browser()
    with chromium() as b:
        yield b


def test_search_finds_words_that_name_object_prototype(site, browser):
    with static_server(site) as base, open_page(browser, WIDE, site) as page:
        page.goto(base + "search.html?q=constructor")
        for i, word in enumerate(WORDS):
            page.fill("#search-input", word)
            titles = page.locator("#search-results .sr-title").all_inner_texts()
            assert any(f"Word {i}" in t for t in titles), (word, titles)
            # the heading named after the word is the section the hit falls under
            hits = page.locator("#search-results .sr-hit").all_inner_texts()
            assert any(h.startswith(word) for h in hits), (word, hits)
        found = page.evaluate("window.sitegenSearch('constructor').length")
        assert found == 1


def _luminance(rgb: str) -> float:
    r, g, b = (int(x) / 255 for x in rgb[rgb.index("(") + 1 : rgb.index(")")].split(",")[:3])
    lin = [c / 12.92 if c <= 0.03928 else ((c + 0.055) / 1.055) ** 2.4 for c in (r, g, b)]
    return 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2]


def contrast(fg: str, bg: str) -> float:
    a, b = sorted((_luminance(fg), _luminance(bg)), reverse=True)
    return (a + 0.05) / (b + 0.05)


@pytest.mark.parametrize("scheme", ["light", "dark"])
def test_search_highlights_are_readable(site, browser, scheme):
    with open_page(browser, PHONE, site, scheme=scheme) as page:
        page.goto(site.as_uri() + "/index.html")
        page.fill(".search-box input", "rover")
        page.wait_for_selector("#search-panel mark")
        colours = page.eval_on_selector_all(
            "#search-panel mark",
            "ms => ms.map(m => [getComputedStyle(m).color, getComputedStyle(m).backgroundColor])",
        )
        assert colours and all(contrast(fg, bg) >= 4.5 for fg, bg in colours), colours


@pytest.mark.parametrize("scheme", ["light", "dark"])
def test_a_deck_follows_light_and_dark_and_shows_sub_slides(site, browser, scheme):
    deck = site.as_uri() + "/slides/w1-report.slides.html"
    with open_page(browser, WIDE, site, scheme=scheme) as page:
        page.goto(deck)
        body = page.evaluate("getComputedStyle(document.body).backgroundColor")
        ink = page.evaluate("getComputedStyle(document.body).color")
        assert (_luminance(body) < 0.1) == (scheme == "dark"), body
        assert contrast(ink, body) >= 7
        page.keyboard.press("ArrowRight")  # the code slide, with two sub-slides below it
        spans = page.eval_on_selector_all(
            ".slide.current pre span",
            "ss => ss.filter(s => s.textContent.trim()).map(s => getComputedStyle(s).color)",
        )
        back = page.evaluate(
            "getComputedStyle(document.querySelector('.slide.current pre')).backgroundColor"
        )
        assert spans and all(contrast(c, back) >= 3 for c in spans), (spans, back)
        down = page.locator(".deck-down")
        assert down.is_visible() and "2" in down.inner_text()
        down.click()
        assert "Below: the result" in page.locator(".slide.current h2").inner_text()
        page.keyboard.press("ArrowRight")
        assert not down.is_visible()  # the last stack has nothing below
        # the site's toggle choice holds for decks too (and the deck's own toggle sets it)
        page.locator(".deck-theme").click()
        flipped = page.evaluate("getComputedStyle(document.body).backgroundColor")
        assert (_luminance(flipped) < 0.1) != (scheme == "dark")
        page.goto(site.as_uri() + "/index.html")
        chosen = page.evaluate("document.documentElement.getAttribute('data-theme')")
        assert chosen == ("light" if scheme == "dark" else "dark")


def test_speaker_notes_stay_off_the_page_and_in_the_deck(site, browser):
    with open_page(browser, WIDE, site) as page:
        page.goto(site.as_uri() + "/slides/w1-report.html")
        assert "Say who is in the group" not in page.locator("main").inner_text()
        assert page.locator(".body").inner_text().count("Below:") == 2
        page.goto(site.as_uri() + "/slides/w1-report.slides.html?notes")
        assert "Say who is in the group" in page.locator("#notes-panel").inner_text()


@pytest.mark.parametrize("size", [WIDE, PHONE], ids=["wide", "phone"])
def test_a_youtube_frame_keeps_its_shape(site, browser, size):
    with open_page(browser, size, site) as page:
        page.route("https://www.youtube.com/**", lambda r: r.fulfill(body="", status=204))
        page.goto(site.as_uri() + "/stage-1/a-video.html")
        box = page.locator(".body iframe").bounding_box()
        assert box["width"] >= min(300, size["width"] - 60)
        assert abs(box["height"] - box["width"] * 9 / 16) < 2, box


def test_the_copy_button_leaves_one_line_code_readable(site, browser):
    with open_page(browser, PHONE, site) as page:
        page.goto(site.as_uri() + "/stage-1/w1/index.html")
        room = page.eval_on_selector_all(
            ".body .highlight",
            """bs => bs.map(b => {
                const pre = b.querySelector('.code pre') || b.querySelector('pre');
                const copy = b.querySelector('.copy');
                const right = pre.getBoundingClientRect().right
                    - parseFloat(getComputedStyle(pre).paddingRight);
                return copy.getBoundingClientRect().left - right;
            })""",
        )
        assert room and min(room) >= 0, room


@pytest.mark.parametrize("size", [WIDE, PHONE], ids=["wide", "phone"])
def test_the_table_of_contents_marks_the_section_jumped_to(site, browser, size):
    with open_page(browser, size, site) as page:
        page.goto(site.as_uri() + "/stage-1/long-page.html")
        links = page.locator(".toc a")
        for i in range(links.count()):
            links.nth(i).click()
            page.wait_for_timeout(150)
            active = page.eval_on_selector_all(
                ".toc a", "as => as.findIndex(a => a.classList.contains('active'))"
            )
            assert active == i, (i, active)


def test_the_two_pagers_are_told_apart(site):
    html = (site / "stage-1/long-page.html").read_text(encoding="utf-8")
    labels = [part.split('"', 2)[1] for part in html.split('<nav class="pager" aria-label=')[1:]]
    assert len(labels) == 2 and labels[0] != labels[1], labels


class _Pages(SimpleHTTPRequestHandler):
    """GitHub Pages: a missing path gets 404.html, whatever its depth."""

    def log_message(self, *args) -> None:
        pass

    def send_error(self, code, message=None, explain=None):
        if code != 404:
            return super().send_error(code, message, explain)
        body = (Path(self.directory) / "404.html").read_bytes()
        self.send_response(404)
        self.send_header("Content-Type", "text/html; charset=utf-8")
        self.send_header("Content-Length", str(len(body)))
        self.end_headers()
        self.wfile.write(body)


@contextlib.contextmanager
def pages_server(folder: Path) -> Iterator[str]:
    server = ThreadingHTTPServer(("127.0.0.1", 0), functools.partial(_Pages, directory=folder))
    threading.Thread(target=server.serve_forever, daemon=True).start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}/"
    finally:
        server.shutdown()
        server.server_close()


def test_a_deep_404_loads_its_files_from_the_site_root(site, browser):
    with pages_server(site) as base, open_page(browser, WIDE, site) as page:
        asked: list[str] = []
        page.on("request", lambda r: asked.append(r.url))
        response = page.goto(base + "a/b/c/missing.html")
        assert response.status == 404
        page.wait_for_load_state("networkidle")
        page.watch.errors.clear()  # the 404 response itself is logged as a failed load
        assert not [u for u in asked if "/a/b/" in u and u != base + "a/b/c/missing.html"]
        assert page.evaluate("getComputedStyle(document.body).display") == "flex"  # styled
        page.locator(".theme-toggle").wait_for(state="visible")  # site.js ran
