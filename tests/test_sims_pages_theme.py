"""The gallery and clip figures come from the theme (``partials/gallery.html``,
``partials/clip.html``): escaped by default, and a project's templates replace them.

The integration's results are set as its ``prepare`` sets them (no clip is rendered here: the
markup, not the renderer, is under test; tests/test_sims_site_clips.py builds real clips)."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

from sims.clips import ClipResult
from sitegen.config import ClipConfig, Config, SimsConfig
from sitegen.i18n import strings
from sitegen.output import OutFile
from sitegen.sims_pages import SimsIntegration

META = {
    "width": 320,
    "height": 240,
    "duration": 5,
    "frames": 100,
    "fps": 20,
    "seed": 7,
    "params": {"speed": 2},
    "renderer": "egl",
    "description": "Cart <drives> & stops",
}


def integration(root: Path, templates: dict[str, str] | None = None) -> SimsIntegration:
    for rel, text in (templates or {}).items():
        (root / "templates" / rel).parent.mkdir(parents=True, exist_ok=True)
        (root / "templates" / rel).write_text(text, encoding="utf-8")
    clips = (
        ClipConfig(name="cart", scenario="cart-reverse", title="Cart <i>"),
        ClipConfig(name="broken", scenario="two-wheel"),
    )
    config = Config(root=root, source_file=root / "sitegen.yml", sims=SimsConfig(clips=clips))
    opts = SimpleNamespace(log=lambda line: None, is_tty=False, retry_failed=False)
    integ = SimsIntegration(config, root / "cache", opts)
    integ.results = {"cart": ClipResult("cart", True, stale=True, meta=META)}
    integ.failed = {"broken": 'scene has no "<robot>"'}
    for name in ("clip.webm", "poster.png", "data.csv", "path.svg"):
        integ._files[f"clips/cart/{name}"] = OutFile("digest")
    return integ


def gallery(integ: SimsIntegration) -> str:
    return integ.pages(strings("en"))[0].body_html


def test_default_gallery_and_figures_escape_and_link(tmp_path):
    integ = integration(tmp_path)
    body = gallery(integ)
    assert body.count('<section class="gallery-item">') == 2
    assert '<h2 id="clip-cart-h">Cart &lt;i&gt;</h2>' in body
    assert '<source src="../clips/cart/clip.webm" type="video/webm; codecs=vp8"></video>' in body
    assert "clip.mp4" not in body  # no MP4 file: no source for it
    assert 'poster="../clips/cart/poster.png"' in body
    assert '<p lang="en">Cart &lt;drives&gt; &amp; stops</p>' not in body  # an English site
    assert "<p>Cart &lt;drives&gt; &amp; stops</p>" in body
    assert (  # no JSON file, no MP4
        '<a href="../clips/cart/data.csv" download>CSV</a> · '
        '<a href="../clips/cart/clip.webm" download>Video (WebM)</a></dd>'
    ) in body
    assert "<code>scene has no &#34;&lt;robot&gt;&#34;</code>" in body
    assert "<figcaption>" not in body  # the gallery is what captions link to
    node = SimpleNamespace(url="w/page.html")
    figure = integ.directives()["clip"]("cart", node)
    assert figure.startswith('<figure class="clip" id="clip-cart">')
    assert (
        '<figcaption>5.0 s simulated · video 0:05 · <a href="../gallery/index.html'
        '#clip-cart">Cart &lt;i&gt;</a> <span class="stale">(' in figure
    )
    failed = integ.directives()["clip"]("broken", node)
    assert failed.startswith('<figure class="clip clip-failed" id="clip-broken">')
    with pytest.raises(LookupError):
        integ.directives()["clip"]("nope", node)


def test_project_templates_replace_gallery_and_clip_markup(tmp_path):
    integ = integration(
        tmp_path,
        {
            "partials/clip.html": '<div class="my-clip">{{ clip.title }}'
            "{% if clip.video %} {{ clip.video.base }}clip.webm{% else %} "
            "{{ clip.placeholder.error }}{% endif %}</div>",
            "partials/gallery.html": "<ol>{% for item in items %}<li>"
            '{% with clip = item.clip %}{% include "partials/clip.html" %}{% endwith %}'
            "</li>{% endfor %}</ol>",
        },
    )
    body = gallery(integ)
    assert body == (
        '<ol><li><div class="my-clip">Cart &lt;i&gt; ../clips/cart/clip.webm</div></li>'
        '<li><div class="my-clip">broken scene has no &#34;&lt;robot&gt;&#34;</div></li></ol>'
    )
    node = SimpleNamespace(url="a/b/c.html")
    assert integ.directives()["clip"]("cart", node) == (
        '<div class="my-clip">Cart &lt;i&gt; ../../clips/cart/clip.webm</div>'
    )
