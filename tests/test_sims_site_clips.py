"""The site's scene-file and ZeroMQ clips render with the default renderer, with no warning.

Recording a ``.simscene.xml`` scene once failed under EGL ("the rebuilt scene does not match the
recorded one"): the render World holds the scene's visual-only bodies, which the physics World
recording the states has not. These build the way CI does (``--strict``, the default renderer)
a small project with the same kinds of clip as this repository's ``lua-arm`` (a scene moved by
its own Lua scripts) and ``zmq-2w1a-drive`` (a ZeroMQ remote API script), and check the
repository's own site embeds both.
"""

from __future__ import annotations

import json
import os
import re

import yaml
from sitegen_helpers import REPO, write_tree

from sitegen.build import BuildOptions, build

SITE_CLIPS = {"lua-arm", "zmq-2w1a-drive", "rover-arena"}


def test_the_site_embeds_the_lua_and_zeromq_clips_in_stage_3_pages():
    config = yaml.safe_load((REPO / "sitegen.yml").read_text(encoding="utf-8"))
    names = {clip["name"] for clip in config["sims"]["clips"]}
    assert SITE_CLIPS <= names
    embedded = {
        name
        for page in (REPO / "content" / "stage-3").rglob("*.md")
        for name in re.findall(r"^::: clip (\S+)$", page.read_text(encoding="utf-8"), re.M)
    }
    assert SITE_CLIPS <= embedded


def test_scene_file_and_zeromq_clips_render_strict_with_the_default_renderer(tmp_path, monkeypatch):
    monkeypatch.delenv("SIMS_RENDERER", raising=False)
    lua = (REPO / "examples" / "lua" / "lua_arm_watch.py").read_text(encoding="utf-8")
    zmq = (REPO / "examples" / "zmq" / "2w1a_drive_stepped.py").read_text(encoding="utf-8")
    scene = (REPO / "data" / "scenes" / "lua_arm.simscene.xml").read_text(encoding="utf-8")
    source = write_tree(
        tmp_path / "src",
        {
            "sitegen.yml": "title: t\nsims:\n  size: 96x64\n  fps: 8\n  formats: [replay, video]\n"
            "  clips:\n"
            "    - {name: arm, script: lua_arm_watch.py, scene: arm.simscene.xml, seconds: 2}\n"
            "    - {name: crawl, script: crawl.py, scene: 2w1a, seconds: 2, speed: 2}\n",
            "lua_arm_watch.py": lua,
            "crawl.py": zmq,
            "arm.simscene.xml": scene,
            "content/index.md": "# Home\n\n::: clip arm\n\n::: clip crawl\n",
        },
    )
    lines: list[str] = []
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, strict=True, log=lines.append))
    assert [str(d) for d in report.diagnostics] == []
    for name in ("arm", "crawl"):
        assert (out / "clips" / name / "clip.webm").stat().st_size > 1000
        assert (out / "clips" / name / "replay.glb").stat().st_size > 1000
        meta = json.loads((out / "clips" / name / "data.json").read_text(encoding="utf-8"))
        assert meta["fps"] == 8
    html = (out / "index.html").read_text(encoding="utf-8")
    assert "clip-failed" not in html and html.count('class="clip clip-replay"') == 2
    assert html.count('/clip.webm">WebM</a>') == 2  # the video beside each replay
    gallery = (out / "gallery" / "index.html").read_text(encoding="utf-8")
    assert "(scene arm.simscene.xml, seed 0)" in gallery  # the scene's name, not a checkout path
    assert str(tmp_path) not in html + gallery
    assert os.environ.get("SIMS_RENDERER") is None
