"""Slide decks (sitegen/slides.py): separators, notes, the deck file beside the page, and the
viewer driven by keys in Chromium over http and from file://."""

from __future__ import annotations

import re
import struct
import zlib
from pathlib import Path

import pytest
from sitegen_helpers import hrefs, run_build, write_tree

from sitegen.errors import BuildError
from sitegen.slides import mark_separators, split_deck


def _png() -> bytes:
    def chunk(kind: bytes, data: bytes) -> bytes:
        return (
            struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
        )

    ihdr = struct.pack(">IIBBBBB", 2, 2, 8, 2, 0, 0, 0)
    raw = zlib.compress(b"\x00" + b"\xff\x00\x00" * 2 + b"\x00" + b"\x00\x00\xff" * 2)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr) + chunk(b"IDAT", raw) + chunk(b"IEND", b"")


DECK = """---
slides: true
---
# 第三週報告

組員：甲、乙

---

## 程式

```python
print("機器人")
---
```

Note: 先說明程式的**目的**。
再展示結果。

--

## 圖片

![紅點](images/dot.png)

---

## 謝謝 & <再見>
"""


def make_site(root: Path) -> Path:
    return write_tree(
        root,
        {
            "sitegen.yml": "title: Deck test\nlanguage: zh-TW\n",
            "content/index.md": "# Home\n\nSee [the report](w3/report.md).\n",
            "content/w3/report.md": DECK,
            "content/w3/images/dot.png": _png(),
            "content/slides/intro.md": "# Intro deck\n\none\n\n---\n\ntwo\n",
            "content/slides/index.md": "# Decks\n\nAll decks.\n",
        },
    )


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    root = make_site(tmp_path_factory.mktemp("deck"))
    out = root / "site"
    run_build(root, out)
    return out


def slides_of(html: str) -> list[str]:
    return re.findall(r'<section class="slide"[^>]*id="([^"]+)"', html)


def test_separators_become_directives_line_for_line_but_not_inside_code():
    text = "a\n---\n```\n---\n--\nNote: x\n```\nb\n--\nNote: say it\nNotes:\n"
    marked = mark_separators(text)
    assert marked.count("\n") == text.count("\n")
    assert marked.split("\n") == [
        "a",
        "::: slide next",
        "```",
        "---",
        "--",
        "Note: x",
        "```",
        "b",
        "::: slide down",
        "::: slide notes say it",
        "::: slide notes",
        "",
    ]


def test_split_deck_keeps_notes_apart_and_puts_the_stripped_title_first():
    body = (
        "<p>one</p><!--slide:next--><hr>"
        '<p>two</p><!--slide:notes--><p class="slide-notes-label">N</p><p>say</p>'
        "<!--slide:down--><hr><p>two-b</p>"
    )
    stacks = split_deck(body, "T <x>")
    assert [[s["html"] for s in st] for st in stacks] == [
        ["<h1>T &lt;x&gt;</h1>\n<p>one</p>"],
        ["<p>two</p>", "<p>two-b</p>"],
    ]
    assert stacks[1][0]["notes"] == "<p>say</p>" and stacks[1][1]["notes"] == ""


def test_deck_file_beside_the_page_with_slides_notes_image_and_links(built):
    page = (built / "w3/第三週報告.html").read_text(encoding="utf-8")
    deck = (built / "w3/第三週報告.slides.html").read_text(encoding="utf-8")
    # the page links to its deck, and the deck back to the page
    assert 'href="%E7%AC%AC%E4%B8%89%E9%80%B1%E5%A0%B1%E5%91%8A.slides.html"' in page
    assert 'class="deck-back" href="%E7%AC%AC%E4%B8%89%E9%80%B1%E5%A0%B1%E5%91%8A.html"' in deck
    assert slides_of(deck) == ["slide-1", "slide-2", "slide-2-2", "slide-3"]
    assert "<h1>第三週報告</h1>" in deck  # the title the page shows in its header
    assert '<span class="nb">print</span>' in deck  # highlighted, and the --- in code kept
    assert '\n<span class="o">---</span>\n</code>' in deck
    notes = re.findall(r'<aside class="notes">(.*?)</aside>', deck, re.S)
    assert len(notes) == 1 and "<strong>目的</strong>" in notes[0] and "再展示結果" in notes[0]
    assert "謝謝 &amp; &lt;再見&gt;" in deck
    # every relative link of the deck exists in the site (image, assets, the page)
    from urllib.parse import unquote

    for href in hrefs(deck):
        if not href.startswith(("?", "#")):
            assert (built / "w3" / unquote(href)).is_file(), href
    assert 'src="images/dot.png"' in deck and (built / "w3/images/dot.png").is_file()
    assert (built / "assets/slides.js").is_file() and (built / "assets/slides.css").is_file()


def test_pages_in_the_slides_folder_are_decks_but_its_index_is_not(built):
    deck = (built / "slides/intro-deck.slides.html").read_text(encoding="utf-8")
    assert slides_of(deck) == ["slide-1", "slide-2"]
    assert not (built / "slides/index.slides.html").exists()


def test_a_broken_link_in_a_deck_is_reported_at_its_own_line(tmp_path):
    root = make_site(tmp_path)
    (root / "content/w3/report.md").write_text(
        DECK.replace("## 謝謝", "[gone](nowhere.md)\n\n## 謝謝"), encoding="utf-8"
    )
    with pytest.raises(BuildError) as err:
        run_build(root, root / "site", strict=True)
    lines = DECK.replace("## 謝謝", "[gone](nowhere.md)\n\n## 謝謝").split("\n")
    want = lines.index("[gone](nowhere.md)") + 1
    found = [d for d in err.value.diagnostics if "nowhere.md" in d.message]
    assert [(d.file, d.line) for d in found] == [("content/w3/report.md", want)]


def test_deck_output_is_deterministic(tmp_path, built):
    root = make_site(tmp_path)
    run_build(root, root / "site")
    name = "w3/第三週報告.slides.html"
    assert (root / "site" / name).read_bytes() == (built / name).read_bytes()


# -- in the browser ------------------------------------------------------------------------


def _current(page) -> str:
    return page.eval_on_selector("section.slide.current", "e => e.id")


@pytest.mark.parametrize("scheme", ["http", "file"])
def test_deck_keys_notes_view_and_print_view_in_chromium(built, scheme):
    from browser_kit import WIDE, chromium, open_page, require_browser, static_server

    require_browser()
    deck = "w3/%E7%AC%AC%E4%B8%89%E9%80%B1%E5%A0%B1%E5%91%8A.slides.html"
    with static_server(built) as base, chromium() as browser:
        url = (base if scheme == "http" else built.resolve().as_uri() + "/") + deck
        with open_page(browser, WIDE, built) as page:
            page.goto(url)
            assert _current(page) == "slide-1"
            assert page.is_visible("text=組員：甲、乙")
            page.keyboard.press("ArrowRight")
            assert _current(page) == "slide-2" and page.is_visible("text=程式")
            assert not page.is_visible("text=組員：甲、乙")
            page.keyboard.press("ArrowDown")
            assert _current(page) == "slide-2-2"
            assert page.eval_on_selector("section.slide.current img", "i => i.naturalWidth") == 2
            page.keyboard.press("ArrowUp")
            page.keyboard.press("s")  # the notes view: the current slide's notes beside it
            assert page.is_visible("#notes-panel") and page.is_visible(
                "#notes-panel >> text=再展示結果"
            )
            assert page.inner_text(".notes-counter") == "2 / 4"
            page.keyboard.press("s")
            assert not page.is_visible("#notes-panel")
            page.keyboard.press("End")
            assert _current(page) == "slide-3"
            page.keyboard.press("ArrowLeft")
            assert _current(page) == "slide-2"
            page.keyboard.press("Home")
            assert _current(page) == "slide-1"
            page.keyboard.press("Space")
            assert _current(page) == "slide-2"
            page.reload()  # the position is in the address
            assert _current(page) == "slide-2"
            page.click(".deck-back")
            page.wait_for_selector("article")
            assert page.url.endswith("%E7%AC%AC%E4%B8%89%E9%80%B1%E5%A0%B1%E5%91%8A.html")
        with open_page(browser, WIDE, built) as page:
            page.goto(url + "?notes#/1")
            assert page.is_visible("#notes-panel >> text=先說明程式的")
        with open_page(browser, WIDE, built) as page:
            page.goto(url + "?print")
            boxes = [page.locator(f"#{i}").bounding_box() for i in slides_of_ids()]
            assert all(b and b["height"] > 100 for b in boxes)  # all shown, one after another
            assert [b["y"] for b in boxes] == sorted(b["y"] for b in boxes)
            page.emulate_media(media="print")
            assert page.eval_on_selector(
                "section.slide", "e => getComputedStyle(e).breakAfter"
            ) in ("page", "always")


def slides_of_ids() -> list[str]:
    return ["slide-1", "slide-2", "slide-2-2", "slide-3"]


def test_deck_swipes_on_a_touch_screen(built):
    from browser_kit import PHONE, chromium, open_page, require_browser

    require_browser()
    url = built.resolve().as_uri() + "/slides/intro-deck.slides.html"
    with chromium() as browser, open_page(browser, PHONE, built) as page:
        page.goto(url)
        assert _current(page) == "slide-1"
        page.evaluate(
            """() => {
            const d = document.querySelector('.deck');
            const t = (x) => [new Touch({identifier: 1, target: d, clientX: x, clientY: 300})];
            d.dispatchEvent(new TouchEvent('touchstart',
                {touches: t(300), changedTouches: t(300)}));
            d.dispatchEvent(new TouchEvent('touchend', {touches: [], changedTouches: t(100)}));
        }"""
        )
        assert _current(page) == "slide-2"
