"""The blog (sitegen/blog.py): posts ordered by date, paginated index, tag pages, the yearly
archive, a valid Atom feed, and dates that do not parse reported with file and line."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path
from urllib.parse import unquote

import pytest
from sitegen_helpers import hrefs, pager, run_build, snapshot, write_tree

from sitegen.errors import BuildError

ATOM = "{http://www.w3.org/2005/Atom}"

POSTS = {
    "content/blog/first.md": (
        "---\ndate: 2020-12-30\ntags: [機器人]\n---\n# 開始 & 準備\n\n第一篇。\n"
    ),
    "content/blog/second.md": (
        "---\ntitle: Cart <demo>\ndate: 2021-03-04 10:20\ntags: robot, 機器人\n"
        "summary: Driving the cart & more\n---\nSee [home](../index.md).\n"
    ),
    "content/blog/third.md": (
        "---\ndate: 2021-05-01T08:00:00+08:00\ntags: [robot]\n---\n# Arm\n\n手臂 arm text.\n"
    ),
}


def make_site(root: Path, config: str = "", posts: dict | None = None) -> Path:
    files = {
        "sitegen.yml": "title: Blog test\nbase_url: https://example.org/c/\n" + config,
        "content/index.md": "# Home\n\nWelcome.\n",
        "content/stage-1/index.md": "# Stage 1\n",
        "content/stage-1/w1.md": "# W1\n\nweek one\n",
        **(POSTS if posts is None else posts),
    }
    return write_tree(root, files)


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    root = make_site(tmp_path_factory.mktemp("blog"), "blog:\n  page_size: 2\n")
    run_build(root, root / "site")
    return root / "site"


def read(site: Path, rel: str) -> str:
    return (site / rel).read_text(encoding="utf-8")


def listed(html: str) -> list[str]:
    return re.findall(r'<article class="post-summary"><h2><a href="[^"]*">(.*?)</a>', html)


def assert_links_resolve(site: Path, rel: str) -> None:
    folder = (site / rel).parent
    for href in hrefs(read(site, rel)):
        if href.startswith(("#", "?", "https:")):
            continue
        target = (folder / unquote(href.split("#")[0])).resolve()
        assert target.is_file(), f"{rel}: {href}"


def test_index_newest_first_paginated_with_pager(site):
    first = read(site, "blog/index.html")
    assert listed(first) == ["Arm", "Cart &lt;demo&gt;"]
    assert listed(read(site, "blog/page-2.html")) == ["開始 &amp; 準備"]
    assert 'rel="next" href="page-2.html"' in first
    assert 'rel="prev" href="index.html"' in read(site, "blog/page-2.html")
    assert "Driving the cart &amp; more" in first  # the summary
    assert '<time datetime="2021-03-04">2021-03-04</time>' in first
    assert "In this section" not in first  # the index is the list, not a list of children
    for rel in ("blog/index.html", "blog/page-2.html", "blog/archive.html", "blog/tags/index.html"):
        assert_links_resolve(site, rel)


def test_tag_pages_and_archive(site):
    tags = read(site, "blog/tags/index.html")
    assert re.findall(r'rel="tag" href="([^"]+)">([^<]+)</a>', tags) == [
        ("robot.html", "robot"),
        ("%E6%A9%9F%E5%99%A8%E4%BA%BA.html", "機器人"),
    ]
    assert listed(read(site, "blog/tags/robot.html")) == ["Arm", "Cart &lt;demo&gt;"]
    assert listed(read(site, "blog/tags/機器人.html")) == ["Cart &lt;demo&gt;", "開始 &amp; 準備"]
    archive = read(site, "blog/archive.html")
    assert re.findall(r'<h2 id="y(\d+)">', archive) == ["2021", "2020"]
    assert_links_resolve(site, "blog/tags/機器人.html")


def test_posts_prev_next_by_date_with_date_and_tag_links(site):
    post = read(site, "blog/cart-demo.html")
    assert pager(post) == ("Arm", "開始 &amp; 準備")
    assert re.search(r'<p class="post-meta"><time datetime="2021-03-04">', post)
    assert 'href="tags/robot.html"' in post and 'href="../index.html"' in post
    assert_links_resolve(site, "blog/cart-demo.html")
    # the first post: H1 is the title, shown once, and its date sits under it
    first = read(site, "blog/開始-準備.html")
    assert first.count("開始 &amp; 準備</h1>") == 1 and 'datetime="2020-12-30"' in first


def test_blog_is_the_last_top_level_menu_entry_and_posts_are_searchable(site):
    home = read(site, "index.html")
    menu = re.search(r'<nav id="nav".*?</nav>', home, re.S).group(0)
    top = re.findall(r'href="([^"]+)"', menu)
    assert top[-1] == "blog/index.html" and "stage-1/index.html" in top
    index = read(site, "assets/search-index.js")
    assert "手臂 arm text" in index and "blog/arm.html" in index


def test_atom_feed_is_valid_with_absolute_links(site):
    root = ET.fromstring((site / "feed.xml").read_bytes())
    assert root.tag == f"{ATOM}feed"
    for name in ("id", "title", "updated", "author"):
        assert root.find(f"{ATOM}{name}") is not None, name
    assert root.find(f"{ATOM}updated").text == "2021-05-01T08:00:00+08:00"
    self_link = root.find(f"{ATOM}link[@rel='self']").get("href")
    assert self_link == "https://example.org/c/feed.xml"
    entries = root.findall(f"{ATOM}entry")
    assert [e.find(f"{ATOM}title").text for e in entries] == ["Arm", "Cart <demo>", "開始 & 準備"]
    for e in entries:
        for name in ("id", "title", "updated", "summary"):
            assert e.find(f"{ATOM}{name}") is not None, name
        link = e.find(f"{ATOM}link").get("href")
        assert link.startswith("https://example.org/c/blog/") and link == e.find(f"{ATOM}id").text
        assert (site / unquote(link.removeprefix("https://example.org/c/"))).is_file()
    cart = entries[1]
    assert cart.find(f"{ATOM}updated").text == "2021-03-04T10:20:00Z"
    assert [c.get("term") for c in cart.findall(f"{ATOM}category")] == ["robot", "機器人"]
    assert cart.find(f"{ATOM}summary").text == "Driving the cart & more"
    assert 'href="../feed.xml"' in read(site, "blog/index.html")


def test_same_posts_same_bytes(tmp_path, site):
    root = make_site(tmp_path, "blog:\n  page_size: 2\n")
    run_build(root, root / "site")
    a, b = snapshot(site), snapshot(root / "site")
    keys = [k for k in a if k.startswith("blog/") or k == "feed.xml"]
    assert keys and all(a[k] == b[k] for k in keys)


def test_no_feed_without_base_url_and_configured_folder(tmp_path):
    posts = {k.replace("content/blog/", "content/diary/"): v for k, v in POSTS.items()}
    root = make_site(tmp_path, "blog:\n  dir: diary\n  title: 日誌\n", posts)
    cfg = root / "sitegen.yml"
    cfg.write_text(cfg.read_text().replace("base_url: https://example.org/c/\n", ""))
    run_build(root, root / "site")
    assert not (root / "site/feed.xml").exists()
    index = read(root / "site", "diary/index.html")
    assert "<h1>日誌</h1>" in index and listed(index) == [
        "Arm",
        "Cart &lt;demo&gt;",
        "開始 &amp; 準備",
    ]
    assert "feed.xml" not in index


def test_unparseable_date_is_an_error_with_file_and_line(tmp_path):
    bad = {"content/blog/bad.md": "---\ntitle: Bad\ntags: [a]\ndate: 2021-02-30\n---\ntext\n"}
    root = make_site(tmp_path, posts={**POSTS, **bad})
    with pytest.raises(BuildError) as err:
        run_build(root, root / "site")
    found = [(d.file, d.line, d.field) for d in err.value.diagnostics if d.severity == "error"]
    assert found == [("blog/bad.md", 4, "date")]
    assert "not a date" in str(err.value.diagnostics[0])


def test_a_post_without_date_is_an_error_naming_it(tmp_path):
    root = make_site(tmp_path, posts={**POSTS, "content/blog/undated.md": "# Undated\n"})
    with pytest.raises(BuildError) as err:
        run_build(root, root / "site")
    assert [(d.file, d.field) for d in err.value.diagnostics] == [
        ("content/blog/undated.md", "date")
    ]


def test_blog_config_errors_name_the_key(tmp_path):
    root = make_site(tmp_path, "blog:\n  page_size: 0\n  dir: ../x\n")
    with pytest.raises(BuildError) as err:
        run_build(root, root / "site")
    assert {d.field for d in err.value.diagnostics} == {"blog.page_size", "blog.dir"}


def test_blog_index_tag_page_and_feed_in_chromium(site):
    from browser_kit import WIDE, chromium, open_page, require_browser, static_server

    require_browser()
    with static_server(site) as base, chromium() as browser, open_page(browser, WIDE, site) as page:
        page.goto(base + "blog/index.html")
        assert page.inner_text("main h1") == "Blog"
        page.click("main .post-summary >> nth=1 >> a.tag >> text=機器人")
        assert unquote(page.url).endswith("blog/tags/機器人.html")
        assert "機器人" in page.inner_text("main h1")
        page.click("main .post-summary a >> text=開始 & 準備")
        assert page.inner_text("main h1") == "開始 & 準備"
        page.click("nav.pager >> nth=0 >> a.prev")  # previous by date: the newer post
        assert page.inner_text("main h1") == "Cart <demo>"
        page.goto(base + "blog/index.html")
        page.click("main .blog-pager >> text=Atom feed")
        assert page.url == base + "feed.xml"
        feed = ET.fromstring(page.request.get(page.url).body())
        assert feed.tag == f"{ATOM}feed" and len(feed.findall(f"{ATOM}entry")) == 3
