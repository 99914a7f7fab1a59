"""When EGL was asked for and TinyRenderer drew the frames, the user is told why, once.

TinyRenderer is several times slower (docs/sims.md), so a build that silently falls back looks
like a slow machine. The fallback is forced the way a broken install causes it: an
``eglRenderer`` module that is not the plugin comes first on the import path (the clip workers
inherit the path), so pybullet cannot load it.
"""

from __future__ import annotations

import gc
import json

import pytest
from sitegen_helpers import write_tree

NOTE = "clips rendered with TinyRenderer (slower): could not load the EGL plugin"


@pytest.fixture
def broken_egl(tmp_path, monkeypatch):
    fake = tmp_path / "fake-egl"
    fake.mkdir()
    (fake / "eglRenderer.py").write_text('"""Not the plugin."""\n', encoding="utf-8")
    monkeypatch.syspath_prepend(str(fake))
    monkeypatch.setenv("SIMS_RENDERER", "auto")
    gc.collect()  # a World an earlier test dropped must not still hold EGL in this process


def test_a_world_says_why_egl_fell_back(broken_egl):
    from sims.render import fallback_note
    from sims.world import World

    with World("cart", render_with="auto") as world:
        assert world.renderer == "tinyrenderer"
        assert world.renderer_fallback == "could not load the EGL plugin"
        assert fallback_note([None, world.renderer_fallback, world.renderer_fallback]) == NOTE
    with World("cart") as world:  # TinyRenderer asked for: not a fallback
        assert world.renderer_fallback is None
    assert fallback_note([None, None]) is None


def test_sims_render_prints_the_reason_once_and_not_for_cached_clips(broken_egl, tmp_path, capsys):
    from sims.cli import main

    args = ["render", "cart-reverse", "cart-avoid", "--size", "96x64", "--fps", "8"]
    args += ["--seconds", "1", "--out", str(tmp_path / "out"), "--cache", str(tmp_path / "c")]
    assert main(args) == 0
    err = capsys.readouterr().err
    assert err.splitlines() == [f"sitegen sims: {NOTE}"]
    meta = json.loads((tmp_path / "out" / "cart-reverse" / "data.json").read_text("utf-8"))
    assert meta["kind"] == "scenario"
    assert main(args) == 0  # from the cache: nothing was rendered now
    assert NOTE not in capsys.readouterr().err


def test_site_build_logs_the_reason(broken_egl, tmp_path):
    from sitegen.build import BuildOptions, build

    source = write_tree(
        tmp_path / "src",
        {
            "sitegen.yml": "title: t\nsims:\n  size: 96x64\n  fps: 8\n  formats: [video]\n"
            "  clips:\n"
            "    - {name: rev, scenario: cart-reverse, seconds: 1}\n",
            "content/index.md": "# Home\n\n::: clip rev\n",
        },
    )
    lines: list[str] = []
    out = tmp_path / "site"
    report = build(BuildOptions(source=source, output=out, strict=True, log=lines.append))
    assert [str(d) for d in report.diagnostics] == []
    assert lines.count(NOTE) == 1
    meta = json.loads((out / "clips" / "rev" / "data.json").read_text(encoding="utf-8"))
    assert meta["fps"] == 8


def test_remote_api_record_prints_the_reason(broken_egl, tmp_path, capsys):
    from sims.remote_api.cli import main

    script = tmp_path / "idle.py"
    script.write_text("import time\ntime.sleep(0.5)\n", encoding="utf-8")
    out = tmp_path / "clip.webm"
    code = main(["run", str(script), "--scene", "cart", "--record", str(out)]
                + ["--size", "96x64", "--fps", "8"])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 0, err
    assert f"[remote-api] {NOTE}" in err.splitlines()
    assert out.stat().st_size > 0
