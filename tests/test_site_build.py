"""The site pipeline: navigation order, previous/next, slugs, links, search, output files."""

from __future__ import annotations

import json
import re
from pathlib import Path

import pytest
from sitegen_helpers import hrefs, pager, run_build, run_cli, snapshot, write_tree

from sitegen.check import check_site
from sitegen.slugs import slugify

COURSE = {
    "sitegen.yml": "title: 課程網站\nlanguage: zh-TW\nbase_url: https://40823112.github.io/cd2021/\n",
    "content/index.md": "# 首頁\n\n歡迎來到課程網站.\n",
    "content/introduction.md": "---\nweight: 1\n---\n# Introduction\n\nAbout the course.\n",
    "content/stage-1/index.md": "---\ntitle: Stage 1\nweight: 3\n---\n\n第一階段.\n",
    "content/stage-1/w1/index.md": "# W1\n\n第一週.\n",
    "content/stage-1/w1/02-repo.md": (
        "# 建立倉儲\n\n倉儲 [W2](../w2/index.md) [齒輪](../w2/gears.md#齒輪-方向與速度)\n"
    ),
    "content/stage-1/w1/01-ssh.md": "# 利用SSH維護倉儲\n\nSSH keys.\n",
    "content/stage-1/w2/index.md": "# W2\n",
    "content/stage-1/w2/gears.md": (
        "# 錯誤排解\n\n## 齒輪 方向與速度\n\n錯誤排解齒輪方向與速度的問題.\n\n"
        "### 小節\n\n![gear](../../images/gear.png)\n"
    ),
    "content/stage-1/w10/index.md": "# W10\n\nafter W2 by natural order\n",
    "content/collaboration.md": "---\nweight: 2\n---\n# Collaboration\n",
    "content/images/gear.png": b"\x89PNG\r\n\x1a\nfake",
}


@pytest.fixture()
def course(tmp_path: Path) -> tuple[Path, Path]:
    src = write_tree(tmp_path / "proj", COURSE)
    out = tmp_path / "out"
    run_build(src, out)
    return src, out


def read(out: Path, rel: str) -> str:
    return (out / rel).read_text(encoding="utf-8")


def test_document_order_and_prev_next(course):
    _src, out = course
    home = read(out, "index.html")
    assert pager(home) == (None, "Introduction")
    assert pager(read(out, "introduction.html")) == ("首頁", "Collaboration")
    # section page, then its children depth-first; numeric prefixes order 01 before 02; w2 < w10
    assert pager(read(out, "stage-1/index.html")) == ("Collaboration", "W1")
    assert pager(read(out, "stage-1/w1/index.html")) == ("Stage 1", "利用SSH維護倉儲")
    assert pager(read(out, "stage-1/w1/利用ssh維護倉儲.html")) == ("W1", "建立倉儲")
    assert pager(read(out, "stage-1/w1/建立倉儲.html")) == ("利用SSH維護倉儲", "W2")
    assert pager(read(out, "stage-1/w2/錯誤排解.html")) == ("W2", "W10")
    assert pager(read(out, "stage-1/w10/index.html")) == ("錯誤排解", None)


def test_menu_expands_only_the_current_branch(course):
    _src, out = course
    page = read(out, "stage-1/w1/建立倉儲.html")
    menu = re.search(r'<nav id="nav".*?</nav>', page, re.S).group(0)
    assert "建立倉儲" in menu and "利用SSH維護倉儲" in menu  # siblings in the open branch
    assert "錯誤排解" not in menu  # W2's pages stay collapsed
    assert 'aria-current="page"' in menu
    sitemap = read(out, "sitemap.html")
    for title in ("錯誤排解", "建立倉儲", "W10", "Collaboration"):
        assert title in sitemap


def test_every_link_is_relative_and_resolves(course):
    _src, out = course
    assert check_site(out) == []
    for page in out.rglob("*.html"):
        for url in hrefs(page.read_text(encoding="utf-8")):
            assert not url.startswith("/"), (page, url)
            assert "://" not in url or page.name == "404.html", (page, url)


def test_source_links_are_rewritten_to_pages_and_anchors(course):
    _src, out = course
    page = read(out, "stage-1/w1/建立倉儲.html")
    assert 'href="../w2/index.html"' in page
    assert "../w2/%E9%8C%AF%E8%AA%A4%E6%8E%92%E8%A7%A3.html#齒輪-方向與速度" in page
    gears = read(out, "stage-1/w2/錯誤排解.html")
    assert 'id="齒輪-方向與速度"' in gears
    assert 'src="../../images/gear.png"' in gears
    assert (out / "images/gear.png").read_bytes().endswith(b"fake")


def test_toc_lists_h2_and_h3(course):
    _src, out = course
    gears = read(out, "stage-1/w2/錯誤排解.html")
    toc = re.search(r'<nav class="toc".*?</nav>', gears, re.S).group(0)
    assert "齒輪 方向與速度" in toc and "小節" in toc


def test_search_index_holds_chinese_running_text(course):
    _src, out = course
    js = read(out, "assets/search-index.js")
    records = json.loads(js[len("window.SITEGEN_SEARCH=") : -2])
    gears = next(r for r in records if r["t"] == "錯誤排解")
    assert "錯誤排解齒輪方向與速度的問題" in gears["x"]
    assert gears["u"] == "stage-1/w2/錯誤排解.html"
    assert gears["p"] == "首頁 › Stage 1 › W2"


def test_site_files_for_github_pages(course):
    _src, out = course
    assert (out / ".nojekyll").exists()
    # 404.html works offline: no <base> to the published site, only its path, set over http(s)
    assert "<base href" not in read(out, "404.html")
    assert '"https://40823112.github.io/cd2021/"' in read(out, "404.html")
    xml = read(out, "sitemap.xml")
    assert "<loc>https://40823112.github.io/cd2021/</loc>" in xml
    assert "https://40823112.github.io/cd2021/stage-1/w1/index.html" in xml
    assert 'lang="zh-TW"' in read(out, "index.html") and "上一頁" in read(out, "introduction.html")
    css = read(out, "assets/pygments.css")
    assert ".highlight" in css and "prefers-color-scheme: dark" in css


def test_two_builds_are_byte_identical(tmp_path):
    src = write_tree(tmp_path / "p", COURSE)
    run_build(src, tmp_path / "a", cache_dir=tmp_path / "ca")
    run_build(src, tmp_path / "b", cache_dir=tmp_path / "cb")
    assert snapshot(tmp_path / "a") == snapshot(tmp_path / "b")


def test_source_date_epoch_is_the_only_date(tmp_path, monkeypatch):
    src = write_tree(tmp_path / "p", COURSE)
    monkeypatch.setenv("SOURCE_DATE_EPOCH", "1609459200")
    run_build(src, tmp_path / "o")
    assert "2021-01-01" in read(tmp_path / "o", "index.html")
    assert "<lastmod>2021-01-01</lastmod>" in read(tmp_path / "o", "sitemap.xml")


@pytest.mark.parametrize(
    ("title", "slug"),
    [
        ("W1 利用SSH維護倉儲", "w1-利用ssh維護倉儲"),
        ("Task 2-2: Remote API!", "task-2-2-remote-api"),
        ("../../etc/passwd", "etc-passwd"),
        ("CON", "con-"),
        ("???", "page"),
        ("ＡＢＣ　全形", "abc-全形"),
    ],
)
def test_slugs_are_readable_and_safe(title, slug):
    assert slugify(title) == slug


def test_duplicate_titles_get_distinct_urls(tmp_path):
    src = write_tree(
        tmp_path / "d",
        {"a.md": "# 討論\n", "b.md": "# 討論\n", "c.md": "---\nslug: index\n---\n# X\n"},
    )
    run_build(src, tmp_path / "o")
    names = sorted(p.name for p in (tmp_path / "o").glob("*.html"))
    assert "討論.html" in names and "討論-2.html" in names
    assert "index-2.html" in names  # a page may not take the home page's name


def test_a_section_url_is_its_index_slug_else_its_folder_name(tmp_path):
    """docs/DESIGN.md "Output URLs": a section's ``index.md`` ``slug:`` wins over its folder."""
    src = write_tree(
        tmp_path / "d",
        {
            "index.md": "# Home\n",
            "02-Week One/index.md": "---\nslug: start\n---\n# W1\n",
            "02-Week One/a.md": "# A\n",
            "03-Week Two/index.md": "# W2\n",
        },
    )
    run_build(src, tmp_path / "o")
    assert (tmp_path / "o" / "start" / "a.html").is_file()
    assert (tmp_path / "o" / "week-two" / "index.html").is_file()
    assert not (tmp_path / "o" / "week-one").exists()


def test_plain_folder_without_config_builds(tmp_path):
    src = write_tree(
        tmp_path / "notes",
        {
            "readme.md": "Intro text, no heading.\n",
            "Part One/first.md": "# First\n",
            "Part One/second.md": "no heading here\n",
        },
    )
    result = run_cli("build", "--source", str(src), "--output", str(tmp_path / "o"))
    assert result.returncode == 0, result.stderr
    out = tmp_path / "o"
    assert (out / "part-one/index.html").exists()  # folder -> section
    assert "<h1>second</h1>" in read(out, "part-one/second.html")  # title from file name
    assert "<h1>First</h1>" in read(out, "part-one/first.html")
    assert check_site(out) == []


def test_broken_links_warn_with_file_and_line_and_fail_strict(tmp_path):
    src = write_tree(
        tmp_path / "s", {"index.md": "# Home\n\nline three\n[x](missing.md) [y](#nowhere)\n"}
    )
    result = run_cli("build", "--source", str(src), "--output", str(tmp_path / "o"))
    assert result.returncode == 0
    assert "index.md:4: warning: link: link target 'missing.md' does not exist" in result.stderr
    assert "anchor '#nowhere' not found" in result.stderr
    strict = run_cli("build", "--source", str(src), "--output", str(tmp_path / "o2"), "--strict")
    assert strict.returncode == 1
    assert not (tmp_path / "o2").exists()
    assert "Traceback" not in strict.stderr


def test_code_blocks_are_highlighted_and_tables_render(tmp_path):
    src = write_tree(
        tmp_path / "s",
        {"index.md": "# H\n\n```python\nimport sim\n```\n\n| a | b |\n|---|---|\n| 1 | 2 |\n"},
    )
    run_build(src, tmp_path / "o")
    page = read(tmp_path / "o", "index.html")
    assert '<div class="highlight">' in page and '<span class="kn">import</span>' in page
    assert "<table>" in page and "<td>2</td>" in page


def test_roster_like_text_is_escaped_in_titles(tmp_path):
    src = write_tree(
        tmp_path / "s", {"x.md": "---\ntitle: '<script>alert(1)</script>'\n---\nbody\n"}
    )
    run_build(src, tmp_path / "o")
    html = "".join(p.read_text(encoding="utf-8") for p in (tmp_path / "o").glob("*.html"))
    assert "<script>alert(1)</script>" not in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html
