"""The build cache's source records: a page taken from the last scan reads its text only when
used, and saving them again neither decodes nor re-encodes the texts nobody read."""

from __future__ import annotations

import dataclasses
import re
from pathlib import Path, PurePosixPath

from hypothesis import given
from hypothesis import strategies as st

from sitegen.build import to_input
from sitegen.content import SourceAsset, SourcePage, read_page
from sitegen.errors import Diagnostics
from sitegen.nav import build_site
from sitegen.page_text import first_heading, text_key
from sitegen.source_records import pack, unpack


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


def test_records_round_trip_with_every_field_and_text():
    records = _records()
    back = unpack(*pack(records))
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


def test_an_unchanged_site_is_navigated_without_reading_any_text():
    back = unpack(*pack(_records()))
    inputs = [to_input(r) for _k, r in back.values() if isinstance(r, SourcePage)]
    site = build_site(inputs)
    assert [n.title for n in site.order] == ["首頁", "w1", "第一週", "b"]
    assert site.order[2].strip_first_heading
    assert all("text" not in p.__dict__ for p in inputs)
    assert all("text" not in r.__dict__ for _k, r in back.values() if isinstance(r, SourcePage))
    assert inputs[1].text == "# 第一週\n\n內容 a\n"  # read when asked for


def test_a_page_whose_text_an_integration_changes_loses_the_text_derived_fields():
    page = to_input(unpack(*pack(_records()))["w1/a.md"][1])
    assert page.text_key and page.heading == ("第一週", 1, True)
    changed = dataclasses.replace(page, text="::: slide deck\n\n# 別的\n")
    assert changed.text_key == "" and changed.heading is None
    assert changed.first_heading() == ("別的", 1, False)


def test_saving_again_keeps_untouched_rows_and_compacts_when_mostly_stale():
    rows, blob = pack(_records())
    back = unpack(rows, blob)
    again_rows, again_blob = pack(back)
    assert again_rows == rows and again_blob == blob
    assert all(again_rows[rel] is rows[rel] for rel in rows if rows[rel][1] == "page")
    # a new version of one page: its text is added, the others keep their place
    key = [7, 7, 7, 7]
    back["w1/b.md"] = (key, _page("w1/b.md", "新的內容\n" * 3))
    rows2, blob2 = pack(back)
    assert rows2["index.md"] is rows["index.md"]
    assert len(blob2) > len(blob)
    assert unpack(rows2, blob2)["w1/b.md"][1].text == "新的內容\n" * 3
    # many rewrites of a long page: the stale versions are dropped
    for n in range(6):
        back = unpack(rows2, blob2)
        back["index.md"] = (key, _page("index.md", f"# 首頁 {n}\n" + "長" * 400))
        rows2, blob2 = pack(back)
    live = sum(r[-1] - r[-2] for r in rows2.values() if r[1] == "page")
    assert len(blob2) <= 2 * live
    final = unpack(rows2, blob2)
    assert final["index.md"][1].text.startswith("# 首頁 5\n")
    assert final["w1/a.md"][1].text == _records()["w1/a.md"][1].text


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
