"""Clips: decodable WebM + data files, content-hash cache, failures isolated, stale kept."""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from sitegen_helpers import REPO

from sims.clips import ClipEvent, ClipSpec, planned, render_clips
from sims.scenarios import get_scenario
from sims.sources import RecordingPlan, register_source_kind, scenario_plan
from sims.video import probe

W, H, FPS, SECONDS = 160, 120, 10, 2.0
FRAMES = round(FPS * SECONDS)


def small(name: str, scenario: str | None = None, **kw) -> ClipSpec:
    return ClipSpec(
        name=name, scenario=scenario or name, width=W, height=H, fps=FPS, seconds=SECONDS, **kw
    )


# Source kinds for failure tests; workers import them from this module by name.
def failing_plan(spec: ClipSpec) -> RecordingPlan:
    plan = scenario_plan(ClipSpec(spec.name, "cart-reverse"))

    def drive(world, record):
        world.advance(0.5)
        raise RuntimeError("motor exploded")

    plan.drive = drive
    return plan


def hanging_plan(spec: ClipSpec) -> RecordingPlan:
    plan = scenario_plan(ClipSpec(spec.name, "cart-reverse"))

    def drive(world, record):
        while True:  # never steps, so only the hard kill can stop it
            time.sleep(0.05)

    plan.drive = drive
    return plan


def endless_plan(spec: ClipSpec) -> RecordingPlan:
    plan = scenario_plan(ClipSpec(spec.name, "cart-reverse"))

    def drive(world, record):
        while True:  # steps forever; the clip is far longer than the time limit allows
            world.step()

    plan.drive = drive
    return plan


@pytest.fixture(scope="module")
def gallery(tmp_path_factory):
    cache = tmp_path_factory.mktemp("clips")
    specs = [small(n) for n in ("2w1a-random", "cart-reverse", "cart-keyboard", "cart-avoid")]
    events: list[ClipEvent] = []
    results = render_clips(specs, cache, progress=events.append)
    return cache, specs, results, events


def test_every_clip_renders_and_decodes(gallery):
    _, specs, results, events = gallery
    assert [r.name for r in results] == [s.name for s in specs]
    for r in results:
        assert r.ok and r.rendered and not r.stale, r.error
        info, frames = probe(r.files["video"], keep_frames=True)
        assert r.files["video"].suffix == ".webm"
        assert (info.width, info.height, info.frames) == (W, H, FRAMES)
        diffs = [np.abs(frames[i].astype(int) - frames[i + 1]).mean() for i in range(FRAMES - 1)]
        assert max(diffs) > 0.5, f"{r.name}: the picture does not move"
        assert r.meta["frames"] == FRAMES and r.meta["fps"] == FPS
        assert r.meta["renderer"] in ("egl", "tinyrenderer")
        assert r.meta["source"].startswith("sims/scenarios/")
        assert r.meta["description"] == get_scenario(r.name).description
    statuses = sorted((e.name, e.status) for e in events if e.status not in ("progress", "queued"))
    assert statuses == sorted([(s.name, st) for s in specs for st in ("started", "done")])


def test_data_files_match_the_video(gallery):
    _, _, results, _ = gallery
    for r in results:
        assert r.files["poster"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        lines = r.files["csv"].read_text().splitlines()
        assert len(lines) == FRAMES + 1 and lines[0].startswith("t,x,y,z,")
        data = json.loads(r.files["json"].read_text())
        assert data["scenario"] == r.name and len(data["samples"]) == FRAMES
        svg = ET.fromstring(r.files["plot"].read_text())
        texts = [t.text for t in svg.iter("{http://www.w3.org/2000/svg}text")]
        assert "x (m)" in texts and "y (m)" in texts
        assert list(svg.iter("{http://www.w3.org/2000/svg}polyline"))


def test_second_render_comes_from_the_cache(gallery):
    cache, specs, first, _ = gallery
    events: list[ClipEvent] = []
    again = render_clips(specs, cache, progress=events.append)  # (its speed: bench/, not here)
    assert not any(r.rendered for r in again)
    assert [e.status for e in events] == ["cached"] * len(specs)
    assert [r.files for r in again] == [r.files for r in first]
    renamed = render_clips([small("other-name", "cart-reverse")], cache)  # same content
    assert not renamed[0].rendered and renamed[0].files == first[1].files


def test_every_field_that_changes_the_output_is_in_the_key():
    """Nothing is rendered: the key alone (sims.clips.planned)."""
    base = small("k", "cart-reverse")
    key = planned(base)[2]
    assert planned(small("renamed", "cart-reverse"))[2] == key  # the name is not content
    changed = [
        small("k", "cart-reverse", seed=3),
        small("k", "cart-reverse", params={"speed": -2.0}),
        small("k", "cart-reverse", speed=2.0),
        small("k", "cart-reverse", camera="overview"),
        small("k", "cart-reverse", trail=True),
        small("k", "cart-reverse", formats=("replay",)),
        dataclasses.replace(base, fps=FPS + 2),
        dataclasses.replace(base, width=W + 2),
        dataclasses.replace(base, seconds=SECONDS + 1),
    ]
    keys = [planned(spec)[2] for spec in changed]
    assert key not in keys and len(set(keys)) == len(keys)


def _key_in(code: Path, memo: Path) -> str:
    script = (
        "from sims.clips import ClipSpec, planned; print(planned(ClipSpec('k', 'cart-reverse'))[2])"
    )
    env = {**os.environ, "PYTHONPATH": str(code), "SITEGEN_CODE_MEMO": str(memo)}
    run = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, env=env, cwd=code
    )
    assert run.returncode == 0, run.stderr
    return run.stdout.strip()


def test_editing_the_engine_changes_the_key(tmp_path):
    """A copy of the packages: an edit of any module a clip runs (the World, the Lua host,
    which no hand-kept list named) gives another key; the same code, the same key."""
    code = tmp_path / "code"
    for name in ("located", "roster", "sims"):
        shutil.copytree(REPO / name, code / name, ignore=shutil.ignore_patterns("__pycache__"))
    memo = tmp_path / "memo.json"
    first = _key_in(code, memo)
    assert _key_in(code, memo) == first
    seen = {first}
    for module in ("sims/world.py", "sims/lua/host.py"):
        path = code / module
        path.write_text(path.read_text(encoding="utf-8") + "\n# edited\n", encoding="utf-8")
        seen.add(_key_in(code, memo))
    assert len(seen) == 3


def test_a_failing_clip_is_reported_by_name_and_keeps_the_stale_render(tmp_path):
    register_source_kind("test-failing", "test_sims_clips:failing_plan")
    first = render_clips([small("demo", "cart-reverse")], tmp_path)[0]
    assert first.ok
    events: list[ClipEvent] = []
    results = render_clips(
        [
            ClipSpec("demo", "cart-reverse", W, H, FPS, SECONDS, kind="test-failing"),
            small("fine", "cart-keyboard"),
        ],
        tmp_path,
        progress=events.append,
    )
    bad, good = results
    assert (
        not bad.ok and bad.stale and "cart-reverse" in bad.error and "motor exploded" in bad.error
    )
    assert bad.files == first.files and bad.files["video"].is_file()
    assert good.ok and good.rendered
    assert ("demo", "failed") in [(e.name, e.status) for e in events]
    unknown = render_clips([small("ghost", "no-such-scenario")], tmp_path)[0]
    assert not unknown.ok and not unknown.stale and "no-such-scenario" in unknown.error


def test_a_clip_past_its_time_limit_is_stopped(tmp_path):
    register_source_kind("test-hanging", "test_sims_clips:hanging_plan")
    spec = ClipSpec("hang", "cart-reverse", W, H, FPS, SECONDS, kind="test-hanging")
    start = time.perf_counter()
    result = render_clips([spec], tmp_path, timeout=1.0)[0]
    assert time.perf_counter() - start < 10
    assert not result.ok and "wall-clock limit" in result.error and "cart-reverse" in result.error
    assert "worker killed" in result.error


def test_a_stepping_clip_past_its_time_limit_stops_itself(tmp_path):
    register_source_kind("test-endless", "test_sims_clips:endless_plan")
    spec = ClipSpec("endless", "cart-reverse", W, H, FPS, seconds=10_000, kind="test-endless")
    result = render_clips([spec], tmp_path, timeout=1.5)[0]
    assert not result.ok and "passed its wall-clock limit of 1.5 s" in result.error
    assert "worker killed" not in result.error  # the Recorder's own deadline stopped it


def test_identical_content_under_two_names_renders_once(tmp_path):
    events: list[ClipEvent] = []
    twins = render_clips(
        [small("twin-a", "cart-reverse"), small("twin-b", "cart-reverse")],
        tmp_path,
        progress=events.append,
    )
    assert [r.rendered for r in twins] == [True, False]
    assert twins[0].files == twins[1].files and twins[1].meta["name"] == "twin-b"
    assert ("twin-b", "cached") in [(e.name, e.status) for e in events]


def test_a_clip_job_crosses_to_the_worker_as_itself():
    """sims.clip_worker.ClipJob: the JSON line a worker reads gives back the same record."""
    import json

    from sims.clip_pool import Job
    from sims.clip_worker import ClipJob

    spec = small("j", "cart-reverse", camera="overview", formats=("replay", "video"))
    job = ClipJob("render", spec, "sims.sources:scenario_plan", "/tmp/x", start=60, stop=120)
    message = json.loads(json.dumps(Job(7, job, 30.0).message()))
    assert message["id"] == 7
    assert ClipJob.from_message(message) == dataclasses.replace(job, time_limit=30.0)
