"""No-op and partial builds trust a content file's stat key instead of reading it, and the
other speed shortcuts of issue 16 give exactly what the plain way gives.

A file's stat key (size, modification and change time, inode) is trusted only when the last
build read the file more than ``sitegen.content.RACY_NS`` after it was written; these tests
set that window to zero so that files written a moment ago count as settled.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st
from markdown.extensions import codehilite
from pygments.lexers import get_lexer_by_name
from sitegen_helpers import run_build, settled_build, snapshot, write_tree

import sitegen.content
from sitegen.markdown_render import MarkdownRenderer
from sitegen.search import record_json, record_parts

TREE = {
    "index.md": "# Home\n\n[a](a.md) and [c](sec/c.md)\n",
    "a.md": "# A\n\ntext a\n\n```python\nprint('a')\n```\n",
    "b.md": "# B\n\ntext b\n",
    "sec/index.md": "# Sec\n",
    "sec/c.md": "# C\n\ntext c ![pic](pic.png)\n",
    "sec/pic.png": b"\x89PNG fake image bytes",
}


@pytest.fixture()
def settled(tmp_path: Path, monkeypatch):
    """A built site whose sources the cache trusts by stat, and a counter of file reads."""
    src, out, cache = settled_build(tmp_path, monkeypatch, TREE)
    reads: list[str] = []
    real = sitegen.content._read_file

    def counting(path, rel, *a, **k):
        reads.append(str(rel))
        return real(path, rel, *a, **k)

    monkeypatch.setattr(sitegen.content, "_read_file", counting)
    return src, out, cache, reads


def test_noop_build_reads_no_content_file(settled):
    src, out, cache, reads = settled
    before = snapshot(out)
    report = run_build(src, out, cache_dir=cache)
    assert report.up_to_date
    assert reads == []
    assert snapshot(out) == before


def test_one_page_edit_reads_only_that_file_and_equals_a_cold_build(settled, tmp_path):
    src, out, cache, reads = settled
    (src / "b.md").write_text("# B\n\ntext b, edited\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert reads == ["b.md"]
    assert report.markdown_rendered == 1 and report.pages_rendered == 1
    cold = run_build(src, tmp_path / "cold", cache_dir=tmp_path / "cold-cache")
    assert cold.markdown_rendered == 5
    assert snapshot(out) == snapshot(tmp_path / "cold")


def test_an_edit_keeping_size_and_mtime_is_still_seen(settled):
    """The change time moves with every write, and no tool can set it back."""
    src, out, cache, reads = settled
    page = src / "b.md"
    old = page.stat()
    page.write_text("# B\n\ntext B\n", encoding="utf-8")  # same size
    os.utime(page, ns=(old.st_atime_ns, old.st_mtime_ns))
    assert page.stat().st_size == old.st_size and page.stat().st_mtime_ns == old.st_mtime_ns
    report = run_build(src, out, cache_dir=cache)
    assert not report.up_to_date and reads == ["b.md"]
    assert "text B" in (out / "b.html").read_text(encoding="utf-8")


def test_a_new_or_removed_file_is_seen_without_any_edit(settled):
    src, out, cache, _reads = settled
    (src / "sec/new.md").write_text("# New\n", encoding="utf-8")
    assert run_build(src, out, cache_dir=cache).pages == 6
    assert (out / "sec/new.html").is_file()
    (src / "sec/new.md").unlink()
    assert run_build(src, out, cache_dir=cache).pages == 5
    assert not (out / "sec/new.html").exists()


def test_a_racy_new_file_is_read_again_next_time(tmp_path, monkeypatch):
    """Written within the window before the scan: its key is not recorded, so the next build
    reads it (a second write in the same timestamp tick could leave the key unchanged)."""
    monkeypatch.setattr(sitegen.content, "RACY_NS", 3600 * 10**9)
    src = write_tree(tmp_path / "src", TREE)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    reads: list[str] = []
    real = sitegen.content._read_file
    monkeypatch.setattr(
        sitegen.content, "_read_file", lambda p, rel, *a: reads.append(str(rel)) or real(p, rel, *a)
    )
    assert run_build(src, out, cache_dir=cache).up_to_date
    assert sorted(reads) == sorted(rel for rel in TREE)


def test_a_moved_content_folder_copies_assets_from_where_they_are_now(settled, tmp_path):
    src, out, cache, _reads = settled
    moved = tmp_path / "elsewhere" / "src"  # same name: pages show nothing of the path
    moved.parent.mkdir()
    src.rename(moved)  # the files keep their stat keys; their path is new
    before = snapshot(out)
    shutil.rmtree(out)
    run_build(moved, out, cache_dir=cache)
    assert snapshot(out) == before


@given(
    title=st.text(max_size=20),
    url=st.text(max_size=20),
    path=st.lists(st.text(max_size=8), max_size=3),
    text=st.text(max_size=7000),
    heads=st.lists(st.tuples(st.text(max_size=6), st.text(max_size=6)), max_size=3),
)
def test_search_record_is_the_json_of_the_whole_record(title, url, path, text, heads):
    """The record assembled from cached parts is byte for byte ``json.dumps`` of it whole."""
    toc = [{"id": i, "title": t, "children": [{"id": t, "title": i}]} for i, t in heads]
    record = {
        "t": title,
        "u": url,
        "p": " › ".join(path),
        "x": text[:6000],
        "h": [x for i, t in heads for x in ([i, t], [t, i])],
    }
    whole = json.dumps(record, ensure_ascii=False, separators=(",", ":"), sort_keys=True)
    assert record_json(title, url, path, record_parts(text, toc)) == whole


def test_one_lexer_per_language_gives_what_a_new_lexer_gives(monkeypatch):
    doc = (
        "```python\nprint('x')\n```\n\n```python\nx = [1, 2]\n```\n\n"
        "```nosuchlanguage\nkept <as> text\n```\n\n```c\nint x;\n```\n"
    )
    cached = MarkdownRenderer().render(doc).html
    monkeypatch.setattr(codehilite, "get_lexer_by_name", get_lexer_by_name)
    fresh = MarkdownRenderer().render(doc).html
    assert cached == fresh
    assert cached.count('class="highlight"') == 4 and "kept &lt;as&gt; text" in cached
