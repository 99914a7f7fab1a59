"""CLI: list, render to --out, one-line errors, exit codes; plus the SVG plot's determinism."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from sims.cli import main
from sims.plot import nice_step, path_svg
from sims.video import mp4_encoder


def test_list_prints_every_scenario(capsys):
    assert main(["list"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert [line.split()[0] for line in out] == [
        "2w1a-random",
        "cart-avoid",
        "cart-keyboard",
        "cart-reverse",
    ]
    assert "75 s" in out[0]


def test_render_writes_clip_files(tmp_path, capsys):
    out, cache = tmp_path / "out", tmp_path / "cache"
    args = [
        "render",
        "cart-reverse",
        "--size",
        "96x64",
        "--fps",
        "10",
        "--seconds",
        "1",
        "--out",
        str(out),
        "--cache",
        str(cache),
    ]
    assert main(args) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith("ok      cart-reverse: 10 frames 96x64, rendered")
    names = sorted(p.name for p in (out / "cart-reverse").iterdir())
    mp4 = ["clip.mp4"] if mp4_encoder() else []  # H.264 where ffmpeg has libx264
    assert names == [*mp4, "clip.webm", "data.csv", "data.json", "path.svg", "poster.png"] + [
        "series.svg"
    ]
    assert main(args) == 0
    assert "cached" in capsys.readouterr().out


def test_usage_errors_exit_2_with_one_line(capsys):
    assert main(["render", "nope"], prog="sitegen sims") == 2
    err = capsys.readouterr().err.splitlines()
    assert err[0] == (
        "sitegen sims: unknown scenario nope (known: 2w1a-random, cart-avoid, "
        "cart-keyboard, cart-reverse)"
    )
    assert main(["render", "cart-reverse", "--size", "big"]) == 2
    assert main([]) == 2
    assert main(["frobnicate"]) == 2
    assert "Traceback" not in capsys.readouterr().err


def test_path_plot_is_deterministic_svg():
    xs, ys = [0.0, 0.1, 0.2, 0.0, 0.05], [0.0, 0.05, 0.0, 0.0, -0.02]
    svg = path_svg(xs, ys, "demo <path>", run_starts=[3])
    assert svg == path_svg(xs, ys, "demo <path>", run_starts=[3])
    root = ET.fromstring(svg)
    ns = "{http://www.w3.org/2000/svg}"
    assert len(list(root.iter(ns + "polyline"))) == 2
    texts = [t.text for t in root.iter(ns + "text")]
    assert "demo <path>" in texts and "#2" in texts
    assert nice_step(0.23) == 0.05 and nice_step(4.0) == 1.0
