"""The build's speed work changes no output: reused formatters, linear Markdown, the menu
rendered once per folder, worker processes, streamed pages, and incremental page work.

No timings here (those live in bench/build_bench.py): each test checks that a shortcut gives
exactly what the plain way gives, or that work is skipped where nothing changed.
"""

from __future__ import annotations

import random
from pathlib import Path

import markdown
import pytest
from hypothesis import given
from hypothesis import strategies as st
from sitegen_helpers import run_build, snapshot, write_tree

import sitegen.links
import sitegen.workers
from sitegen.markdown_render import MarkdownRenderer
from sitegen.markdown_speed import BlockQueue, _OrderList
from sitegen.nav import PageInput, build_site, menu_for
from sitegen.pages import Menus
from sitegen.theme import Theme

DOC = """# Title

Intro with a footnote[^a] and another[^b] and the first again[^a].

```python
print("hi")
```

```c
int main(void) { return 0; }
```

~~~ {.python hl_lines="1"}
x = 1
~~~

    indented code

Term
:   definition

| a | b |
|---|---|
| 1 | 2 |

<div markdown="1">*inside html*</div>

[^a]: Note A.
[^b]: Note B.
"""


def _stock() -> markdown.Markdown:
    """Python-Markdown as configured before the speed work (no sitegen extensions)."""
    return markdown.Markdown(
        extensions=[
            "tables",
            "fenced_code",
            "footnotes",
            "attr_list",
            "def_list",
            "sane_lists",
            "md_in_html",
            "codehilite",
            "toc",
        ],
        extension_configs={
            "codehilite": {"css_class": "highlight", "guess_lang": False, "wrapcode": True},
            "toc": {"permalink": "#", "permalink_class": "anchor", "permalink_title": ""},
        },
        output_format="html",
    )


def _ours() -> markdown.Markdown:
    from sitegen.markdown_speed import (
        LinearBlocksExtension,
        LinearFootnotesExtension,
        cached_formatter,
    )

    return markdown.Markdown(
        extensions=[
            "tables",
            "fenced_code",
            LinearFootnotesExtension(),
            "attr_list",
            "def_list",
            "sane_lists",
            "md_in_html",
            "codehilite",
            "toc",
            LinearBlocksExtension(),
        ],
        extension_configs={
            "codehilite": {
                "css_class": "highlight",
                "guess_lang": False,
                "wrapcode": True,
                "pygments_formatter": cached_formatter,
            },
            "toc": {"permalink": "#", "permalink_class": "anchor", "permalink_title": ""},
        },
        output_format="html",
    )


def test_linear_markdown_gives_stock_output():
    rng = random.Random(3)
    many_notes = "".join(f"ref[^n{i}] " for i in rng.sample(range(300), 300)) + "\n\n"
    many_notes += "".join(f"[^n{i}]: note {i}\n" for i in range(300))
    many_blocks = "\n\n".join(f"## H {i}\n\n- a {i}\n- b\n\n> q {i}" for i in range(200))
    stock, ours = _stock(), _ours()
    for doc in (DOC, many_notes, many_blocks, DOC + many_notes):
        stock.reset()
        ours.reset()
        assert ours.convert(doc) == stock.convert(doc)
        assert ours.toc_tokens == stock.toc_tokens  # type: ignore[attr-defined]


def test_renderer_is_reset_not_rebuilt_between_pages():
    r = MarkdownRenderer()
    first = r.render(DOC)
    r.render("# Other\n\nx[^z]\n\n[^z]: z\n\n## Heading\n")
    assert r.render(DOC).html == first.html  # no footnote or id leaks from the page before


@given(
    st.lists(st.text(max_size=3), max_size=6),
    st.lists(
        st.one_of(
            st.tuples(st.just("pop0")),
            st.tuples(st.just("pop")),
            st.tuples(st.just("insert0"), st.text(max_size=2)),
            st.tuples(st.just("insert"), st.integers(-8, 8), st.text(max_size=2)),
            st.tuples(st.just("append"), st.text(max_size=2)),
        ),
        max_size=20,
    ),
)
def test_block_queue_behaves_like_a_list(start, ops):
    ref, q = list(start), BlockQueue(start)
    for op in ops:
        if op[0] in ("pop0", "pop") and not ref:
            with pytest.raises(IndexError):
                q.pop(0)
            continue
        if op[0] == "pop0":
            assert q.pop(0) == ref.pop(0)
        elif op[0] == "pop":
            assert q.pop() == ref.pop()
        elif op[0] == "insert0":
            q.insert(0, op[1])
            ref.insert(0, op[1])
        elif op[0] == "insert":
            q.insert(op[1], op[2])
            ref.insert(op[1], op[2])
        else:
            q.append(op[1])
            ref.append(op[1])
        assert list(q) == ref and len(q) == len(ref) and bool(q) == bool(ref)
        if ref:
            assert q[0] == ref[0] and q[-1] == ref[-1] and q[0:2] == ref[0:2]


def test_footnote_order_list_answers_like_a_list():
    order = _OrderList()
    for x in ["b", "a", "c", "a"]:
        if x not in order:
            order.append(x)
    assert order == ["b", "a", "c"] and order.index("c") == 2 and "z" not in order
    with pytest.raises(ValueError):
        order.index("z")


def _site():
    pages = [PageInput(Path("index.md"), {}, "# Home\n", True, None, "index")]  # type: ignore[arg-type]
    for d in ("a", "b/c"):
        pages.append(PageInput(Path(f"{d}/index.md"), {}, f"# {d}\n", True, None, "index"))  # type: ignore[arg-type]
        for i in range(4):
            stem = f"p{i}"
            title = f"<{d}> & page {i}"
            pages.append(PageInput(Path(f"{d}/{stem}.md"), {}, f"# {title}\n", False, None, stem))  # type: ignore[arg-type]
    from pathlib import PurePosixPath

    for p in pages:
        p.rel = PurePosixPath(str(p.rel))
    return build_site(pages)


def test_menu_rendered_once_per_folder_equals_menu_rendered_per_page():
    theme = Theme(None)
    site = _site()
    menus = Menus(theme, site)
    tree = theme.env.get_template("menu.html")
    for node in site.order:
        root = "../" * node.url.count("/")
        full = tree.make_module({"root": root}).tree(menu_for(site, node))
        assert str(menus.html(node)) == str(full), node.url
    assert "aria-current" not in str(menus.html(None))


def test_a_theme_menu_without_item_entries_still_marks_the_page(tmp_path):
    write_tree(
        tmp_path / "theme",
        {
            "menu.html": "{% macro item(it, current) %}{% endmacro %}"
            "{% macro tree(items) %}{% for it in items %}<b>{{ it.title }}"
            "{% if it.current %}*{% endif %}</b>{{ tree(it.children) }}{% endfor %}{% endmacro %}"
        },
    )
    site = _site()
    menus = Menus(Theme(tmp_path / "theme"), site)
    page = next(n for n in site.order if n.title == "<a> & page 2")
    assert "&lt;a&gt; &amp; page 2*</b>" in str(menus.html(page))


TREE = {
    "index.md": "# Home\n\n[a](a/p0.md) [gone](nope.md)\n",
    **{
        f"a/p{i}.md": f"# A{i}\n\nSee [next](p{i + 1}.md#h).\n\n## H\n\ntext {i}\n"
        for i in range(40)
    },
    **{f"b/q{i}.md": f"# B{i}\n\n```python\nx = {i}\n```\n" for i in range(40)},
    "b/index.md": "# B\n\n[home](../index.md)\n",
}


def test_worker_processes_give_the_same_bytes_as_one_process(tmp_path, monkeypatch):
    src = write_tree(tmp_path / "src", TREE)
    monkeypatch.setattr(sitegen.workers, "MIN_PARALLEL", 2)
    monkeypatch.setattr(sitegen.workers, "CHUNK", 3)
    monkeypatch.setenv("SITEGEN_JOBS", "1")
    one = run_build(src, tmp_path / "one", cache_dir=tmp_path / "c1")
    monkeypatch.setenv("SITEGEN_JOBS", "2")
    two = run_build(src, tmp_path / "two", cache_dir=tmp_path / "c2")
    assert snapshot(tmp_path / "one") == snapshot(tmp_path / "two")
    assert one.diagnostics == two.diagnostics and two.pages_rendered == len(TREE) + 1
    assert not any(".sitegen-building" in p.name for p in tmp_path.iterdir())


def test_one_page_edit_relinks_only_that_page_and_keeps_warnings(tmp_path, monkeypatch):
    src = write_tree(tmp_path / "src", TREE)
    out, cache = tmp_path / "site", tmp_path / "cache"
    first = run_build(src, out, cache_dir=cache)
    assert any("nope.md" in d.message for d in first.diagnostics)
    calls: list[str] = []
    real = sitegen.links.rewrite_links

    def counting(fragment, node, *a, **k):
        calls.append(node.url)
        return real(fragment, node, *a, **k)

    monkeypatch.setattr("sitegen.page_jobs.rewrite_links", counting)
    (src / "b/q7.md").write_text("# B7\n\nnew text\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    assert calls == ["b/b7.html"]
    assert report.markdown_rendered == 1 and report.pages_rendered == 1
    assert "new text" in (out / "b/b7.html").read_text(encoding="utf-8")
    # the unchanged home page's broken link is still reported, from the cache
    assert [d.message for d in report.diagnostics] == [d.message for d in first.diagnostics]


def test_a_new_heading_relinks_pages_but_rerenders_only_what_shows_it(tmp_path):
    src = write_tree(tmp_path / "src", TREE)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    before = snapshot(out)
    (src / "a/p3.md").write_text("# A3\n\n## Other\n\ntext\n", encoding="utf-8")
    report = run_build(src, out, cache_dir=cache)
    after = snapshot(out)
    changed = {rel for rel in after if after[rel] != before.get(rel)}
    # every page is re-linked (an id changed), but only p3 and p2 (whose link to p3.md#h is
    # now broken, so left as written and reported) are rendered again
    assert changed == {"a/a2.html", "a/a3.html", "assets/search-index.js"}
    assert report.pages_rendered == 2
    assert any(d.file.endswith("a/p2.md") and "#h" in d.message for d in report.diagnostics)


def test_a_damaged_fragment_store_means_pages_are_converted_again(tmp_path):
    src = write_tree(tmp_path / "src", TREE)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    before = snapshot(out)
    for extra in ("-wal", "-shm"):
        (cache / f"fragments.sqlite{extra}").unlink(missing_ok=True)
    (cache / "fragments.sqlite").write_bytes(b"not a database" * 100)
    (src / "a/p1.md").write_text(
        "# A1\n\nSee [next](p2.md#h).\n\n## H\n\nedited\n", encoding="utf-8"
    )
    report = run_build(src, out, cache_dir=cache)
    assert report.markdown_rendered == len(TREE)  # every page again, from scratch
    after = snapshot(out)
    assert {rel for rel in after if after[rel] != before.get(rel)} == {
        "a/a1.html",
        "assets/search-index.js",
    }
