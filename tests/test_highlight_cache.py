"""Highlighted code blocks are kept by content: the same HTML as Pygments gives, and an edit
to a page's prose converts it again without lexing its unchanged code (issue 16)."""

from __future__ import annotations

import sqlite3
from collections import OrderedDict
from pathlib import Path

import pygments
import pytest
from pygments.formatters import HtmlFormatter
from pygments.lexers import get_lexer_by_name
from sitegen_helpers import run_build, snapshot, write_tree

from sitegen.highlight_cache import BLOCKS, HighlightCache, LazyLexer
from sitegen.markdown_render import cached_lexer

CODE = {
    "python": "import sim as vrep\nfor i in range(3):\n    print(i, '<b>&')\n",
    "c": "int main(void) { return 0; }\n",
    "text": "plain <text> & more\n",
}


@pytest.mark.parametrize("lang", sorted(CODE))
def test_a_cached_block_is_what_pygments_gives(lang):
    cache = HighlightCache()
    formatter = HtmlFormatter(cssclass="highlight", wrapcode=True)
    lexer = cached_lexer(lang)
    assert isinstance(lexer, LazyLexer)
    want = pygments.highlight(CODE[lang], get_lexer_by_name(lang), formatter)
    assert cache.highlight(CODE[lang], lexer, formatter) == want  # made
    assert cache.highlight(CODE[lang], lexer, formatter) == want  # from memory
    stored = cache.take_new()
    assert list(stored.values()) == [want]
    later = HighlightCache()
    later.lookup = stored.get
    assert later.highlight(CODE[lang], lexer, formatter) == want  # from the "store"
    assert later.take_new() == {}  # nothing highlighted again


def test_options_and_text_are_part_of_the_key():
    cache = HighlightCache()
    plain = HtmlFormatter(cssclass="highlight")
    numbered = HtmlFormatter(cssclass="highlight", linenos="inline")
    src = CODE["python"]
    a = cache.highlight(src, cached_lexer("python"), plain)
    b = cache.highlight(src, cached_lexer("python"), numbered)
    c = cache.highlight(src, cached_lexer("python", stripall=True), plain)
    d = cache.highlight(src + "x = 1\n", cached_lexer("python"), plain)
    assert len({a, b, d}) == 3 and "x" in d
    assert len(cache.take_new()) == 4 and c == a  # stripall changes nothing here, key does


PAGES = {
    "index.md": "# Home\n\nprose\n\n```python\nprint('home')\n```\n",
    "a.md": "# A\n\nfirst words\n\n```python\nfor i in range(2):\n    print(i)\n```\n",
}


def _blocks(cache: Path) -> set[str]:
    db = sqlite3.connect(cache / "fragments.sqlite")
    try:
        return {row[0] for row in db.execute("SELECT key FROM highlight")}
    finally:
        db.close()


def test_a_prose_edit_does_not_lex_unchanged_code(tmp_path, monkeypatch):
    src = write_tree(tmp_path / "src", PAGES)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    assert len(_blocks(cache)) == 2

    def no_lexing(self):
        raise AssertionError(f"lexer made for {self.name}")

    monkeypatch.setattr(BLOCKS, "memo", OrderedDict())  # nothing from this process
    monkeypatch.setattr(LazyLexer, "lexer", no_lexing)
    (src / "a.md").write_text(PAGES["a.md"].replace("first", "edited"), encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == 1
    html = (out / "a.html").read_text(encoding="utf-8")
    assert "edited words" in html and '<span class="nb">range</span>' in html


def test_changed_code_is_lexed_and_the_old_block_forgotten(tmp_path):
    src = write_tree(tmp_path / "src", PAGES)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    before = _blocks(cache)
    (src / "a.md").write_text(PAGES["a.md"].replace("range(2)", "range(5)"), encoding="utf-8")
    run_build(src, out, cache_dir=cache)
    after = _blocks(cache)
    assert len(after) == 2 and len(after & before) == 1  # home's block kept, a's replaced
    assert '<span class="mi">5</span>' in (out / "a.html").read_text(encoding="utf-8")
    fresh_out = tmp_path / "fresh"
    run_build(src, fresh_out, cache_dir=tmp_path / "fresh-cache")
    assert snapshot(fresh_out) == snapshot(out)
