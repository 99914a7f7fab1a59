"""The reader's side of the theme in Chromium: every item at 1280×800 and 390×844, over http and
from file://, with the keyboard where a reader would use it.

A small course site is built once (no clips, so it is quick); the repository's own site, with
its gallery and clips, is covered by tests/test_browser.py.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from browser_kit import PHONE, SIZES, WIDE, chromium, open_page, require_browser, static_server
from sitegen_helpers import run_build, write_tree

LONG = "\n\n".join(f"## 段落 {i}\n\n" + "這一段是用來捲動的文字. " * 40 for i in range(1, 7))
SITE = {
    "sitegen.yml": "title: 測試課程\nlanguage: zh-TW\nbase_url: https://example.github.io/course/\n",
    "content/index.md": "# 首頁\n\n歡迎.\n",
    "content/stage-1/index.md": "---\ntitle: Stage 1\n---\n\n第一階段.\n",
    "content/stage-1/w1/index.md": "# W1 開始\n\n"
    + "```python\nclientID = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)  "
    + "# "
    + "a long comment that must scroll inside the block " * 3
    + "\n```\n\n"
    + '```{.python linenums="1"}\nfor i in range(3):\n    print(i)\n```\n\n'
    + "| 物件 | 名稱 | 說明 |\n|---|---|---|\n"
    + "| 馬達 | `ShoulderMotor` | 肩關節的旋轉馬達, 用 sim.simxSetJointTargetVelocity 控制速度 |\n"
    + "| 感測器 | `Proximity_sensor_front` | 前方距離感測器, 回傳偵測到的點 |\n\n"
    + '!!! note "注意"\n    這是 note.\n\n!!! warning\n    小心.\n\n!!! tip\n    技巧.\n\n'
    + '=== "Windows"\n    在 Windows 執行 `py main.py`.\n\n'
    + '=== "macOS"\n    在 macOS 執行 `python3 main.py`.\n\n'
    + '=== "Linux"\n    在 Linux 執行 `python3 main.py`.\n\n'
    + LONG
    + "\n",
    "content/stage-1/w1/more.md": "# W1 補充\n\n補充說明.\n",
    "content/stage-2/index.md": "---\ntitle: Stage 2\n---\n\n第二階段.\n",
    "content/stage-2/w5/index.md": "# W5 齒輪\n\n本週頁面.\n",
    "content/stage-2/w5/gears.md": (
        "---\nslug: gears\n---\n# 錯誤排解\n\n開頭.\n\n"
        "## 齒輪比\n\n主動輪與從動輪的齒輪比決定轉速.\n"
    ),
}
W1 = "stage-1/w1/index.html"


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    require_browser()
    root = tmp_path_factory.mktemp("reader")
    src = write_tree(root / "src", SITE)
    out = root / "site"
    run_build(src, out, strict=True)
    return out


@pytest.fixture(scope="module")
def http(site):
    with static_server(site) as base:
        yield base


@pytest.fixture(scope="module")
def browser(site):
    with chromium() as b:
        yield b


@pytest.fixture(params=["http", "file"])
def where(request, site, http):
    """A function: site-relative path -> URL, over http or from file://."""
    if request.param == "http":
        return lambda rel: http + rel
    return lambda rel: (
        (site / rel.split("#")[0]).as_uri() + ("#" + rel.split("#")[1] if "#" in rel else "")
    )


@pytest.fixture(params=list(SIZES))
def size(request) -> dict:
    return SIZES[request.param]


def _no_sideways(page) -> None:
    wide = page.evaluate("document.documentElement.scrollWidth - innerWidth")
    assert wide <= 0, f"page scrolls sideways by {wide}px"


def test_sidebar_and_toc_stay_and_mark_the_heading_being_read(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where(W1))
        assert page.locator(".toc a.active").inner_text() == "段落 1"
        page.evaluate("document.getElementById('段落-4').scrollIntoView()")
        page.wait_for_function("document.querySelector('.toc a.active').textContent === '段落 4'")
        page.evaluate("scrollBy(0, -200)")  # back up into 段落 3
        page.wait_for_function("document.querySelector('.toc a.active').textContent === '段落 3'")
        if size is WIDE:  # both boxes still on screen after scrolling a long page
            for sel in ("#nav", ".toc"):
                box = page.locator(sel).bounding_box()
                assert box and 0 <= box["y"] < 120, (sel, box)
            assert page.locator("#nav li.current > a").is_visible()
        else:  # the phone menu is a drawer, closed until asked for
            assert not page.locator("#nav").is_visible()
        _no_sideways(page)


def test_menu_sections_fold_in_place_with_the_keyboard(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where(W1))
        if size is PHONE:
            page.locator(".menu-toggle").click()
            assert page.locator("#nav").is_visible()
        stage2 = page.locator("#nav li", has=page.locator("a", has_text="Stage 2")).first
        fold = stage2.locator(":scope > button.fold")
        assert fold.get_attribute("aria-expanded") == "false"
        fold.focus()
        page.keyboard.press("Enter")  # expands in place: no navigation
        w5 = stage2.locator("a", has_text="W5 齒輪")
        w5.wait_for()
        assert (
            page.url.endswith(W1.split("/")[-1]) and fold.get_attribute("aria-expanded") == "true"
        )
        inner = stage2.locator("li", has=page.locator("a", has_text="W5 齒輪"))
        inner = inner.locator(":scope > button.fold")
        inner.click()
        stage2.locator("a", has_text="錯誤排解").wait_for()
        fold.press("Space")  # collapse again
        assert fold.get_attribute("aria-expanded") == "false" and not w5.is_visible()
        # the current branch starts open and folds too
        stage1 = page.locator("#nav li.open", has=page.locator("a", has_text="Stage 1")).first
        own = stage1.locator(":scope > button.fold")
        assert own.get_attribute("aria-expanded") == "true"
        own.click()
        assert not page.locator("#nav li.current").is_visible()
        # current page only: the week page is marked, nothing else
        assert page.locator('#nav [aria-current="page"]').count() == 1


def test_phone_menu_says_how_to_close_and_closes(browser, site, where):
    with open_page(browser, PHONE, site) as page:
        page.goto(where(W1))
        toggle = page.locator(".menu-toggle")
        toggle.click()
        hint = page.locator(".menu-close")
        assert hint.is_visible() and "Esc" in hint.inner_text() and "關閉選單" in hint.inner_text()
        assert page.evaluate("document.activeElement.closest('#nav') !== null")  # focus moved in
        page.keyboard.press("Escape")
        page.wait_for_function("!document.getElementById('nav').classList.contains('shown')")
        assert toggle.get_attribute("aria-expanded") == "false"
        assert page.evaluate("document.activeElement.classList.contains('menu-toggle')")
        toggle.click()
        hint.locator("button").click()
        assert toggle.get_attribute("aria-expanded") == "false"
        toggle.click()
        page.mouse.click(380, 600)  # a tap beside the drawer
        assert toggle.get_attribute("aria-expanded") == "false"


def test_search_as_you_type_with_the_keyboard(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where("index.html"))
        page.keyboard.press("/")
        box = page.locator(".search-box input")
        assert page.evaluate("document.activeElement.name") == "q"
        page.keyboard.type("齒輪")
        panel = page.locator("#search-panel")
        panel.locator("a").first.wait_for()
        groups = panel.locator(".sr-page")
        gears = groups.filter(has_text="錯誤排解").first
        assert gears.locator("a.sr-title").inner_text().startswith("錯誤排解")
        assert gears.locator("a.sr-hit", has_text="齒輪比").count() == 1  # the matching heading
        assert "W5" in gears.inner_text()  # where the page is
        box.press("ArrowDown")
        first = panel.locator('a[aria-selected="true"]')
        assert first.count() == 1 and box.get_attribute(
            "aria-activedescendant"
        ) == first.get_attribute("id")
        target = None
        for _ in range(panel.locator("a").count()):
            if "齒輪比" in panel.locator('a[aria-selected="true"]').inner_text():
                target = panel.locator('a[aria-selected="true"]').get_attribute("href")
                break
            box.press("ArrowDown")
        assert target and target.endswith("#" + "%E9%BD%92%E8%BC%AA%E6%AF%94")
        box.press("Enter")
        page.wait_for_url(re.compile(r"gears\.html#"))
        box = page.locator(".search-box input")
        box.fill("齒輪")
        panel.locator("a").first.wait_for()
        box.press("Escape")
        assert panel.is_hidden()


def test_search_page_is_the_fallback_without_javascript(browser, site, where):
    with open_page(browser, WIDE, site, js=False) as page:
        page.goto(where("index.html"))
        page.locator(".search-box input").fill("齒輪")
        page.locator(".search-box input").press("Enter")
        page.wait_for_url(re.compile(r"search\.html\?q="))
        assert "JavaScript" in page.locator("main").inner_text()
    with open_page(browser, WIDE, site) as page:  # the same address with JavaScript: results
        page.goto(where("search.html") + "?q=" + "齒輪")
        hit = page.locator("#search-results a.sr-hit", has_text="齒輪比")
        hit.wait_for()
        assert page.locator("#search-results .sr-page").count() == 2  # W5 and 錯誤排解


def test_copy_button_copies_the_code_with_the_keyboard(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where(W1))
        buttons = page.locator(".body .copy")
        assert buttons.count() == 2
        numbered = buttons.nth(1)
        numbered.focus()
        page.keyboard.press("Enter")
        page.wait_for_function(
            "document.querySelectorAll('.body .copy')[1].textContent === '已複製'"
        )
        text = page.evaluate("navigator.clipboard.readText()")
        assert text == "for i in range(3):\n    print(i)"  # the code, not the line numbers


def test_line_numbers_are_per_block_and_long_lines_scroll_inside(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where(W1))
        blocks = page.locator(".body div.highlight")
        assert blocks.nth(0).locator(".linenos").count() == 0
        assert blocks.nth(1).locator(".linenos").inner_text().split() == ["1", "2"]
        pre = blocks.nth(0).locator("pre")
        widths = pre.evaluate("p => [p.scrollWidth, p.clientWidth]")
        assert widths[0] > widths[1]  # the long line scrolls inside its block
        _no_sideways(page)


def test_tables_scroll_sideways_instead_of_breaking_identifiers(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where(W1))
        code = page.locator(".body table code", has_text="ShoulderMotor")
        line = code.evaluate("c => parseFloat(getComputedStyle(c).lineHeight) || 20")
        assert code.bounding_box()["height"] < 1.6 * line  # one line: not ShoulderMot/or
        if size is PHONE:
            table = page.locator(".body table:not(.highlighttable)")
            assert table.evaluate("t => t.scrollWidth > t.clientWidth")
        _no_sideways(page)


def test_light_dark_toggle_overrides_the_system_and_is_remembered(browser, site, where, size):
    with open_page(browser, size, site, scheme="dark") as page:
        page.goto(where(W1))
        bg = "getComputedStyle(document.body).backgroundColor"
        assert page.evaluate(bg) == "rgb(13, 17, 23)"  # the system's dark
        page.locator(".theme-toggle").click()
        assert page.evaluate(bg) == "rgb(255, 255, 255)"
        code = "getComputedStyle(document.querySelector('.highlight .k')).color"
        light_keyword = page.evaluate(code)
        page.goto(where("stage-2/w5/gears.html"))
        assert page.evaluate(bg) == "rgb(255, 255, 255)"  # remembered on the next page
        page.goto(where(W1))
        assert page.evaluate(code) == light_keyword  # code colours follow the choice too
        page.locator(".theme-toggle").click()
        assert page.evaluate(bg) == "rgb(13, 17, 23)"
        assert page.evaluate(code) != light_keyword


@pytest.mark.parametrize("scheme", ["light", "dark"])
def test_admonitions_and_tabs(browser, site, where, scheme):
    with open_page(browser, WIDE, site, scheme=scheme) as page:
        page.goto(where(W1))
        colours = page.locator(".admonition").evaluate_all(
            "els => els.map(e => getComputedStyle(e).borderLeftColor)"
        )
        assert len(colours) == 3 and len(set(colours)) == 3  # note, warning, tip differ
        assert page.locator(".admonition.note .admonition-title").inner_text() == "注意"
        tabs = page.locator(".tabbed-set label")
        assert tabs.all_inner_texts() == ["Windows", "macOS", "Linux"]
        blocks = page.locator(".tabbed-content")
        assert blocks.nth(0).is_visible() and not blocks.nth(1).is_visible()
        tabs.nth(1).click()
        assert blocks.nth(1).is_visible() and not blocks.nth(0).is_visible()
        page.keyboard.press("ArrowRight")  # the focused tab's radio: arrows move between tabs
        assert blocks.nth(2).is_visible() and "python3 main.py" in blocks.nth(2).inner_text()


def test_404_page_works_offline_and_marks_nothing_current(browser, site, where, size):
    with open_page(browser, size, site) as page:
        page.goto(where("404.html"))
        assert page.evaluate("getComputedStyle(document.body).display") == "flex"  # CSS loaded
        assert page.locator("main h1").inner_text() == "找不到頁面"
        page.locator("main a", has_text="網站地圖").click()
        page.wait_for_url(re.compile(r"sitemap\.html"))
        for rel in ("404.html", "search.html", "sitemap.html"):
            page.goto(where(rel))
            assert page.locator("#nav .current, #nav [aria-current]").count() == 0, rel


def test_missing_page_over_http_gets_the_styled_404_and_no_favicon_error(browser, site, http):
    responses = []
    with open_page(browser, WIDE, site) as page:
        page.on("response", lambda r: responses.append((r.status, r.url)))
        page.goto(http + W1)
        page.goto(http + "index.html")
        assert [r for r in responses if r[0] >= 400] == []
        icon = page.evaluate("document.querySelector('link[rel=icon]').href")
        assert page.request.get(icon).status == 200


def test_generated_and_special_pages_speak_the_site_language(browser, site, where):
    with open_page(browser, WIDE, site) as page:
        page.goto(where(W1))
        assert page.locator(".menu-toggle").get_attribute("data-close") == "關閉選單"
        assert page.locator(".body .copy").first.inner_text() == "複製"
        assert page.locator(".toc h2").inner_text() == "本頁內容"
