"""cmsimde sites imported with nothing lost (issue 30): four real sites from 2020-2023, and one
test per defect they showed.

The real sites (../shared/data/sites2, SOURCES.md) come without their images and downloads,
so links to those files are the only build warnings allowed. Each defect is also built here
from a small site of our own with every file present, so the fix is checked end to end.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml
from browser_kit import WIDE, chromium, open_page, require_browser, static_server
from shared_data import shared
from sitegen_helpers import run_build, run_cli, write_tree

from sitegen.check import check_site
from sitegen.importers.cmsimde import import_cmsimde
from sitegen.importers.youtube import poster, video_id

SITES2 = {  # folder -> (repository, the number of pages cmsimde makes: one per H1-H3)
    "40923134_cd2022_guide": ("40923134/cd2022_guide", None),
    "mdecd2023_2a3-pj3ag1": ("mdecd2023/2a3-pj3ag1", None),
    "scrum-1_cd2023": ("scrum-1/cd2023", None),
    "mdecourse_cp2020": ("mdecourse/cp2020", 62),
}
HEADING = re.compile(r"<h([1-3])\b[^>]*>(.*?)</h\1\s*>", re.S | re.I)


def headings(content: str) -> int:
    return sum(1 for m in HEADING.finditer(content) if re.sub(r"<[^>]+>", "", m.group(2)).strip())


def project_config(project: Path) -> dict:
    text = (project / "sitegen.yml").read_text("utf-8")
    return yaml.safe_load(text)


@pytest.mark.parametrize("name", sorted(SITES2))
def test_real_site_imports_and_builds_with_only_absent_files_warned(name: str, tmp_path) -> None:
    site = shared("data", "sites2", name)
    repo, pages = SITES2[name]
    owner, repo_name = repo.split("/")
    project = tmp_path / "p"
    url = f"https://{owner.lower()}.github.io/{repo_name}/"
    report = import_cmsimde(site, project / "content", base_url=url)
    source = (site / "config" / "content.htm").read_text("utf-8")
    assert len(report.pages) == headings(source) == (pages or headings(source))
    config = project_config(project)
    assert config["base_url"] == url
    sitetitle = site / "config" / "sitetitle"
    if sitetitle.exists():  # cmsimde from 2023 on: the title is that file, not the first heading
        assert config["title"] == sitetitle.read_text("utf-8").strip() != "About"
    assert (project / "content" / "index.md").is_file()  # the first page is the home page

    out = tmp_path / "site"
    built = run_build(project, out)
    others = [
        str(d)
        for d in built.diagnostics
        if not re.search(
            r"link target '(\.\./)*(images|downloads)/[^']+' does not exist", d.message
        )
    ]
    assert others == []
    missing = [d for d in built.diagnostics if "does not exist" in d.message]
    for d in missing:  # each really is a file the folder does not have
        target = re.search(r"'((?:\.\./)*)((images|downloads)/[^']+)'", d.message).group(2)
        assert not (site / target).exists()
    home = (out / "index.html").read_text("utf-8")
    assert f"<title>{report.pages[0].title}" in home or report.pages[0].title in home


# --- each defect, on a site of our own ------------------------------------------------------

THREE_PAGE = """<!DOCTYPE html><html><head><link rel="stylesheet" href="3d.css">
<style>body{background:url('img/bg.png')}</style></head><body>
<script src="three.min.js"></script><script src='js/demo.js'></script>
<script type="importmap">{"imports": {"addons/": "./jsm/"}}</script>
<iframe src="inner.html"></iframe></body></html>"""


def demo_site(root: Path, content: str, **extra: str | bytes) -> Path:
    files: dict[str, str | bytes] = {"config/content.htm": content, **extra}
    return write_tree(root, files)


def test_image_in_a_pasted_pre_is_kept(tmp_path: Path) -> None:
    site = demo_site(
        tmp_path / "old",
        '<h1>A</h1><pre class="tw-data-text" dir="ltr"><span lang="zh-TW"> '
        '<img alt="" height="500" src="/images/計.jpg" width="760"/><br/></span>'
        "得分後球會回到中心</pre>\n",
        **{"images/計.jpg": b"jpg"},
    )
    project = tmp_path / "p"
    import_cmsimde(site, project / "content")
    page = (project / "content" / "index.md").read_text("utf-8")
    assert '<img alt="" height="500" src="images/計.jpg" width="760">' in page
    assert "得分後球會回到中心" in page
    out = tmp_path / "site"
    run_build(project, out, strict=True)
    assert 'src="images/計.jpg"' in (out / "index.html").read_text("utf-8")
    assert (out / "images" / "計.jpg").read_bytes() == b"jpg"
    assert check_site(out) == []


def test_backslashes_in_local_links_are_slashes(tmp_path: Path) -> None:
    site = demo_site(
        tmp_path / "old",
        '<h1>A</h1><p><a href="/downloads/nxopen\\block_ui\\x.mp4?t=1">video</a></p>\n',
        **{"downloads/nxopen/block_ui/x.mp4": b"mp4"},
    )
    project = tmp_path / "p"
    report = import_cmsimde(site, project / "content")
    assert "[video](downloads/nxopen/block_ui/x.mp4?t=1)" in (
        project / "content" / "index.md"
    ).read_text("utf-8")
    assert report.files_copied == ["downloads/nxopen/block_ui/x.mp4"]
    (said,) = [w for w in report.warnings if "backslashes" in w]
    assert "read as /downloads/nxopen/block_ui/x.mp4?t=1, as browsers do (line 1)" in said
    out = tmp_path / "site"
    run_build(project, out, strict=True)
    assert check_site(out) == []


def test_sitetitle_home_page_and_base_url_from_the_git_remote(tmp_path: Path) -> None:
    site = demo_site(
        tmp_path / "old",
        "<h1>About</h1><p>關於本站: 協同產品設計實習課程的分組網站, 記錄每週進度與心得.</p>"
        "<h2>Sub</h2><p>sub.</p><h1>B</h1><p>b.</p>\n",
        **{
            "config/sitetitle": "2023 Spring 協同產品設計實習",
            "config/config": "password:x\n",
            ".git/config": '[core]\n\tbare = false\n[remote "origin"]\n'
            "\turl = git@github.com:Scrum-1/cd2023.git\n",
        },
    )
    project = tmp_path / "p"
    report = import_cmsimde(site, project / "content")
    assert project_config(project) == {
        "title": "2023 Spring 協同產品設計實習",
        "language": "zh-TW",
        "base_url": "https://scrum-1.github.io/cd2023/",
    }
    assert [p.path for p in report.pages] == ["index.md", "01-sub.md", "02-b.md"]
    assert any("is the home page" in n for n in report.notes)
    assert any("from the site's GitHub remote" in n for n in report.notes)
    out = tmp_path / "site"
    run_build(project, out, strict=True)
    home = (out / "index.html").read_text("utf-8")
    assert "關於本站" in home and "2023 Spring 協同產品設計實習" in home
    # the 404 page finds its styles from any depth under /cd2023/ (templates/404.html)
    assert '"https://scrum-1.github.io/cd2023/"' in (out / "404.html").read_text("utf-8")
    # --base-url wins; a bad one stops the import with one line
    again = import_cmsimde(site, project / "content", force=True, base_url="https://mde.tw/x")
    assert project_config(project)["base_url"] == "https://scrum-1.github.io/cd2023/"  # kept
    assert any("left unchanged" in w for w in again.warnings)
    done = run_cli(
        "import", "cmsimde", str(site), "--dest", str(tmp_path / "q" / "c"), "--base-url", "mde.tw"
    )
    assert done.returncode == 1 and "not an http(s) address" in done.stderr


def test_iframed_local_page_is_copied_with_what_it_loads(tmp_path: Path) -> None:
    site = demo_site(
        tmp_path / "old",
        '<h1>A</h1><p><iframe src="/downloads/threejs_ex/index.html" width="300"></iframe></p>\n',
        **{
            "downloads/threejs_ex/index.html": THREE_PAGE,
            "downloads/threejs_ex/3d.css": "@import 'base.css'; h1{background:url(img/t.png)}",
            "downloads/threejs_ex/base.css": "body{margin:0}",
            "downloads/threejs_ex/img/t.png": b"t",
            "downloads/threejs_ex/img/bg.png": b"bg",
            "downloads/threejs_ex/three.min.js": "var THREE={};",
            "downloads/threejs_ex/js/demo.js": "import {x} from './util.js';\n"
            "loader.load( 'jansen-asm.obj', f ); var s = 'not/a/file.txt';",
            "downloads/threejs_ex/js/util.js": "export const x = 1;",
            "downloads/threejs_ex/jansen-asm.obj": "v 0 0 0",
            "downloads/threejs_ex/inner.html": (
                '<img src="../../images/logo.png"><img src="gone.png">'
            ),
            "images/logo.png": b"logo",
            "downloads/threejs_ex/unused.txt": "not loaded by anything",
        },
    )
    project = tmp_path / "p"
    report = import_cmsimde(site, project / "content")
    copied = set(report.files_copied)
    demo = "downloads/threejs_ex/"
    assert {
        demo + f
        for f in (
            "index.html",
            "3d.css",
            "base.css",
            "img/t.png",
            "img/bg.png",
            "three.min.js",
            "js/demo.js",
            "js/util.js",
            "jansen-asm.obj",
            "inner.html",
        )
    } | {"images/logo.png"} == copied
    page = report.pages[0]
    assert any("10 file(s) it loads copied" in n for n in page.notes)
    assert [w for w in page.warnings if "iframed page" in w] == [
        "iframed page downloads/threejs_ex/inner.html loads gone.png, which is not in the "
        "site (line 1)"
    ]
    out = tmp_path / "site"
    run_build(project, out)
    problems = check_site(out)
    assert problems == ["downloads/threejs_ex/inner.html:1: 'gone.png' not found"]


def test_youtube_iframes_become_posters_unless_kept(tmp_path: Path) -> None:
    site = demo_site(
        tmp_path / "old",
        "<h1>Videos</h1><p>影片說明文字, 這是一段中文的說明.</p>"
        '<p><iframe width="560" height="315" src="https://www.youtube.com/embed/dQw4w9WgXcQ?'
        'start=30&amp;si=abc" title="YouTube video player" allowfullscreen></iframe></p>'
        '<div><iframe src="//youtu.be/abcdefghijk" title="W5 齒輪"></iframe></div>\n',
    )
    project = tmp_path / "p"
    report = import_cmsimde(site, project / "content")
    page = (project / "content" / "index.md").read_text("utf-8")
    assert page.count('class="youtube-poster"') == 2
    assert "youtube.com/embed" not in page and ' src="' not in page
    assert "https://www.youtube-nocookie.com/embed/dQw4w9WgXcQ" in page
    assert "name=&quot;start&quot; value=&quot;30&quot;" in page and "si=" not in page
    assert report.youtube_posters == 2
    assert [n.split(" (line")[0] for n in report.pages[0].notes] == [
        "YouTube video dQw4w9WgXcQ made a click-to-load poster",
        "YouTube video abcdefghijk made a click-to-load poster",
    ]
    assert any("--youtube keep" in n for n in report.notes)
    kept = import_cmsimde(site, tmp_path / "k" / "content", youtube="keep")
    text = (tmp_path / "k" / "content" / "index.md").read_text("utf-8")
    assert 'src="https://www.youtube.com/embed/dQw4w9WgXcQ?start=30&amp;si=abc"' in text
    assert kept.youtube_posters == 0
    out = tmp_path / "site"
    run_build(project, out, strict=True)
    assert check_site(out) == []


@pytest.mark.parametrize(
    ("src", "found"),
    [
        ("https://www.youtube.com/embed/dQw4w9WgXcQ", ("dQw4w9WgXcQ", {})),
        ("//www.youtube-nocookie.com/embed/dQw4w9WgXcQ?rel=0", ("dQw4w9WgXcQ", {"rel": "0"})),
        ("https://youtu.be/dQw4w9WgXcQ?t=1m5s", ("dQw4w9WgXcQ", {"start": "65"})),
        ("https://m.youtube.com/watch?v=dQw4w9WgXcQ&list=PL1", ("dQw4w9WgXcQ", {"list": "PL1"})),
        ("https://www.youtube.com/embed/videoseries?list=PL1", ("videoseries", {"list": "PL1"})),
        ("https://vimeo.com/123", None),
        ("http://[bad", None),
    ],
)
def test_youtube_urls(src: str, found) -> None:
    assert video_id(src) == found
    assert (poster(src, "", "", "", "en") is None) == (found is None)


def test_youtube_poster_loads_nothing_until_play_is_pressed(tmp_path: Path) -> None:
    """In Chromium, JavaScript off: the page asks nothing of YouTube; the Play button (a real
    button with a name) sends the frame to youtube-nocookie.com, and only then."""
    require_browser()
    site = demo_site(
        tmp_path / "old",
        '<h1>V</h1><p><iframe src="https://www.youtube.com/embed/dQw4w9WgXcQ" '
        'title="Gear demo"></iframe></p>\n',
    )
    project = tmp_path / "p"
    import_cmsimde(site, project / "content")
    out = tmp_path / "site"
    run_build(project, out, strict=True)
    with chromium() as browser, static_server(out) as base:
        with open_page(browser, WIDE, out, js=False) as page:
            page.goto(base + "index.html")
            page.wait_for_load_state("networkidle")
            assert page.watch.outside == []
            frame = page.frame_locator("iframe.youtube-poster")
            button = frame.get_by_role(
                "button", name="Play video: Gear demo (loads the YouTube player)"
            )
            assert button.is_visible()
            with page.expect_request(re.compile(r"youtube-nocookie")) as asked:
                button.click()
            assert (
                asked.value.url == "https://www.youtube-nocookie.com/embed/dQw4w9WgXcQ?autoplay=1"
            )
            for _ in range(40):  # the blocked request reaches the watch just after
                if page.watch.outside:
                    break
                page.wait_for_timeout(50)
            assert page.watch.outside == [asked.value.url]  # that one request, after the press
            page.watch.outside.clear()
