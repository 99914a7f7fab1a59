"""A clip's ``title:`` heads its gallery entry and links its caption; the gallery and caption
labels (frames, seed, seconds, render failed) follow the site's language (sitegen/i18n.py).
Captions state the simulated length, the speed-up and the video's own length, so they agree
with the player (issue 26: "75.0 s" was printed under a 0:09 video)."""

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
    - {{name: rev, scenario: cart-reverse, seconds: 2, speed: 2, formats: [video],
       title: "Cart <backs> up"}}
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
    return gallery, home, out


def captions(html: str) -> list[str]:
    return [re.sub(r"<[^>]+>", "", c) for c in re.findall(r"<figcaption>(.*?)</figcaption>", html)]


def test_titles_head_the_gallery_and_link_the_captions_escaped(tmp_path):
    from sims.video import probe

    gallery, home, out = site(tmp_path, "en")
    heads = re.findall(r'<h2 id="clip-[^"]+-h">(.*?)</h2>', gallery)
    assert heads == ["Cart &lt;backs&gt; up", "plain", "Broken run"]
    links = re.findall(r'<figcaption>.*?<a href="[^"]*#clip-(\w+)">(.*?)</a>', home)
    assert links == [("rev", "Cart &lt;backs&gt; up"), ("plain", "plain"), ("broken", "Broken run")]
    assert "<backs>" not in home + gallery
    info, _ = probe(out / "clips" / "rev" / "clip.webm")
    assert (info.frames, info.fps) == (4, 4.0)  # a 1 s video of 2 simulated seconds
    caps = captions(home)
    assert caps[0] == "2.0 s simulated · 2× time-lapse · video 0:01 · Cart &lt;backs&gt; up"
    assert caps[1] == "1.0 s simulated · plain"  # a replay: played in simulated time
    assert "2.0 s simulated · 2× time-lapse · video 0:01 (4 frames, 64×48)" in gallery
    assert "seed 0" in gallery
    assert "{&#34;" not in gallery and "null" not in gallery  # parameters are not raw JSON
    assert "Renderer" not in gallery and "egl" not in gallery and "tinyrenderer" not in gallery
    assert "Broken run (render failed)" in caps[2]


def test_labels_follow_the_site_language(tmp_path):
    gallery, home, _ = site(tmp_path, "zh-TW")
    assert "模擬 2.0 秒 · 2× 快轉 · 影片 0:01 (4 影格, 64×48)" in gallery
    assert "亂數種子 " in gallery
    assert " frames" not in gallery and "seed " not in gallery and "simulated" not in gallery
    assert '<p lang="en">' in gallery  # the scenario's own English text is marked as English
    caps = captions(home)
    assert caps[0] == "模擬 2.0 秒 · 2× 快轉 · 影片 0:01 · Cart &lt;backs&gt; up"
    assert caps[1] == "模擬 1.0 秒 · plain"
    assert caps[2] == "Broken run (產生失敗)"
    assert "影片尚未產生" in home
