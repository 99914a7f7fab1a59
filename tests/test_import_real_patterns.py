"""Real cmsimde sites in, without loss (issue 13): malformed URLs, links inside code, external
resources checked for form only, the site's title and language, root-absolute downloads; and
an asset whose name holds ``#`` (issue 15).

The fixture ``tests/fixtures/cmsimde/patterns`` is a small cmsimde site holding each pattern;
the 300 KB site with one malformed URL is generated here.
"""

from __future__ import annotations

import html
import re
from pathlib import Path

import markdown
import pytest
import yaml
from shared_data import shared
from sitegen_helpers import run_build, run_cli, write_tree

from sitegen.check import check_site
from sitegen.errors import BuildError
from sitegen.importers.cmsimde import import_cmsimde
from sitegen.importers.project_config import detect_language

PATTERNS = Path(__file__).parent / "fixtures" / "cmsimde" / "patterns"
MALFORMED = "http://user:pw@[proxy_ipv6_address]port"
MD_EXTS = ["fenced_code", "tables", "footnotes", "attr_list", "def_list", "sane_lists"]
PRE = re.compile(r"<pre\b[^>]*>(.*?)</pre>", re.S)
TAG = re.compile(r"<[^>]+>")


def imported(tmp_path: Path, source: Path = PATTERNS) -> Path:
    """Import ``source`` into ``tmp_path/project/content``; return the project folder."""
    project = tmp_path / "project"
    import_cmsimde(source, project / "content")
    return project


def code_texts(page_html: str) -> list[str]:
    """The text of every <pre> block as a reader sees it (highlighting markup removed)."""
    return [html.unescape(TAG.sub("", block)).strip("\n") for block in PRE.findall(page_html)]


def source_code_texts(md_file: Path) -> list[str]:
    """The code blocks of a Markdown source, rendered by plain Python-Markdown (no sitegen)."""
    text = md_file.read_text(encoding="utf-8")
    if text.startswith("---\n"):
        text = text.split("\n---\n", 1)[1]
    return code_texts(markdown.markdown(text, extensions=MD_EXTS))


def assert_code_unchanged(content: Path, site: Path) -> int:
    """Every code block of every page of the built site reads exactly as in its source."""
    source = sorted(c for md in content.rglob("*.md") for c in source_code_texts(md))
    built = sorted(c for page in site.rglob("*.html") for c in code_texts(page.read_text("utf-8")))
    assert built == source
    return len(source)


# --- links inside code, external resources, check == build --strict ------------------------


def test_code_is_never_rewritten_and_check_agrees_with_strict_build(tmp_path: Path) -> None:
    project = imported(tmp_path)
    site = tmp_path / "site"
    report = run_build(project, site, strict=True)  # raises BuildError on any warning
    assert report.pages == 4  # the first page, 首頁, is the home page
    assert assert_code_unchanged(project / "content", site) == 3
    w1 = (site / "w1" / "index.html").read_text("utf-8")
    # inline code keeps the cmsimde path, not "../images/missing.png", and raises no warning
    assert '<code>&lt;img src="/images/missing.png"&gt;</code>' in w1
    # the YouTube iframe is a click-to-load poster (issue 30): no YouTube URL in a src;
    # external images pass both checks; //host became https://host
    video = (site / "w1" / "影片.html").read_text("utf-8")
    assert 'data-youtube="dQw4w9WgXcQ"' in video and "youtube.com/embed" not in video
    assert 'src="https://mde.tw/images/nfu.png"' in video and 'src="//' not in video
    assert check_site(site) == []
    done = run_cli("check", str(site))
    assert done.returncode == 0 and "0 problem(s)" in done.stderr


def test_markdown_code_samples_are_kept_exactly(tmp_path: Path) -> None:
    sample = '<a href="/images/a.png">x</a> <img src=\'b.png\'> <video poster="c.png">'
    content = {
        "sitegen.yml": "title: T\n",
        "content/index.md": "# Home\n\n[page](p.md)\n",
        "content/p.md": (
            f"# Page\n\n```\n{sample}\n```\n\n```html\n{sample}\n```\n\n"
            f'Inline `{sample}` and\n\n    {sample}\n\n<!-- <a href="gone.md">x</a> -->\n'
        ),
    }
    project = write_tree(tmp_path / "p", content)
    site = tmp_path / "site"
    run_build(project, site, strict=True)
    assert assert_code_unchanged(project / "content", site) == 3
    page = (site / "page.html").read_text("utf-8")
    assert f"<code>{html.escape(sample, quote=False)}</code>" in page


def test_protocol_relative_url_in_markdown_becomes_https(tmp_path: Path) -> None:
    project = write_tree(
        tmp_path / "p",
        {"sitegen.yml": "title: T\n", "content/index.md": '# H\n\n<img src="//mde.tw/x.png">\n'},
    )
    run_build(project, tmp_path / "site", strict=True)
    assert 'src="https://mde.tw/x.png"' in (tmp_path / "site" / "index.html").read_text()


# --- malformed URLs -------------------------------------------------------------------------


def generated_site(folder: Path, target_bytes: int = 300_000) -> tuple[Path, list[str], int]:
    """A cmsimde content.htm of about ``target_bytes`` with one malformed URL.

    Returns (file, every heading title, the line of the malformed link).
    """
    parts, titles = [], []
    n = 0
    bad_line = 0
    while sum(len(p.encode()) for p in parts) < target_bytes:
        n += 1
        level = 1 if n % 7 == 1 else (2 if n % 3 else 3)
        title = f"W{n} 第{n}週進度"
        titles.append(title)
        parts.append(f"<h{level}>{title}</h{level}>\n")
        parts.append(
            "<p>" + "本週完成齒輪機構的設計與模擬, 並整理報告與影片. " * 12 + "</p>\n"
            f'<p><a href="https://github.com/mdecourse/cd2021/issues/{n}">issue {n}</a></p>\n'
            '<pre class="brush:py">for i in range(10):\n    print(i)</pre>\n'
        )
        if n == 40:
            bad_line = sum(p.count("\n") for p in parts) + 1
            parts.append(f'<p>代理伺服器: <a href="{MALFORMED}">proxy</a></p>\n')
    file = folder / "content.htm"
    folder.mkdir(parents=True, exist_ok=True)
    file.write_text("".join(parts), encoding="utf-8")
    return file, titles, bad_line


def test_300kb_site_with_a_malformed_url_imports_every_page(tmp_path: Path) -> None:
    file, titles, bad_line = generated_site(tmp_path / "old")
    assert file.stat().st_size >= 300_000
    report = import_cmsimde(file, tmp_path / "project" / "content")
    assert [p.title for p in report.pages] == titles
    for page in report.pages:
        assert (tmp_path / "project" / "content" / page.path).is_file()
    (warning,) = [w for w in report.warnings if MALFORMED in w]
    assert warning.startswith(f"W40 第40週進度: link '{MALFORMED}': malformed URL")
    assert warning.endswith(
        f"its text is kept, not as a link (the URL is in a comment beside it) (line {bad_line})"
    )
    page = next(p for p in report.pages if p.title == "W40 第40週進度")
    text = (tmp_path / "project" / "content" / page.path).read_text("utf-8")
    # a browser cannot follow it either: the text stays, the URL is kept beside it (issue 30)
    assert f"proxy<!-- link URL that does not parse: {MALFORMED} -->" in text

    # so the imported site builds with --strict, and the comment reaches the page unchanged
    site = tmp_path / "site"
    run_build(tmp_path / "project", site, strict=True)
    assert check_site(site) == []


def test_a_malformed_url_written_in_markdown_is_reported_by_build_and_check(
    tmp_path: Path,
) -> None:
    project = write_tree(
        tmp_path / "p",
        {"sitegen.yml": "title: T\n", "content/index.md": f"# H\n\ntext\n\n[proxy]({MALFORMED})\n"},
    )
    site = tmp_path / "site"
    with pytest.raises(BuildError):
        run_build(project, site, strict=True)
    done = run_cli("build", "--source", str(project), "--output", str(site))
    assert done.returncode == 0 and "Traceback" not in done.stderr
    (line,) = [ln for ln in done.stderr.splitlines() if MALFORMED in ln]
    assert "content/index.md:5: warning: link: malformed URL" in line
    checked = check_site(site)
    assert [p for p in checked if MALFORMED in p] and all("Traceback" not in p for p in checked)


def test_check_reports_malformed_and_hostless_urls_without_traceback(tmp_path: Path) -> None:
    site = write_tree(
        tmp_path / "site",
        {
            "index.html": (
                f'<a href="{MALFORMED}">a</a>\n<img src="http:///x.png">\n'
                '<a href="https://host:port/">p</a>\n<iframe src="https://youtu.be/x"></iframe>\n'
            )
        },
    )
    problems = check_site(site)
    assert len(problems) == 3
    assert problems[0].startswith("index.html:1: <a href>: malformed URL")
    assert problems[1].startswith("index.html:2: <img src>: URL 'http:///x.png' has no host")
    assert problems[2].startswith("index.html:3:")


# --- title, language, downloads -----------------------------------------------------------


def test_import_writes_sitegen_yml_with_title_and_language(tmp_path: Path) -> None:
    project = imported(tmp_path)
    config = yaml.safe_load((project / "sitegen.yml").read_text("utf-8"))
    assert config == {"title": "40823999 cd2021 協同產品設計", "language": "zh-TW"}
    site = tmp_path / "site"
    run_build(project, site)
    page = (site / "index.html").read_text("utf-8")
    assert '<html lang="zh-TW"' in page and "40823999 cd2021 協同產品設計" in page
    # an existing sitegen.yml (it may hold rosters) is never replaced; the report says so
    (project / "sitegen.yml").write_text("title: Mine\n", encoding="utf-8")
    again = import_cmsimde(PATTERNS, project / "content", force=True)
    assert (project / "sitegen.yml").read_text() == "title: Mine\n"
    assert any("sitegen.yml" in w and "left unchanged" in w for w in again.warnings)


def test_import_into_another_folder_names_it_in_sitegen_yml(tmp_path: Path) -> None:
    import_cmsimde(PATTERNS, tmp_path / "old-site")
    config = yaml.safe_load((tmp_path / "sitegen.yml").read_text("utf-8"))
    assert config["content_dir"] == "old-site"
    run_build(tmp_path, tmp_path / "site", strict=True)


def test_language_detection() -> None:
    assert detect_language(["本週完成齒輪機構的設計與模擬, 並整理報告與影片." * 3]) == "zh-TW"
    code = "```python\n" + "print('hello world')\n" * 50 + "```\n"
    assert detect_language([code + "第一週進度與心得報告整理完成了嗎? 是的已經完成了"]) == "zh-TW"
    assert detect_language(["An English page that names 齒輪 once. " * 20]) == "en"


def test_root_absolute_downloads_become_relative_or_warn(tmp_path: Path) -> None:
    old = tmp_path / "old"
    write_tree(
        old,
        {
            "config/content.htm": (
                '<h1>A</h1><p><a href="/downloads/vrep_remoteapi_ex.7z">ok</a></p>\n'
                '<h1>B</h1><h2>C</h2><p><a href="/downloads/gone.7z">gone</a></p>\n'
            ),
            "downloads/vrep_remoteapi_ex.7z": b"7z",
        },
    )
    report = import_cmsimde(old, tmp_path / "p" / "content")
    content = tmp_path / "p" / "content"
    assert (content / "downloads" / "vrep_remoteapi_ex.7z").read_bytes() == b"7z"
    assert "[ok](downloads/vrep_remoteapi_ex.7z)" in (content / "index.md").read_text()
    assert "[gone](../downloads/gone.7z)" in (content / "02-b" / "01-c.md").read_text()
    assert "C: link /downloads/gone.7z names downloads/gone.7z, which is not in the site" in (
        "\n".join(report.warnings)
    )


# --- issue 15: an asset named a#b.png -------------------------------------------------------


def test_asset_with_hash_in_its_name_gets_a_working_link(tmp_path: Path) -> None:
    project = write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": "title: T\n",
            "content/index.md": "# H\n\n![a](a%23b.png) [l](sub/c%23d.png#x)\n",
            "content/a#b.png": b"png",
            "content/sub/c#d.png": b"png",
        },
    )
    site = tmp_path / "site"
    run_build(project, site, strict=True)
    page = (site / "index.html").read_text("utf-8")
    assert 'src="a%23b.png"' in page and 'href="sub/c%23d.png#x"' in page
    assert check_site(site) == []


# --- the real sites: code text survives import and build ------------------------------------


@pytest.mark.parametrize(
    "name",
    ["content_40823111.htm", "content_40823145.htm", "content_40823245.htm"],
)
def test_real_sites_code_text_survives_import_and_build(tmp_path: Path, name: str) -> None:
    source = shared("data", "cmsimde-sites", name)
    project = imported(tmp_path, source)
    site = tmp_path / "site"
    run_build(project, site)
    assert assert_code_unchanged(project / "content", site) > 0
