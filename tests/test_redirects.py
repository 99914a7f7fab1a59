"""Old URLs keep working: ``aliases:`` redirect pages, and the warning when a page moved."""

from __future__ import annotations

import html
import re
from pathlib import Path

import pytest
from sitegen_helpers import run_build, run_cli, write_tree

from sitegen.check import check_site
from sitegen.errors import BuildError
from sitegen.redirects import alias_path


def page(title: str, aliases: str = "", body: str = "Text.\n") -> str:
    extra = f"aliases: {aliases}\n" if aliases else ""
    return f"---\ntitle: {title}\n{extra}---\n{body}"


def make_site(root: Path, pages: dict[str, str], config: str = "title: T\n") -> Path:
    return write_tree(
        root, {"sitegen.yml": config, **{f"content/{k}": v for k, v in pages.items()}}
    )


def redirect_target(file: Path) -> tuple[str, str, str]:
    """(refresh URL, canonical href, plain link href) of a redirect page."""
    text = file.read_text(encoding="utf-8")
    refresh = re.search(r'http-equiv="refresh" content="0; url=([^"]*)"', text).group(1)
    canonical = re.search(r'<link rel="canonical" href="([^"]*)"', text).group(1)
    link = re.search(r'<body>\s*<p><a href="([^"]*)"', text).group(1)
    assert '<meta name="robots" content="noindex">' in text
    return html.unescape(refresh), html.unescape(canonical), html.unescape(link)


def test_each_alias_becomes_a_relative_redirect_to_the_page(tmp_path):
    src = make_site(
        tmp_path / "src",
        {
            "w/week.md": page("Week One", "[old/week.html, /w1/, legacy, old%20name.html]"),
        },
    )
    out = tmp_path / "out"
    run_build(src, out)
    target = "w/week-one.html"
    assert (out / target).is_file()
    assert redirect_target(out / "old/week.html") == ("../" + target,) * 3
    assert redirect_target(out / "w1/index.html") == ("../" + target,) * 3
    assert redirect_target(out / "legacy/index.html") == ("../" + target,) * 3
    assert redirect_target(out / "old name.html")[0] == target  # the decoded file name
    assert check_site(out) == []  # every redirect's links resolve


def test_canonical_is_absolute_with_base_url_and_titles_are_escaped(tmp_path):
    src = make_site(
        tmp_path / "src",
        {"p.md": page('"<b>Bold</b>"', "[was.html]")},
        config="title: T\nbase_url: https://u.github.io/repo/\n",
    )
    out = tmp_path / "out"
    run_build(src, out)
    text = (out / "was.html").read_text(encoding="utf-8")
    assert "<b>" not in text and "&lt;b&gt;Bold&lt;/b&gt;" in text
    refresh, canonical, _ = redirect_target(out / "was.html")
    assert refresh == "b-bold-b.html"
    assert canonical == "https://u.github.io/repo/b-bold-b.html"


def test_redirect_output_is_deterministic(tmp_path):
    src = make_site(tmp_path / "src", {"p.md": page("P", "[a.html, b/]")})
    run_build(src, tmp_path / "o1")
    run_build(src, tmp_path / "o2", clean=True)
    for rel in ("a.html", "b/index.html"):
        assert (tmp_path / "o1" / rel).read_bytes() == (tmp_path / "o2" / rel).read_bytes()


@pytest.mark.parametrize(
    ("raw", "problem"),
    [
        ("../up.html", "not a plain relative path"),
        ("a/./b.html", "not a plain relative path"),
        ("a//b.html", "not a plain relative path"),
        ("http://example.com/x.html", "scheme"),
        ("javascript:alert(1)", "scheme"),
        ("//evil.example/x", "another host"),
        ("x.html?a=1", "query or fragment"),
        ("a%2F..%2Fb", "not a plain relative path"),
        ("a\\b.html", "backslash"),
    ],
)
def test_unsafe_alias_is_refused(raw, problem):
    path, why = alias_path(raw)
    assert path is None and problem in why


def test_unsafe_alias_is_an_error_naming_file_line_and_field(tmp_path):
    src = make_site(
        tmp_path / "src",
        {"p.md": "---\ntitle: P\naliases:\n  - fine.html\n  - ../../etc/x.html\n---\nText.\n"},
    )
    out = tmp_path / "out"
    with pytest.raises(BuildError) as info:
        run_build(src, out)
    lines = [d.format() for d in info.value.diagnostics]
    assert lines == [
        "content/p.md:5: error: aliases: '../../etc/x.html' is not a plain relative path "
        "(no '..', '.' or empty parts)"
    ]
    assert not (out / "fine.html").exists()  # nothing published from a failed build


def test_alias_colliding_with_a_page_or_another_alias_is_an_error(tmp_path):
    src = make_site(
        tmp_path / "src",
        {
            "a.md": page("Alpha", "[beta.html, shared.html]"),
            "b.md": "---\ntitle: Beta\naliases:\n  - shared.html\n  - assets/style.css.html\n"
            "  - search.html\n  - files/notes.html\n---\nText.\n",
            "files/notes.html": "<p>a file of the site</p>",
        },
    )
    with pytest.raises(BuildError) as info:
        run_build(src, tmp_path / "out")
    got = sorted(d.format() for d in info.value.diagnostics)
    assert got == [
        "content/a.md:3: error: aliases: 'beta.html' is the URL of the page 'Beta' (beta.html); "
        "an alias must be an old URL",
        "content/b.md:4: error: aliases: 'shared.html' names the same file (shared.html) "
        "as the alias at content/a.md:3",
        "content/b.md:5: error: aliases: 'assets/style.css.html' is inside 'assets/', "
        "which the build fills",
        "content/b.md:6: error: aliases: 'search.html' is the path of a page the build makes",
        "content/b.md:7: error: aliases: 'files/notes.html' is the path of the file "
        "content/files/notes.html",
    ]


def test_cli_reports_alias_error_without_traceback(tmp_path):
    src = make_site(tmp_path / "src", {"p.md": page("P", "[p.html]")})
    result = run_cli("build", "--source", str(src))
    assert result.returncode != 0
    assert "Traceback" not in result.stderr
    assert "content/p.md:3: error: aliases: 'p.html' is the URL of this page" in result.stderr


def test_title_change_warns_with_the_alias_to_add_and_strict_fails(tmp_path):
    src = make_site(tmp_path / "src", {"notes.md": page("First Title")})
    out = tmp_path / "out"
    first = run_build(src, out)
    assert first.diagnostics == []
    (src / "content/notes.md").write_text(page("Second Title"), encoding="utf-8")

    with pytest.raises(BuildError) as info:
        run_build(src, out, strict=True)
    want = (
        "content/notes.md: warning: url: URL changed from first-title.html to "
        "second-title.html; add `aliases: [first-title.html]` to keep old links working"
    )
    assert [d.format() for d in info.value.diagnostics] == [want]
    assert (out / "first-title.html").is_file()  # the failed build left the old site

    cli = run_cli("build", "--strict", "--source", str(src), "--output", str(out))
    assert cli.returncode == 1 and want in cli.stderr and "Traceback" not in cli.stderr

    report = run_build(src, out)  # without --strict: built, warned once
    assert [d.format() for d in report.diagnostics] == [want]
    assert (out / "second-title.html").is_file()
    assert run_build(src, out).diagnostics == []  # the new URL is now the remembered one


def test_adding_the_suggested_alias_silences_the_warning(tmp_path):
    src = make_site(tmp_path / "src", {"notes.md": page("First Title")})
    out = tmp_path / "out"
    run_build(src, out)
    (src / "content/notes.md").write_text(
        page("Second Title", "[first-title.html]"), encoding="utf-8"
    )
    report = run_build(src, out, strict=True)
    assert report.diagnostics == []
    assert redirect_target(out / "first-title.html")[0] == "second-title.html"
