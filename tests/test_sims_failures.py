"""A broken clip never costs the site; the clip cache survives a move; renders are byte-identical.

These build small projects the way a user does (sitegen.yml with scenario and script clips) and
check what the user relies on: the warning, the placeholder, ``--strict``, the remembered
failure and ``--retry-failed``, a copied checkout that renders nothing, and the same bytes from
two renders however the frame ranges were shared out.
"""

from __future__ import annotations

import shutil
import time
from pathlib import Path

import pytest
from sitegen_helpers import REPO, run_cli, snapshot, write_tree

from sims.clip_worker import RANGE_FRAMES
from sims.clips import ClipEvent, ClipSpec, render_clips
from sims.video import mp4_encoder
from sitegen.build import BuildOptions, build
from sitegen.errors import BuildError

CART_SCRIPT = (REPO / "examples" / "remote_api" / "cart_velocity.py").read_text(encoding="utf-8")
BROKEN = """import sim

client = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
raise RuntimeError("the left wheel fell off")
"""
CONFIG = """title: t
sims:
  size: 96x64
  fps: 8
  clips:
    - {name: rev, scenario: cart-reverse, seconds: 1.5}
    - {name: drive, script: scripts/drive.py, scene: cart, seconds: 2, speed: 2}
"""


def project(root: Path, script: str = CART_SCRIPT) -> Path:
    return write_tree(
        root,
        {
            "sitegen.yml": CONFIG,
            "scripts/drive.py": script,
            "content/index.md": "# Home\n\n::: clip rev\n\n::: clip drive\n",
        },
    )


def build_logged(source: Path, **kw) -> tuple[list[str], object]:
    lines: list[str] = []
    report = build(BuildOptions(source=source, log=lines.append, **kw))
    return lines, report


def warnings_of(report) -> list[str]:
    return [str(d) for d in report.diagnostics]


def test_a_broken_clip_gets_a_placeholder_and_a_warning_and_fails_strict(tmp_path):
    src = project(tmp_path / "p", BROKEN)
    lines, report = build_logged(src)
    [warning] = [w for w in warnings_of(report) if "sims.clips[drive]" in w]
    assert "the left wheel fell off" in warning and "placeholder" in warning
    page = (src / "site" / "index.html").read_text(encoding="utf-8")
    assert 'class="clip clip-failed" id="clip-drive"' in page  # the page builds, with a placeholder
    assert "the left wheel fell off" in page
    assert 'data-replay="clips/rev/replay.js"' in page  # the good clip is still there
    gallery = (src / "site" / "gallery" / "index.html").read_text(encoding="utf-8")
    assert "clip-placeholder" in gallery and "the left wheel fell off" in gallery
    assert "drive.py" in gallery  # the script's source is still shown
    assert any(line.startswith("clip drive: FAILED") for line in lines)
    # the command line: exit 0 and the warning on stderr; --strict turns it into an error
    done = run_cli("build", "--source", str(src), "--output", str(tmp_path / "o"))
    assert done.returncode == 0, done.stderr
    assert "sims.clips[drive]" in done.stderr and "Traceback" not in done.stderr
    strict = run_cli("build", "--strict", "--source", str(src), "--output", str(tmp_path / "s"))
    assert strict.returncode != 0 and "sims.clips[drive]" in strict.stderr
    with pytest.raises(BuildError):
        build(BuildOptions(source=src, output=tmp_path / "s2", strict=True, log=lambda _: None))


def test_a_failure_is_remembered_until_retried_or_changed(tmp_path):
    src = project(tmp_path / "p", BROKEN)
    build_logged(src, output=tmp_path / "o1")
    lines, report = build_logged(src, output=tmp_path / "o2")
    assert not any("started" in line for line in lines)  # not run again
    [warning] = [w for w in warnings_of(report) if "sims.clips[drive]" in w]
    assert "remembered from an earlier build" in warning and "--retry-failed" in warning
    lines, report = build_logged(src, output=tmp_path / "o3", retry_failed=True)
    assert "clip drive: started (replay)" in lines  # tried again, failed again
    assert any(
        "the left wheel fell off" in w and "remembered from" not in w for w in warnings_of(report)
    )
    (src / "scripts" / "drive.py").write_text(CART_SCRIPT, encoding="utf-8")  # fixed: new inputs
    lines, report = build_logged(src, output=tmp_path / "o4")
    assert "clip drive: started (replay)" in lines and warnings_of(report) == []
    assert (tmp_path / "o4" / "clips" / "drive" / "replay.glb").stat().st_size > 0


def test_the_last_good_render_is_kept_and_marked_stale(tmp_path):
    src = project(tmp_path / "p")
    build_logged(src)
    good = (src / "site" / "clips" / "drive" / "replay.glb").read_bytes()
    (src / "scripts" / "drive.py").write_text(BROKEN, encoding="utf-8")
    _, report = build_logged(src)
    assert any("previous render" in w for w in warnings_of(report))
    assert (src / "site" / "clips" / "drive" / "replay.glb").read_bytes() == good
    page = (src / "site" / "index.html").read_text(encoding="utf-8")
    assert "stale" in page and "clip-failed" not in page


def test_a_copied_checkout_with_its_cache_renders_nothing(tmp_path):
    src = project(tmp_path / "first")
    lines, _ = build_logged(src)
    assert sum(line.endswith("(replay)") and "started" in line for line in lines) == 2
    copy = tmp_path / "elsewhere" / "second"
    shutil.copytree(src, copy)
    shutil.rmtree(copy / "site")  # make the copy build its pages (and ask for every clip)
    lines, report = build_logged(copy)
    assert sorted(line for line in lines if line.startswith("clip ")) == [
        "clip drive: cached",
        "clip rev: cached",
    ]
    assert warnings_of(report) == []
    first, second = snapshot(src / "site" / "clips"), snapshot(copy / "site" / "clips")
    assert first == second and len(first) == 14  # 7 files a replay clip: glb, js, data, plots


def test_one_clip_rendered_twice_is_byte_identical_however_ranges_are_shared(tmp_path):
    seconds = (RANGE_FRAMES + 12) / 10  # more than one frame range
    spec = ClipSpec(
        "arm", "2w1a-random", width=96, height=64, fps=10, seconds=seconds,
        formats=("replay", "video"),
    )  # fmt: skip
    one = render_clips([spec], tmp_path / "a", jobs=1)[0]
    two = render_clips([spec], tmp_path / "b", jobs=2)[0]
    assert one.ok and two.ok, (one.error, two.error)
    assert one.meta["frames"] == RANGE_FRAMES + 12
    kinds = {"video", "replay", "replay_js", "poster", "csv", "json", "plot", "series"}
    if mp4_encoder():  # the H.264 MP4 too, where ffmpeg has libx264
        kinds.add("mp4")
    assert set(one.files) == kinds == set(two.files)
    for kind in sorted(kinds):
        assert one.files[kind].read_bytes() == two.files[kind].read_bytes(), kind
    meta = one.files["video"].parent / "meta.json"
    assert meta.read_bytes() == (two.files["video"].parent / "meta.json").read_bytes()


def test_time_lapse_films_every_nth_sample_and_keeps_all_data(tmp_path):
    from sims.video import probe

    spec = ClipSpec("rev", "cart-reverse", width=96, height=64, fps=10, seconds=4, speed=4)
    result = render_clips([spec], tmp_path)[0]
    assert result.ok, result.error
    info, _ = probe(result.files["video"])
    assert info.frames == 10 and result.meta["frames"] == 10 and result.meta["speed"] == 4
    rows = result.files["csv"].read_text(encoding="utf-8").splitlines()[1:]
    assert len(rows) == 40 and result.meta["duration"] == 4.0  # data keep every 1/fps s


def test_a_script_sleeping_forever_stops_at_its_simulated_limit(tmp_path):

    script = write_tree(tmp_path, {"idle.py": "import time\nwhile True:\n    time.sleep(1)\n"})
    spec = ClipSpec(
        "idle",
        str(script / "idle.py"),
        kind="script",
        width=96,
        height=64,
        fps=8,
        seconds=2,
        params={"scene": "2w1a"},  # a continuous server: the simulation never starts
    )
    start = time.monotonic()
    result = render_clips([spec], tmp_path / "cache", timeout=120)[0]
    assert not result.ok and "time limit of 13 s (simulated time)" in result.error
    assert time.monotonic() - start < 60


def test_the_wall_clock_net_reaches_script_clips(tmp_path):

    script = write_tree(tmp_path, {"busy.py": "while True:\n    pass\n"})
    spec = ClipSpec(
        "busy",
        str(script / "busy.py"),
        kind="script",
        width=96,
        height=64,
        fps=8,
        seconds=2,
        params={"scene": "cart"},
        timeout=3,
    )
    start = time.monotonic()
    result = render_clips([spec], tmp_path / "cache")[0]
    assert not result.ok and "wall-clock" in result.error, result.error
    assert time.monotonic() - start < 30


def test_progress_lines_in_pipes_name_each_clip_with_frames_per_second():
    from sitegen.progress import ClipProgress

    lines: list[str] = []
    shown = ClipProgress(live=False, log=lines.append)
    shown(ClipEvent("a", "queued", total=40))
    shown(ClipEvent("a", "started", total=40))
    shown(ClipEvent("a", "progress", frames=20, total=40, phase="rendering"))
    shown(ClipEvent("a", "done", 2.0, frames=40, total=40))
    shown(ClipEvent("b", "cached"))
    shown(ClipEvent("c", "failed", error="scenario 'x' failed: boom", remembered=True))
    shown.close()
    assert lines == [
        "clip a: started (40 frames)",
        "clip a: done, 40 frames in 2.0 s (20.0 frames/s)",
        "clip b: cached",
        "clip c: FAILED (remembered): scenario 'x' failed: boom",
    ]
