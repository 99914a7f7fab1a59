"""``sitegen import cmsimde`` brings a site's Pelican posts (markdown/*.md) and reveal decks
(reveal/*.html, *.md) along into blog/ and slides/, and the result builds."""

from __future__ import annotations

import re
from pathlib import Path

from sitegen_helpers import run_build, write_tree

from sitegen.importers.cmsimde import import_cmsimde
from sitegen.importers.pelican import parse_pelican

CONTENT = "<h1>About</h1><p>Course site.</p><h1>Week 1</h1><p>Notes.</p>"
POST = """Title: W3 進度 & 問題
Date: 2021-03-18 11:30
Category: cd2021
Tags: pybullet, 機器人
Slug: w3-progress
Author: 40823112
Summary: Cart runs in pybullet

本週完成 cart 的模擬，見 ![cart]({static}/images/cart.png)。

```python
print("ok")
```
"""
DECK = """<html><head><link rel="stylesheet" href="reveal.js/dist/reveal.css"></head><body>
<div class="reveal"><div class="slides">
<section><h1>第三週報告</h1><p>組員：甲</p></section>
<section>
  <section><h2>程式</h2><pre><code class="python">print("hi")</code></pre>
    <aside class="notes">先講程式</aside></section>
  <section><h2>結果</h2><p>It <em>works</em>.</p></section>
</section>
<section data-markdown><textarea data-template>
  ## Markdown slide
  - one
</textarea></section>
</div></div><script src="reveal.js/dist/reveal.js"></script></body></html>
"""


def make_cmsimde(root: Path, post: str = POST) -> Path:
    return write_tree(
        root,
        {
            "config/content.htm": CONTENT,
            "markdown/2021-03-18-w3.md": post,
            "markdown/pelicanconf.py": "AUTHOR = 'x'\n",
            "reveal/w3.html": DECK,
            "reveal/old.html": "<html><body><p>not a reveal deck</p></body></html>",
            "reveal/w4.md": "## W4\n\nfirst\n\n---\n\n## Next\n\nNote: say\n",
        },
    )


def test_parse_pelican_metadata_and_body_line():
    meta, body, line = parse_pelican("Title: A\nTags: x, y\n\n\nBody\n")
    assert meta == {"title": ("A", 1), "tags": ("x, y", 2)} and body == "Body\n" and line == 5


def test_import_brings_posts_and_decks_and_the_site_builds(tmp_path):
    src = make_cmsimde(tmp_path / "cms")
    dest = tmp_path / "site" / "content"
    report = import_cmsimde(src, dest)
    post = (dest / "blog/2021-03-18-w3.md").read_text(encoding="utf-8")
    assert post.startswith('---\ntitle: "W3 進度 & 問題"\ndate: "2021-03-18 11:30:00"\n')
    assert 'tags: ["pybullet", "機器人", "cd2021"]' in post  # the category is a tag too
    assert 'slug: "w3-progress"' in post and 'summary: "Cart runs in pybullet"' in post
    assert "*40823112*" in post  # the author kept as text, and said so
    assert "](../images/cart.png)" in post and "{static}" not in post
    deck = (dest / "slides/w3.md").read_text(encoding="utf-8")
    assert "slides: true" in deck
    body = deck.split("---\n", 2)[2]
    assert [p.strip().split("\n")[0] for p in re.split(r"^---$", body, flags=re.M)] == [
        "# 第三週報告",
        "## 程式",
        "## Markdown slide",
    ]
    assert "\n--\n" in body and "Note: 先講程式" in body and "It *works*." in body
    assert (dest / "slides/w4.md").read_text(encoding="utf-8").startswith("---\nslides: true\n")
    assert (dest / "reveal/old.html").is_file()  # not a deck we can read: copied, reported
    assert any("reveal/old.html" in w and "copied as it is" in w for w in report.warnings)
    paths = [p.path for p in report.pages]
    assert {"blog/2021-03-18-w3.md", "slides/w3.md", "slides/w4.md"} <= set(paths)
    assert any("Author" in w for w in report.warnings)

    (dest / "images").mkdir(exist_ok=True)
    (dest / "images/cart.png").write_bytes(b"\x89PNG\r\n\x1a\n")
    out = tmp_path / "out"
    run_build(dest.parent, out)
    assert (out / "blog/w3-progress.html").is_file()
    tag = (out / "blog/tags/機器人.html").read_text(encoding="utf-8")
    assert "W3 進度 &amp; 問題" in tag
    slides = (out / "slides/第三週報告.slides.html").read_text(encoding="utf-8")
    assert slides.count('<section class="slide"') == 4 and "先講程式" in slides


def test_a_pelican_date_that_does_not_parse_is_reported(tmp_path):
    src = make_cmsimde(tmp_path / "cms", POST.replace("2021-03-18 11:30", "18 March"))
    report = import_cmsimde(src, tmp_path / "site" / "content")
    assert any("Date '18 March' (line 2) is not a date" in w for w in report.warnings)
