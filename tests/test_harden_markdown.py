"""Issue 33: raw HTML in Markdown reaches the site as written by default (docs/security.md says
what that means for a site that takes pages from others); ``markdown: {raw_html: strip}``
removes scripts, frames, handlers and ``javascript:`` links and keeps what Markdown writes."""

from __future__ import annotations

import pytest
from sitegen_helpers import run_build, write_tree

from sitegen.config import parse_config
from sitegen.errors import BuildError

HOSTILE = """# Page

<script>alert("page")</script>
<iframe src="https://example.org/frame"></iframe>

<p onclick="alert('click')">text</p>

[a link](javascript:alert('link')) and [another](JaVaScRiPt:alert(2))

[attributes](page.md){onmouseover="alert('attr')" data-replay="https://example.org/x.js"}

<img src="x.png" onerror="alert('img')" alt="pic">

| a | b |
|:--|--:|
| 1 | 2 |

!!! note "Kept"
    Admonitions stay.

=== "One"
    tab one

=== "Two"
    tab two
"""
DECK = """---
slides: true
---
# Deck

First slide

Note: <img src=y onerror="alert('notes')"> said aloud
"""
BAD = ("alert(", "<script>alert", "<iframe", "javascript:", "onclick", "onerror", "onmouseover")


def _site(tmp_path, mode: str | None):
    config = "title: t\n" + (f"markdown:\n  raw_html: {mode}\n" if mode else "")
    src = write_tree(
        tmp_path / "p",
        {"sitegen.yml": config, "content/index.md": HOSTILE, "content/deck.md": DECK},
    )
    run_build(src, tmp_path / "site")
    page = (tmp_path / "site" / "index.html").read_text(encoding="utf-8")
    deck = next((tmp_path / "site").glob("*.slides.html")).read_text(encoding="utf-8")
    return page, deck


def test_raw_html_is_kept_by_default(tmp_path):
    page, deck = _site(tmp_path, None)
    assert '<script>alert("page")</script>' in page and 'href="javascript:' in page
    assert "onerror=\"alert('notes')\"" in deck


def test_raw_html_strip_removes_what_runs_and_keeps_what_markdown_writes(tmp_path):
    page, deck = _site(tmp_path, "strip")
    body = page[page.index("<main") : page.index("</main>")]
    for bad in BAD:
        assert bad not in body, bad
        assert bad not in deck[deck.index("<body") :].replace('<script src="', ""), bad
    assert "data-replay" not in body
    assert "<p>text</p>" in body and 'alt="pic"' in body and 'src="x.png"' in body
    assert '<th style="text-align:left">a</th>' in body  # tables keep their alignment
    assert '<p class="admonition-title">Kept</p>' in body
    assert 'type="radio"' in body and "tab two" in body  # content tabs
    assert '<a href="page.md">attributes</a>' in body  # the link, without its handler
    assert "said aloud" in deck and "<script" not in body


def test_raw_html_takes_only_keep_or_strip(tmp_path):
    with pytest.raises(BuildError) as info:
        parse_config("markdown:\n  raw_html: escape\n", tmp_path)
    assert [(d.line, d.field, d.message) for d in info.value.diagnostics] == [
        (2, "markdown.raw_html", "must be keep or strip")
    ]
    assert parse_config("markdown:\n  raw_html: strip\n", tmp_path).markdown.raw_html == "strip"
