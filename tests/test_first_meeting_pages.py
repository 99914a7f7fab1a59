"""Pages as a newcomer first reads them (issue 26): a title taken from a heading reads as the
heading does (no Markdown markup), a blog post without ``summary:`` has the same excerpt on the
blog's lists as in its feed, and the documentation site is called by its name."""

from __future__ import annotations

import re
import shutil

from sitegen_helpers import REPO, run_build, run_cli, write_tree

from sitegen.blog import SUMMARY_CHARS, excerpt
from sitegen.page_text import first_heading, plain_title


def test_titles_from_headings_have_no_markdown_markup(tmp_path):
    assert plain_title("Preview: `sitegen serve`") == "Preview: sitegen serve"
    assert (
        plain_title("Rosters (`roster/`) and **more** [here](x.md)")
        == "Rosters (roster/) and more here"
    )
    assert plain_title("keep snake_case_names and 2*3") == "keep snake_case_names and 2*3"
    assert first_heading("# The `sims` package\n")[0] == "The sims package"
    src = write_tree(
        tmp_path / "s", {"index.md": "# Home\n", "a.md": "# Using `sitegen.yml`\n\nx\n"}
    )
    out = tmp_path / "o"
    run_build(src, out)
    page = next(out.glob("using-sitegen*.html")).read_text(encoding="utf-8")
    assert "<title>Using sitegen.yml · " in page and "<h1>Using sitegen.yml</h1>" in page
    assert "`" not in (out / "index.html").read_text(encoding="utf-8")


def test_blog_lists_show_the_feeds_excerpt(tmp_path):
    body = "We **set up** the `tools` and [the site](../index.md) this week.\n\n```\ncode\n```\n"
    src = write_tree(
        tmp_path / "s",
        {
            "sitegen.yml": "title: B\nbase_url: https://example.org/b/\n",
            "content/index.md": "# Home\n",
            "content/blog/p.md": f"---\ndate: 2024-01-02\n---\n# A post\n\n{body}",
        },
    )
    run_build(src, tmp_path / "o")
    index = (tmp_path / "o/blog/index.html").read_text(encoding="utf-8")
    feed = (tmp_path / "o/feed.xml").read_text(encoding="utf-8")
    words = "We set up the tools and the site this week."
    assert f"<p>{words}</p>" in index
    assert f"<summary>{words}</summary>" in feed
    long = excerpt("# T\n\n" + "word " * 200)
    assert long.endswith("…") and len(long) <= SUMMARY_CHARS + 1
    assert excerpt("中文" * 300).endswith("…")


def test_the_documentation_site_has_its_name(tmp_path):
    docs = shutil.copytree(REPO / "docs", tmp_path / "docs", ignore=shutil.ignore_patterns(".*"))
    out = tmp_path / "docs-site"
    done = run_cli("build", "--strict", "--source", str(docs), "--output", str(out))
    assert done.returncode == 0, done.stderr
    home = (out / "index.html").read_text(encoding="utf-8")
    assert re.search(r"<title>[^<]* · sitegen documentation</title>", home)
    assert not (out / "sitegen.yml").exists(), "the docs' settings are not a page of the site"
    headings = "".join(p.read_text(encoding="utf-8") for p in out.glob("*.html"))
    assert not re.search(r"<h1>[^<]*`", headings) and not re.search(r"<title>[^<]*`", headings)
