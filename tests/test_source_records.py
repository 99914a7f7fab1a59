"""The build cache's source records: a page taken from the last scan reads its text only when
used, and saving them again neither decodes, re-encodes nor rewrites the texts nobody read."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path, PurePosixPath

from hypothesis import given
from hypothesis import strategies as st

from sitegen.build import to_input
from sitegen.cache import Cache
from sitegen.content import SourceAsset, SourcePage, read_page
from sitegen.errors import Diagnostics
from sitegen.nav import build_site
from sitegen.page_text import first_heading, text_key


def _page(rel: str, text: str) -> SourcePage:
    page = read_page(PurePosixPath(rel), PurePosixPath(rel), text.encode(), Diagnostics())
    assert page is not None
    return page


def _records() -> dict:
    pages = {
        "index.md": _page("index.md", "# 首頁\n\n歡迎.\n"),
        "w1/a.md": _page("w1/a.md", "---\ntitle: 第一週\nweight: 2\n---\n# 第一週\n\n內容 a\n"),
        "w1/b.md": _page("w1/b.md", "沒有標題的頁面\n"),
    }
    records: dict = {rel: ([1, 2, 3, i], page) for i, (rel, page) in enumerate(pages.items())}
    asset = SourceAsset(PurePosixPath("w1/pic.png"), Path("c/w1/pic.png"), "d")
    records["w1/pic.png"] = ([9, 9, 9, 9], asset)
    records["w1/draft.md"] = ([8, 8, 8, 8], None)
    return records


ROOT = Path("/content")


def _saved_and_loaded(tmp_path: Path, records: dict) -> dict:
    cache = Cache(tmp_path / "cache")
    cache.save_sources(ROOT, records)
    return cache.load_sources(ROOT)


def _texts(tmp_path: Path) -> list[Path]:
    return sorted((tmp_path / "cache").glob("sources-*.texts"))


def test_records_round_trip_with_every_field_and_text(tmp_path):
    records = _records()
    back = _saved_and_loaded(tmp_path, records)
    assert list(back) == list(records)
    for rel, (key, record) in records.items():
        assert back[rel][0] == key
        if isinstance(record, SourcePage):
            got = back[rel][1]
            assert "text" not in got.__dict__  # deferred
            assert got == record and got.text == record.text
            assert (got.text_key, got.heading) == (record.text_key, record.heading)
            assert got.text_key == text_key(record.text)
        else:
            assert back[rel][1] == record


def test_an_unchanged_site_is_navigated_without_reading_any_text(tmp_path):
    back = _saved_and_loaded(tmp_path, _records())
    inputs = [to_input(r) for _k, r in back.values() if isinstance(r, SourcePage)]
    site = build_site(inputs)
    assert [n.title for n in site.order] == ["首頁", "w1", "第一週", "b"]
    assert site.order[2].strip_first_heading
    assert all("text" not in p.__dict__ for p in inputs)
    assert all("text" not in r.__dict__ for _k, r in back.values() if isinstance(r, SourcePage))
    assert inputs[1].text == "# 第一週\n\n內容 a\n"  # read when asked for


def test_a_page_whose_text_an_integration_changes_loses_the_text_derived_fields(tmp_path):
    page = to_input(_saved_and_loaded(tmp_path, _records())["w1/a.md"][1])
    assert page.text_key and page.heading == ("第一週", 1, True)
    changed = dataclasses.replace(page, text="::: slide deck\n\n# 別的\n")
    assert changed.text_key == "" and changed.heading is None
    assert changed.first_heading() == ("別的", 1, False)


def test_an_edit_appends_its_text_and_a_mostly_stale_file_is_written_afresh(tmp_path):
    cache = Cache(tmp_path / "cache")
    cache.save_sources(ROOT, _records())
    [first] = _texts(tmp_path)
    size = first.stat().st_size
    # saved again unchanged: the same file, nothing added, no text decoded
    back = cache.load_sources(ROOT)
    cache.save_sources(ROOT, back)
    assert _texts(tmp_path) == [first] and first.stat().st_size == size
    assert all("text" not in r.__dict__ for _k, r in back.values() if isinstance(r, SourcePage))
    # one page read anew: only its text is added to the same file
    back = cache.load_sources(ROOT)
    back["w1/b.md"] = ([7, 7, 7, 7], _page("w1/b.md", "新的內容\n" * 3))
    cache.save_sources(ROOT, back)
    assert _texts(tmp_path) == [first]
    assert first.stat().st_size == size + len(("新的內容\n" * 3).encode())
    assert cache.load_sources(ROOT)["w1/b.md"][1].text == "新的內容\n" * 3
    # many rewrites of a long page: the file of mostly old versions is replaced
    for n in range(40):
        back = cache.load_sources(ROOT)
        back["index.md"] = ([7, 7, 7, n], _page("index.md", f"# 首頁 {n}\n" + "長" * 4000))
        cache.save_sources(ROOT, back)
    [now] = _texts(tmp_path)  # 40 versions of 12 KB were written; at most a few are kept
    live = 12_100 + 200
    assert now != first and now.stat().st_size <= 2 * live + (64 << 10) + 12_100
    final = cache.load_sources(ROOT)
    assert final["index.md"][1].text.startswith("# 首頁 39\n")
    assert final["w1/a.md"][1].text == _records()["w1/a.md"][1].text
    assert final["w1/b.md"][1].text == "新的內容\n" * 3


def test_a_cut_short_file_of_texts_means_no_cached_records(tmp_path):
    cache = Cache(tmp_path / "cache")
    cache.save_sources(ROOT, _records())
    [texts] = _texts(tmp_path)
    texts.write_bytes(texts.read_bytes()[:10])
    assert cache.load_sources(ROOT) == {}
    texts.unlink()
    assert cache.load_sources(ROOT) == {}


_LINES = st.sampled_from(
    ["# A", "## B c", "", "```", "~~~", "text", "  ", "#no", "### x ###", "\t# t"]
)


@given(st.lists(_LINES, max_size=8), st.booleans())
def test_first_heading_stops_at_the_heading_but_reads_as_every_line_would(lines, newline):
    """The first heading as a reading of every line (what nav did before) finds it."""
    text = "\n".join(lines) + ("\n" if newline else "")
    in_fence, seen, want = False, False, (None, 0, False)
    for line in text.split("\n"):
        if line.lstrip().startswith(("```", "~~~")):
            in_fence, seen = not in_fence, True
        elif not in_fence and re.match(r"^(#{1,6})[ \t]+(.+?)[ \t]*#*[ \t]*$", line):
            m = re.match(r"^(#{1,6})[ \t]+(.+?)[ \t]*#*[ \t]*$", line)
            want = (m.group(2).strip(), len(m.group(1)), not seen)
            break
        elif not in_fence and line.strip():
            seen = True
    assert first_heading(text) == want
