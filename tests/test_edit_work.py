"""A one-page edit does work for that page only, and gives what a clean build gives.

Each shortcut of a partial build (docs/DESIGN.md, "A partial build does work proportional to
what changed") is checked two ways: the work it skips is not done (counted), and the site is
byte-identical to a build of the same sources from an empty cache. No timings here: those are
in bench/build_bench.py.
"""

from __future__ import annotations

import gc
from pathlib import Path

import pytest
from sitegen_helpers import run_build, settled_build, snapshot

import sitegen.build
import sitegen.content
import sitegen.markdown_stage
import sitegen.page_jobs
import sitegen.page_text

TREE = {
    "index.md": "# Home\n\n[a](a/p0.md)\n",
    **{
        f"a/p{i}.md": f"# A{i}\n\nSee [next](p{i + 1}.md).\n\n## H\n\ntext {i}\n" for i in range(12)
    },
    "a/p12.md": "# A12\n\nlast\n",
    **{f"b/q{i}.md": f"# B{i}\n\n```python\nx = {i}\n```\n" for i in range(8)},
    "b/index.md": "# B\n\n[home](../index.md)\n",
}


@pytest.fixture()
def settled(tmp_path: Path, monkeypatch):
    """A built site whose sources the cache trusts by stat (no racy window)."""
    return settled_build(tmp_path, monkeypatch, TREE)


def _clean_build(src: Path, tmp_path: Path) -> dict[str, bytes]:
    run_build(src, tmp_path / "clean", cache_dir=tmp_path / "clean-cache")
    return snapshot(tmp_path / "clean")


def _count(monkeypatch, owner, name: str) -> list:
    """Record the second argument (the one after ``self`` for a method) of each call."""
    calls: list = []
    real = getattr(owner, name)

    def counting(*args, **kw):
        calls.append(args[1] if len(args) > 1 else args[0])
        return real(*args, **kw)

    monkeypatch.setattr(owner, name, counting)
    return calls


def test_a_text_edit_hashes_one_context_makes_one_record_and_reads_one_text(
    settled, tmp_path, monkeypatch
):
    src, out, cache = settled
    keys = _count(monkeypatch, sitegen.page_jobs.PagePhase, "input_key")
    records = _count(monkeypatch, sitegen.markdown_stage, "record_json")
    texts: list[str] = []
    real_getattr = sitegen.page_text.DeferredText.__getattr__

    def reading(self, name):
        if name == "text":
            texts.append(str(self.rel))
        return real_getattr(self, name)

    monkeypatch.setattr(sitegen.page_text.DeferredText, "__getattr__", reading)
    (src / "a/p5.md").write_text("# A5\n\nSee [next](p6.md).\n\n## H\n\nedited\n", "utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == 1 and report.pages_rendered == 1
    assert [n.url for n in keys] == ["a/a5.html"]  # the other pages keep their keys
    # one page's search record made, the others copied (but for the generated page of the
    # folder without index.md, whose record is always made: it has no source to key on)
    assert records == ["a/index.html", "a/a5.html"]
    assert texts == []  # no unchanged page's Markdown was even decoded
    assert snapshot(out) == _clean_build(src, tmp_path)


def test_a_new_title_makes_every_input_key_again_and_still_equals_a_clean_build(
    settled, tmp_path, monkeypatch
):
    src, out, cache = settled
    keys = _count(monkeypatch, sitegen.page_jobs.PagePhase, "input_key")
    (src / "a/p5.md").write_text("# Renamed\n\nSee [next](p6.md).\n\n## H\n\ntext 5\n", "utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert len(keys) == report.pages  # the tree changed: no key is taken on trust
    # the neighbours (pager) and the folder's pages (menu) show the new title
    assert 1 < report.pages_rendered < report.pages
    assert snapshot(out) == _clean_build(src, tmp_path)


def test_a_search_index_edited_by_hand_is_made_whole_again(settled, tmp_path):
    src, out, cache = settled
    index = out / "assets" / "search-index.js"
    index.write_bytes(index.read_bytes().replace(b"text 3", b"XXXX 3"))
    (src / "b/q2.md").write_text("# B2\n\n```python\nx = 'two'\n```\n", "utf-8")
    run_build(src, out, cache_dir=cache)
    assert b"XXXX" not in index.read_bytes()
    assert snapshot(out) == _clean_build(src, tmp_path)


def test_same_files_other_contents_are_read_without_a_second_walk(settled, monkeypatch):
    src, out, cache = settled
    walked = _count(monkeypatch, sitegen.content, "_reuse")  # the walk's per-file step
    (src / "b/q3.md").write_text("# B3\n\nno code now\n", "utf-8")
    run_build(src, out, cache_dir=cache)
    assert walked == []  # the no-op check's stat walk served the scan too
    assert "no code now" in (out / "b" / "b3.html").read_text("utf-8")


def test_the_collector_is_paused_for_the_build_only(settled, monkeypatch):
    src, out, cache = settled
    seen: list[bool] = []
    real = sitegen.build.site_tree

    def watching(*args, **kw):
        seen.append(gc.isenabled())
        return real(*args, **kw)

    monkeypatch.setattr(sitegen.build, "site_tree", watching)
    assert gc.isenabled()
    (src / "a/p1.md").write_text("# A1\n\nchanged\n", "utf-8")
    run_build(src, out, cache_dir=cache)
    assert seen == [False] and gc.isenabled()
