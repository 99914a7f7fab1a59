"""cmsimde import: one page per H1-H3 in cmsimde's order, nothing visible lost.

The real sites in /work/shared/data are the main fixtures: the checks below compute what
they expect from the HTML independently (regexes and a plain text extractor), not from the
importer's own parser, and render the produced Markdown with the ``markdown`` package.
"""

from __future__ import annotations

import base64
import hashlib
import html
import re
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote

import markdown
import pytest
import yaml

from sitegen.importers.cli import main
from sitegen.importers.cmsimde import CmsimdeImportError, import_cmsimde

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT.parent / "shared" / "data"
TEMPLATE = DATA / "cmstemplate_content.htm"
SITES = DATA / "cmsimde-sites"
WITH_BASE64 = SITES / "content_40823145.htm"
EDGE = ROOT / "tests" / "fixtures" / "cmsimde" / "edge.htm"

BASIC_EXTS = ["tables", "fenced_code"]
# what sitegen's renderer adds that can change how text reads (toc/codehilite only decorate)
SITEGEN_EXTS = BASIC_EXTS + ["footnotes", "attr_list", "def_list", "sane_lists", "md_in_html"]
HEADING = re.compile(r"<h([1-3])\b[^>]*>(.*?)</h\1\s*>", re.S | re.I)

needs_real_data = pytest.mark.needs_shared("data", "cmstemplate_content.htm")


# -- independent helpers ---------------------------------------------------------------------


class _Visible(HTMLParser):
    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.parts: list[str] = []
        self.hidden = 0

    def handle_starttag(self, tag, attrs):
        self.hidden += tag in ("script", "style")

    def handle_endtag(self, tag):
        self.hidden -= tag in ("script", "style") and self.hidden > 0

    def handle_data(self, data):
        if not self.hidden:
            self.parts.append(data)


def visible(fragment: str) -> str:
    """Text a browser shows, with all whitespace removed (layout is not compared)."""
    parser = _Visible()
    parser.feed(fragment)
    parser.close()
    return re.sub(r"\s+", "", "".join(parser.parts))


def sections(source: str) -> list[tuple[str, str]]:
    """(heading title, visible text of its own section) for each H1-H3, in file order."""
    found = list(HEADING.finditer(source))
    out = []
    for i, m in enumerate(found):
        end = found[i + 1].start() if i + 1 < len(found) else len(source)
        title = html.unescape(re.sub(r"<[^>]+>", "", m.group(2))).strip()
        out.append((title, visible(source[m.end() : end])))
    return out


def split_page(path: Path) -> tuple[dict, str]:
    text = path.read_text(encoding="utf-8")
    m = re.match(r"---\n(.*?)\n---\n", text, re.S)
    assert m, f"{path} has no front matter"
    return yaml.safe_load(m.group(1)), text[m.end() :]


def document_order(content: Path) -> list[Path]:
    """DESIGN.md order: a folder's index.md first, then children by weight, prefix, name."""

    def key(p: Path) -> tuple:
        meta, _ = split_page(p / "index.md" if p.is_dir() else p)
        m = re.match(r"(\d+)", p.name)
        return (meta.get("weight", 10**9), int(m.group(1)) if m else 10**9, p.name)

    def visit(folder: Path) -> list[Path]:
        kids = [
            p
            for p in folder.iterdir()
            if (p.is_dir() and (p / "index.md").is_file())
            or (p.suffix == ".md" and p.name != "index.md")
        ]
        out = []
        for kid in sorted(kids, key=key):
            if kid.is_dir():
                out.append(kid / "index.md")
                out.extend(visit(kid))
            else:
                out.append(kid)
        return out

    home = [content / "index.md"] if (content / "index.md").is_file() else []
    return home + visit(content)


def rendered_text(path: Path, exts: list[str]) -> str:
    return visible(markdown.markdown(split_page(path)[1], extensions=exts))


def tree_bytes(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def template(tmp_path_factory):
    dest = tmp_path_factory.mktemp("template") / "content"
    return dest, import_cmsimde(TEMPLATE, dest)


# -- the cmsimde template site -----------------------------------------------------------------


@needs_real_data
def test_one_page_per_heading_in_cmsimde_order(template):
    dest, report = template
    expected = [title for title, _ in sections(TEMPLATE.read_text(encoding="utf-8"))]
    assert len(expected) == len(re.findall(r"<h[1-3][\s>]", TEMPLATE.read_text(encoding="utf-8")))
    pages = document_order(dest)
    assert [split_page(p)[0]["title"] for p in pages] == expected
    # nothing before the first heading: the first page is the home page, as cmsimde opens it
    assert split_page(dest / "index.md")[0] == {"title": "About"}
    assert [p.title for p in report.pages] == expected


@needs_real_data
def test_headings_with_children_become_folders(template):
    dest, _ = template
    assert (dest / "index.md").is_file() and not (dest / "01-about.md").exists()
    assert split_page(dest / "04-cmsimde" / "index.md")[0] == {"title": "CMSiMDE", "weight": 4}
    assert (
        split_page(dest / "04-cmsimde" / "02-基本操作" / "07-檢視-stl.md")[0]["title"] == "檢視 STL"
    )


@needs_real_data
@pytest.mark.parametrize("exts", [BASIC_EXTS, SITEGEN_EXTS], ids=["basic", "sitegen-extensions"])
def test_no_visible_text_lost(template, exts):
    dest, _ = template
    expected = sections(TEMPLATE.read_text(encoding="utf-8"))
    pages = document_order(dest)
    for (title, before), page in zip(expected, pages, strict=True):
        assert rendered_text(page, exts) == before, f"text differs on page {title!r} ({page})"


@needs_real_data
def test_code_blocks_fenced_with_their_language(template):
    dest, _ = template
    brushes = re.findall(r'<pre class="brush:\s*(\w+)', TEMPLATE.read_text(encoding="utf-8"))
    mapping = {"py": "python", "js": "javascript", "html": "html", "dart": "dart"}
    fences = []
    for page in document_order(dest):
        fences += re.findall(r"^```(\w+)$", split_page(page)[1], re.M)
    assert fences == [mapping[b] for b in brushes]
    assert "<pre" not in "".join(split_page(p)[1] for p in document_order(dest))


@needs_real_data
def test_scripts_reported_per_page(template):
    _, report = template
    by_title = {p.title: p.warnings for p in report.pages}
    assert sum("<script>" in w for w in by_title["Wink"]) == 2
    assert any("<script>" in w and "spikeball.stl" in w for w in by_title["檢視 STL"])
    assert "Wink: <script> not carried over (167 lines inline) (line 78)" in report.warnings


@needs_real_data
def test_raw_html_kept_and_asset_urls_rewritten(template):
    dest, report = template
    wink = split_page(dest / "03-wink" / "index.md")[1]
    assert wink.count("<video") == 2 and 'src="../downloads/wink_tutorial1.mp4"' in wink
    stl = split_page(dest / "04-cmsimde" / "02-基本操作" / "07-檢視-stl.md")[1]
    assert '<iframe height="400" src="../../static/viewstl.html?src=https://mde.tw/' in stl
    about = split_page(dest / "index.md")[1]  # the first page is the home page
    assert "[PythonNotesForProfessionals.pdf](downloads/PythonNotesForProfessionals.pdf)" in about
    assert '<span style="background-color: #00ff00;">Use this template</span>' in about
    # a bare content.htm has no images/ or downloads/ beside it: every file is reported missing
    assert any("missing file(s)" in w and "images/nfu_logo_mde.png" in w for w in report.warnings)
    assert report.files_copied == []


@needs_real_data
def test_import_is_deterministic(template, tmp_path):
    dest, _ = template
    again = tmp_path / "again"
    import_cmsimde(TEMPLATE, again)
    assert tree_bytes(again) == tree_bytes(dest)


# -- real student sites ------------------------------------------------------------------------


@needs_real_data
def test_base64_images_extracted(tmp_path):
    dest = tmp_path / "content"
    report = import_cmsimde(WITH_BASE64, dest)
    source = WITH_BASE64.read_text(encoding="utf-8")
    payloads = re.findall(r'src="data:image/jpeg;base64,([^"]+)"', source)
    assert len(payloads) == 2
    names = {f"images/{hashlib.sha256(base64.b64decode(p)).hexdigest()[:16]}.jpg" for p in payloads}
    assert set(report.images_extracted) == names
    for name in names:
        assert (dest / name).read_bytes()[:2] == b"\xff\xd8"  # JPEG
    markdown_text = "".join(p.read_text(encoding="utf-8") for p in dest.rglob("*.md"))
    assert "data:image" not in markdown_text
    for name in names:
        assert f'src="../{name}"' in markdown_text


@needs_real_data
@pytest.mark.parametrize("site", sorted(SITES.glob("*.htm")), ids=lambda p: p.stem)
def test_student_sites_keep_text_and_order(site, tmp_path):
    dest = tmp_path / "content"
    report = import_cmsimde(site, dest)
    expected = sections(site.read_text(encoding="utf-8"))
    pages = document_order(dest)
    assert [split_page(p)[0]["title"] for p in pages] == [t for t, _ in expected]
    for (title, before), page, info in zip(expected, pages, report.pages, strict=True):
        after = rendered_text(page, SITEGEN_EXTS)
        if any("SyntaxHighlighter" in w or "literal text" in w for w in info.warnings):
            # documented changes: highlighter line numbers dropped, typed tags shown as code
            before, after = re.sub(r"\d", "", before), re.sub(r"\d", "", after)
            assert _is_subsequence(before, after), f"text lost on page {title!r}"
        else:
            assert after == before, f"text differs on page {title!r}"


def _is_subsequence(small: str, big: str) -> bool:
    it = iter(big)
    return all(ch in it for ch in small)


@needs_real_data
def test_pasted_highlighter_and_typed_tags_become_code(tmp_path):
    dest = tmp_path / "content"
    import_cmsimde(WITH_BASE64, dest)
    task1 = split_page(dest / "06-stage3-ag1" / "01-task1.md")[1]
    assert "```python\n# open file, default is read mode" in task1
    assert "syntaxhighlighter" not in task1 and "<table" not in task1
    stage2 = split_page(dest / "05-stage2-ag1.md")[1]
    assert '<hslider id="1" maximum="100"' in stage2  # typed inside brush:html, kept as code


# -- edge cases (hand-written fixture) ---------------------------------------------------------


@pytest.fixture()
def edge_site(tmp_path):
    """A site folder: config/content.htm, images/ beside config/, downloads/ under content/."""
    site = tmp_path / "site"
    (site / "config").mkdir(parents=True)
    (site / "config" / "content.htm").write_bytes(EDGE.read_bytes())
    (site / "config" / "config").write_text("siteTitle:My 網站\npassword:x\n", encoding="utf-8")
    (site / "images").mkdir()
    (site / "images" / "photo.png").write_bytes(b"png")  # referenced as Photo.PNG
    (site / "images" / "unused.gif").write_bytes(b"gif")
    (site / "content" / "downloads").mkdir(parents=True)
    (site / "content" / "downloads" / "notes.pdf").write_bytes(b"pdf")
    return site


def test_edge_structure(edge_site, tmp_path):
    dest = tmp_path / "out"
    report = import_cmsimde(edge_site, dest)
    pages = document_order(dest)
    titles = [split_page(p)[0]["title"] for p in pages]
    assert titles == [
        "My 網站",  # the text before the first heading, in a page of its own (below)
        "Starts at H2",
        'Intro: "quotes" & \\back#slash',
        "Deep",
        "Week 1",
        "Week 1",
        "Markup in heading",
    ]
    assert pages[1].name == "01-starts-at-h2.md"
    assert [p.relative_to(dest).as_posix() for p in pages[3:5]] == [
        "02-intro-quotes-back-slash/01-deep.md",
        "02-intro-quotes-back-slash/02-week-1.md",
    ]
    # text before the first heading: a front page titled like the cmsimde site, and reported
    meta, body = split_page(dest / "index.md")
    assert meta == {"title": "My 網站"} and body.strip() == "Welcome text before any heading."
    assert (
        report.pages[0].level == 0
        and "text before the first heading" in report.pages[0].warnings[0]
    )
    # the second "Week 1" was inside a <div>: split there, both pages kept
    assert "inside a box" in split_page(pages[4])[1]
    assert (
        "second week" in split_page(pages[5])[1]
        and "after an empty heading" in split_page(pages[5])[1]
    )


def test_edge_links_and_files(edge_site, tmp_path):
    dest = tmp_path / "out"
    report = import_cmsimde(edge_site, dest)
    intro = split_page(dest / "02-intro-quotes-back-slash" / "index.md")[1]
    for link in (
        "[dynamic](02-week-1.md)",
        "[static duplicate](03-week-1.md)",
        "[static](../01-starts-at-h2.md)",
        "[query](01-deep.md)",
        "[home](../01-starts-at-h2.md)",
        "[unknown](/get_page/Nowhere)",
        "[server](/login)",
    ):
        assert link in intro
    last = split_page(dest / "02-intro-quotes-back-slash" / "04-markup-in-heading.md")[1]
    assert '<img src="../images/photo.png" alt="" width="40" height="30">' in last
    assert "[notes](../downloads/notes.pdf)" in last
    assert sorted(report.files_copied) == ["downloads/notes.pdf", "images/photo.png"]
    assert (dest / "downloads" / "notes.pdf").read_bytes() == b"pdf"
    assert len(report.images_extracted) == 1 and (dest / report.images_extracted[0]).is_file()
    joined = "\n".join(report.warnings)
    assert (
        'Intro: "quotes" & \\back#slash: '
        "link to unknown cmsimde page 'Nowhere' left as is (line 7)" in joined
    )
    assert "missing file(s), linked but not copied: images/missing.png" in joined
    assert "not referenced by any page, not copied: images/unused.gif" in joined


def test_edge_problems_reported_on_their_page(edge_site, tmp_path):
    report = import_cmsimde(edge_site, tmp_path / "out")
    by_title = {p.title: p.warnings for p in report.pages}
    last = by_title["Markup in heading"]
    for expected in (
        "markup inside the heading not carried over (<a>)",
        "Brython (Python) script",
        "unclosed <span>",
        "unknown element <blink>",
        "stray </div> ignored (line 29)",
    ):
        assert any(expected in w for w in last), expected
    assert any("holds page headings" in w for w in report.pages[4].warnings)  # first "Week 1"
    assert any("empty <h2> is not a page" in w for w in report.pages[5].warnings)
    assert (
        "first heading is <h2>: made a top-level page, as cmsimde does (line 2)"
        in report.pages[1].warnings
    )
    assert all(": " in w for w in report.warnings)


@pytest.mark.parametrize("exts", [BASIC_EXTS, SITEGEN_EXTS], ids=["basic", "sitegen-extensions"])
def test_edge_special_characters_survive_rendering(edge_site, tmp_path, exts):
    dest = tmp_path / "out"
    import_cmsimde(edge_site, dest)
    page = dest / "02-intro-quotes-back-slash" / "04-markup-in-heading.md"
    text = rendered_text(page, exts)
    assert "Special:1.notalist,*star,_under_,`tick`,[brackets],<tag>,a|b,{#id},C#" in text
    assert ":::clipnot-a-directive" in text
    body = split_page(page)[1]
    assert not re.search(r"^::: ", body, re.M)  # not read as a sitegen directive
    assert '```python\ndef f():\n    return "<b>"\n```' in body
    assert '<table><tr><td rowspan="2">a</td>' in body


def test_titles_round_trip_through_yaml(tmp_path):
    titles = [
        'a: "b" #c',
        "back\\slash",
        "tab\there",
        "'single'",
        "---",
        "- dash",
        "中文 標題！",
        "@at",
        "null",
    ]
    source = "".join(f"<h1>{html.escape(t)}</h1><p>x</p>" for t in titles)
    (tmp_path / "content.htm").write_text(source, encoding="utf-8")
    import_cmsimde(tmp_path / "content.htm", tmp_path / "out")
    assert [split_page(p)[0]["title"] for p in document_order(tmp_path / "out")] == titles


def test_first_heading_is_top_level_like_cmsimde(tmp_path):
    # cmsimde turns a first <h3> into <h1>, so the <h2> after it is its child
    (tmp_path / "content.htm").write_text(
        "<h3>A</h3><h2>B</h2><h1>C</h1><h3>D</h3>", encoding="utf-8"
    )
    report = import_cmsimde(tmp_path / "content.htm", tmp_path / "out")
    # A is the first page, so the home page (issue 30): its child B is a top-level page
    assert [p.path for p in report.pages] == [
        "index.md",
        "01-b.md",
        "02-c/index.md",
        "02-c/01-d.md",
    ]
    assert [p.level for p in report.pages] == [1, 2, 1, 3]
    assert "the first page, 'A', is the home page (index.md); its 1 sub-page(s)" in report.notes[0]


def test_reserved_file_names_avoided(tmp_path):
    (tmp_path / "content.htm").write_text(
        "<p>front</p><h1>Index</h1><h2>README</h2><h1>x</h1>", encoding="utf-8"
    )
    import_cmsimde(tmp_path / "content.htm", tmp_path / "out")
    assert (tmp_path / "out" / "01-index-page" / "index.md").is_file()
    assert (tmp_path / "out" / "01-index-page" / "01-readme-page.md").is_file()


# -- destination and errors --------------------------------------------------------------------


def test_dest_must_be_empty_unless_force(tmp_path):
    src = tmp_path / "content.htm"
    src.write_text("<h1>A</h1><p>a</p>", encoding="utf-8")
    dest = tmp_path / "out"
    (dest / "old").mkdir(parents=True)
    (dest / "old" / "stale.md").write_text("old", encoding="utf-8")
    with pytest.raises(CmsimdeImportError, match="not empty"):
        import_cmsimde(src, dest)
    import_cmsimde(src, dest, force=True)
    assert sorted(tree_bytes(dest)) == ["index.md"]  # replaced, no stale files left


def test_force_refuses_a_git_folder_or_the_source(tmp_path):
    src = tmp_path / "site" / "config" / "content.htm"
    src.parent.mkdir(parents=True)
    src.write_text("<h1>A</h1>", encoding="utf-8")
    with pytest.raises(CmsimdeImportError, match="contains the site"):
        import_cmsimde(src, tmp_path / "site", force=True)
    repo = tmp_path / "repo"
    (repo / ".git").mkdir(parents=True)
    with pytest.raises(CmsimdeImportError, match=".git"):
        import_cmsimde(src, repo, force=True)


def test_errors_carry_file_and_line(tmp_path):
    bad = tmp_path / "content.htm"
    bad.write_bytes(b"<h1>ok</h1>\n<p>\n\xff\xfe</p>")
    with pytest.raises(CmsimdeImportError) as err:
        import_cmsimde(bad, tmp_path / "out")
    assert (err.value.file, err.value.line) == (str(bad), 3)
    (tmp_path / "empty.htm").write_text(
        "<p>no headings</p><h4>h4 is not a page</h4>", encoding="utf-8"
    )
    with pytest.raises(CmsimdeImportError, match="no <h1>, <h2> or <h3>"):
        import_cmsimde(tmp_path / "empty.htm", tmp_path / "out")
    (tmp_path / "empty").mkdir()
    with pytest.raises(CmsimdeImportError, match="not a cmsimde site"):
        import_cmsimde(tmp_path / "empty", tmp_path / "out")
    assert not (tmp_path / "out").exists()


# -- CLI ---------------------------------------------------------------------------------------


def test_cli_exit_codes_and_output(edge_site, tmp_path, capsys):
    dest = tmp_path / "out"
    assert main(["cmsimde", str(edge_site), "--dest", str(dest)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("Imported 7 page(s) from ")
    assert "02-intro-quotes-back-slash/04-markup-in-heading.md  [Markup in heading]" in out
    assert "! unknown element <blink> unwrapped, its text kept (line 26)" in out

    assert main(["cmsimde", str(edge_site), "--dest", str(dest)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [f"{dest}:0: destination is not empty (use --force to replace it)"]
    assert main(["cmsimde", str(edge_site), "--dest", str(dest), "--force"]) == 0
    capsys.readouterr()

    assert main(["cmsimde", str(tmp_path / "nope.htm"), "--dest", str(tmp_path / "x")]) == 1
    assert "nope.htm:0: no such file or directory" in capsys.readouterr().err
    assert main(["wordpress", "x"]) == 2
    assert main([]) == 2
    assert main(["cmsimde"], prog="sitegen import") == 2
    assert "usage: sitegen import" in capsys.readouterr().err


# -- end to end with the site builder ----------------------------------------------------------


@needs_real_data
def test_imported_template_builds_strict(tmp_path):
    """A complete site folder (every referenced file present) imports and builds cleanly."""
    site = tmp_path / "cmstemplate"
    (site / "config").mkdir(parents=True)
    source = TEMPLATE.read_text(encoding="utf-8")
    (site / "config" / "content.htm").write_text(source, encoding="utf-8")
    for kind, name in re.findall(r'(?:src|href)="/(images|downloads|static)/([^"?#]+)', source):
        path = site / kind / unquote(name)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(b"placeholder")
    content, output = tmp_path / "content", tmp_path / "site"
    report = import_cmsimde(site, content)
    assert len(report.files_copied) == 8 and not any("missing" in w for w in report.warnings)

    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "sitegen",
            "build",
            "--source",
            str(content),
            "--output",
            str(output),
            "--strict",
        ],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    titles = [t for t, _ in sections(source)]
    generated = {"index.html", "404.html", "search.html", "sitemap.html"}
    pages = [
        p
        for p in output.rglob("*.html")
        if p.relative_to(output).as_posix() not in generated
        and not p.relative_to(output).parts[0] == "static"
    ]
    assert len(pages) == len(titles) - 1  # the first page is the home page, index.html
    # follow rel="next" from the home page: cmsimde's sequence of titles, in order
    page = output / "index.html"
    title = re.search(r"<title>(.*?)</title>", page.read_text(encoding="utf-8"), re.S).group(1)
    seen = [html.unescape(title)]
    for _ in range(len(titles) - 1):
        m = re.search(
            r'<a[^>]*rel="next"[^>]*href="([^"]+)"|<a[^>]*href="([^"]+)"[^>]*rel="next"',
            page.read_text(encoding="utf-8"),
        )
        assert m, f"no next link on {page}"
        page = (page.parent / unquote(m.group(1) or m.group(2))).resolve()
        title = re.search(r"<title>(.*?)</title>", page.read_text(encoding="utf-8"), re.S).group(1)
        seen.append(html.unescape(title))
    assert all(s.startswith(t) for s, t in zip(seen, titles, strict=True)), list(
        zip(seen, titles, strict=False)
    )
