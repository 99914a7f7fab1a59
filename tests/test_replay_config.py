"""``formats:`` in sitegen.yml (site-wide and per clip), checked at its line; what each format
puts in the page; formats are part of a clip's cache key."""

from __future__ import annotations

import pytest
from sitegen_helpers import write_tree

from sims.clips import ClipSpec, render_clips, spec_fields
from sims.video import mp4_encoder, probe
from sitegen.build import BuildOptions, build
from sitegen.config import parse_config
from sitegen.errors import BuildError


def test_formats_default_to_replay_and_are_checked_at_their_line(tmp_path):
    config = parse_config("sims:\n  clips:\n    - {name: a, scenario: cart-avoid}\n", tmp_path)
    assert config.sims.formats == ("replay",) and config.sims.clips[0].formats is None
    config = parse_config(
        "sims:\n  formats: [replay, video]\n  clips:\n"
        "    - {name: a, scenario: cart-avoid, formats: [video]}\n",
        tmp_path,
    )
    assert config.sims.formats == ("replay", "video")
    assert config.sims.clips[0].formats == ("video",)
    for text, line, field in (
        ("sims:\n  formats: [gif]\n", 2, "sims.formats"),
        ("sims:\n  formats: replay\n", 2, "sims.formats"),
        ("sims:\n  clips:\n    - {name: a, scenario: cart-avoid, formats: []}\n", 3,
         "sims.clips[0].formats"),
    ):  # fmt: skip
        with pytest.raises(BuildError) as info:
            parse_config(text, tmp_path)
        (d,) = info.value.diagnostics
        assert (d.line, d.field) == (line, field)
        assert "replay and/or video" in d.message


def test_formats_are_part_of_the_key_and_an_unknown_one_fails_the_clip(tmp_path):
    def fields(**kw):
        return spec_fields(ClipSpec(name="a", scenario="cart-avoid", **kw), 0, {})

    assert fields(formats=("replay",)) != fields(formats=("video",))
    assert fields(formats=("video", "replay")) == fields(formats=("replay", "video"))
    (r,) = render_clips([ClipSpec("a", "cart-reverse", formats=("gif",))], tmp_path)
    assert not r.ok and "formats must be some of replay, video" in r.error


def test_a_page_shows_a_replay_or_a_video_as_asked(tmp_path):
    source = write_tree(
        tmp_path / "src",
        {
            "sitegen.yml": "title: t\nlanguage: zh-TW\nsims:\n  size: 64x48\n  fps: 4\n  clips:\n"
            "    - {name: r, scenario: cart-reverse, seconds: 2, speed: 2}\n"
            "    - {name: v, scenario: cart-reverse, seconds: 2, speed: 2, formats: [video]}\n"
            "    - {name: b, scenario: cart-reverse, seconds: 1, formats: [replay, video]}\n",
            "content/index.md": "# Home\n\n::: clip r\n\n::: clip v\n\n::: clip b\n",
            "content/plain.md": "# Plain\n\nNo clip here.\n",
        },
    )
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, strict=True, log=lambda line: None))
    assert [str(d) for d in report.diagnostics] == []
    home = (out / "index.html").read_text(encoding="utf-8")
    assert home.count('src="assets/replay/replay.js" defer></script>') == 1
    assert home.count('class="clip clip-replay"') == 2 and home.count("<video") == 1
    assert 'data-glb="clips/r/replay.glb"' in home and 'data-replay="clips/r/replay.js"' in home
    assert "模擬 2.0 秒 · 以 2× 播放 · " in home  # the replay starts at the clip's speed
    assert 'href="clips/b/clip.webm">WebM</a>' in home  # the video beside a replay
    assert '<source src="clips/v/clip.webm" type="video/webm; codecs=vp8">' in home
    if mp4_encoder():  # H.264 for Safari on iPhones, after the WebM
        mp4 = out / "clips" / "v" / "clip.mp4"
        assert '<source src="clips/v/clip.mp4" type="video/mp4">' in home
        assert home.index("clips/v/clip.webm") < home.index("clips/v/clip.mp4")
        assert b"avc1" in mp4.read_bytes()[:4096]  # H.264 sample entry in the MP4 header
        info, _ = probe(mp4)
        webm, _ = probe(out / "clips" / "v" / "clip.webm")
        assert (info.frames, info.width, info.height) == (webm.frames, 64, 48) == (4, 64, 48)
    assert "assets/replay/" not in (out / "plain.html").read_text(encoding="utf-8")
    assert sorted(p.name for p in (out / "clips" / "r").iterdir()) == [
        "data.csv", "data.json", "path.svg", "poster.png", "replay.glb", "replay.js", "series.svg",
    ]  # fmt: skip
    assert not (out / "clips" / "r" / "clip.webm").exists()
    assert (out / "clips" / "v" / "clip.webm").is_file() and not (
        out / "clips" / "v" / "replay.glb"
    ).exists()
    gallery = (out / "gallery" / "index.html").read_text(encoding="utf-8")
    assert 'href="../clips/r/replay.glb" download>3D 場景 (glTF)</a>' in gallery


@pytest.mark.parametrize("jobs", ["1", "2"])
def test_a_page_and_its_slide_deck_each_load_the_viewer_once(tmp_path, monkeypatch, jobs):
    """A deck is the page's own Markdown expanded a second time: both load the viewer once, in
    whatever order and process they are made (one worker once left the deck without it: its
    replays never played), and two replays in one page still load it once."""
    monkeypatch.setenv("SITEGEN_JOBS", jobs)
    source = write_tree(
        tmp_path / "src",
        {
            "sitegen.yml": "title: t\nsims:\n  size: 64x48\n  fps: 4\n  clips:\n"
            "    - {name: r, scenario: cart-reverse, seconds: 1}\n"
            "    - {name: s, scenario: cart-avoid, seconds: 1}\n",
            "content/index.md": "# Home\n\nHello.\n",
            "content/talk.md": "---\nslides: true\n---\n# Talk\n\n::: clip r\n\n---\n\n"
            "## Two\n\n::: clip s\n",
        },
    )
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, strict=True, log=lambda line: None))
    assert [str(d) for d in report.diagnostics] == []
    viewer = 'src="assets/replay/replay.js" defer></script>'
    for name in ("talk.html", "talk.slides.html"):
        html = (out / name).read_text(encoding="utf-8")
        assert html.count('class="clip clip-replay"') == 2 and html.count(viewer) == 1, name


def test_replay_only_clips_render_on_every_worker_asked_for(tmp_path, monkeypatch):
    """A replay draws no frames, so the pool was sized by frames to draw: one worker, and a site
    of replays built one clip after another on a 2-core machine (33 s instead of 18 s)."""
    from sims import clip_schedule

    sizes: list[int] = []
    real = clip_schedule.make_pool

    def recorded(workers, log_dir):
        sizes.append(workers)
        return real(workers, log_dir)

    monkeypatch.setattr(clip_schedule, "make_pool", recorded)
    specs = [
        ClipSpec(n, "cart-reverse", seconds=0.5, seed=i, formats=("replay",))
        for i, n in enumerate("ab")
    ]
    results = render_clips(specs, tmp_path, jobs=2)
    assert all(r.ok for r in results) and sizes == [2]
