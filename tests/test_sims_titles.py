"""A clip's ``title:`` heads its gallery entry and links its caption; the gallery and caption
labels (frames, seed, seconds, render failed) follow the site's language (sitegen/i18n.py)."""

from __future__ import annotations

import re

from sitegen_helpers import write_tree

from sitegen.build import BuildOptions, build

BROKEN = 'import sim\n\nraise RuntimeError("no wheels")\n'


def site(root, language: str):
    config = f"""title: t
language: {language}
sims:
  size: 64x48
  fps: 4
  clips:
    - {{name: rev, scenario: cart-reverse, seconds: 2, title: "Cart <backs> up"}}
    - {{name: plain, scenario: cart-reverse, seconds: 1}}
    - {{name: broken, script: broken.py, scene: cart, seconds: 1, title: Broken run}}
"""
    source = write_tree(
        root / "src",
        {
            "sitegen.yml": config,
            "broken.py": BROKEN,
            "content/index.md": "# Home\n\n::: clip rev\n\n::: clip plain\n\n::: clip broken\n",
        },
    )
    out = root / "site"
    build(BuildOptions(source=source, output=out, log=lambda line: None))
    gallery = (out / "gallery" / "index.html").read_text(encoding="utf-8")
    home = (out / "index.html").read_text(encoding="utf-8")
    return gallery, home


def captions(html: str) -> list[str]:
    return [re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<figcaption>(.*?)</figcaption>", html)]


def test_titles_head_the_gallery_and_link_the_captions_escaped(tmp_path):
    gallery, home = site(tmp_path, "en")
    heads = re.findall(r'<h2 id="clip-[^"]+-h">(.*?)</h2>', gallery)
    assert heads == ["Cart &lt;backs&gt; up", "plain", "Broken run"]
    links = re.findall(r'<figcaption>.*?<a href="[^"]*#clip-(\w+)">(.*?)</a>', home)
    assert links == [("rev", "Cart &lt;backs&gt; up"), ("plain", "plain"), ("broken", "Broken run")]
    assert "<backs>" not in home + gallery
    assert re.search(r"\d\.\d s · \d+ frames · 64×48", gallery)
    assert "seed " in gallery
    assert captions(home)[0].endswith(
        " s · Cart <backs> up".replace("<", "&lt;").replace(">", "&gt;")
    )
    assert "Broken run (render failed)" in captions(home)[2]


def test_labels_follow_the_site_language(tmp_path):
    gallery, home = site(tmp_path, "zh-TW")
    assert re.search(r"\d\.\d 秒 · \d+ 影格 · 64×48", gallery)
    assert "亂數種子 " in gallery
    assert " frames" not in gallery and "seed " not in gallery
    caps = captions(home)
    assert re.search(r"\d\.\d 秒 · Cart &lt;backs&gt; up$", caps[0])
    assert caps[2] == "Broken run (產生失敗)"
    assert "影片尚未產生" in home
