"""A scene file read again is not decoded again: the content-hash cache in
sims/scene/scene_cache.py gives back exactly the decoded scene, follows the file's bytes, and
never turns a bad or unwritable cache into an error."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from shared_data import shared

from sims.scene import scene_cache
from sims.scene.load import load_scene
from sims.world import World

REPO = Path(__file__).resolve().parents[1]
ROVER = REPO / "data" / "scenes" / "rover.simscene.xml"


@pytest.fixture()
def cache(tmp_path, monkeypatch) -> Path:
    folder = tmp_path / "cache"
    monkeypatch.setenv(scene_cache.ENV, str(folder))
    return folder


class Counting:
    """load_scene, counting the decodes."""

    def __init__(self) -> None:
        self.calls = 0

    def __call__(self, path: str):
        self.calls += 1
        return load_scene(path)


def test_a_second_read_is_the_cached_scene_exactly_and_follows_the_bytes(cache, tmp_path):
    decode = Counting()
    first = scene_cache.load(ROVER, decode)
    assert decode.calls == 1 and len(list(cache.glob("*.json"))) == 1
    again = scene_cache.load(ROVER, decode)
    assert decode.calls == 1  # served from the cache
    assert again == first == load_scene(ROVER)
    # the same bytes elsewhere hit the same entry, and the scene names the file read now
    copy = tmp_path / "elsewhere" / "copy.simscene.xml"
    copy.parent.mkdir()
    shutil.copyfile(ROVER, copy)
    moved = scene_cache.load(copy, decode)
    assert decode.calls == 1 and moved.source == str(copy)
    assert moved == load_scene(copy)
    # an edited file is decoded again
    copy.write_text(ROVER.read_text().replace("Rover", "Rover2"), encoding="utf-8")
    edited = scene_cache.load(copy, decode)
    assert decode.calls == 2 and any(o.name == "Rover2" for o in edited.objects)
    assert len(list(cache.glob("*.json"))) == 2


def test_a_cached_course_ttt_builds_the_same_world(cache):
    ttt = shared("data", "scenes", "vrep_remoteapi_ex", "2w1a", "2w1a.ttt")
    decode = Counting()
    decoded = scene_cache.load(ttt, decode)
    cached = scene_cache.load(ttt, decode)
    assert decode.calls == 1 and cached == decoded  # floats exact: no rounding on the way
    poses = []
    for scene in (decoded, cached):
        with World(scene) as w:
            w.set_joint_target_position("ShoulderMotor", 1.0)
            w.advance(1.0)
            poses.append((w.object_pose("2W1A"), w.joint_position("ShoulderMotor")))
    assert poses[0] == poses[1]  # identical, not close


def test_bad_entries_and_unwritable_folders_are_not_errors(cache, tmp_path, monkeypatch):
    decode = Counting()
    scene_cache.load(ROVER, decode)
    (entry,) = cache.glob("*.json")
    wrong_type = json.dumps({"format": scene_cache.FORMAT, "scene": 3})
    for junk in ("{not json", json.dumps({"format": "other"}), wrong_type):
        entry.write_text(junk, encoding="utf-8")
        assert scene_cache.load(ROVER, decode) == load_scene(ROVER)
        assert json.loads(entry.read_text(encoding="utf-8"))["format"] == scene_cache.FORMAT
    assert decode.calls == 4  # each bad entry decoded again and replaced
    blocked = tmp_path / "a file, not a folder"
    blocked.write_text("x", encoding="utf-8")
    monkeypatch.setenv(scene_cache.ENV, str(blocked / "cache"))
    assert scene_cache.load(ROVER, decode) == load_scene(ROVER)
    assert decode.calls == 5 and list(tmp_path.glob("**/.*.tmp")) == []


def test_off_turns_it_off_and_entries_are_pruned(cache, tmp_path, monkeypatch):
    monkeypatch.setenv(scene_cache.ENV, "off")
    decode = Counting()
    scene_cache.load(ROVER, decode)
    scene_cache.load(ROVER, decode)
    assert decode.calls == 2 and not cache.exists()
    monkeypatch.setenv(scene_cache.ENV, str(cache))
    monkeypatch.setattr(scene_cache, "MAX_ENTRIES", 2)
    text = ROVER.read_text()
    for k in range(4):
        variant = tmp_path / f"v{k}.simscene.xml"
        variant.write_text(text.replace("Rover", f"Rover{k}"), encoding="utf-8")
        scene_cache.load(variant, decode)
    assert len(list(cache.glob("*.json"))) == 2


def test_a_new_process_reads_the_cached_scene_without_decoding(cache):
    """What each isolated run or clip sees: the first process decodes and writes the entry, the
    next one reads it (marked here, so that the test can tell a read from a decoding)."""
    probe = (
        "from sims.scene.resolve import open_scene; "
        f"print(' '.join(o.name for o in open_scene({str(ROVER)!r}).objects))"
    )
    env = dict(os.environ, **{scene_cache.ENV: str(cache)})

    def names() -> list[str]:
        run = [sys.executable, "-c", probe]
        return subprocess.run(
            run, env=env, capture_output=True, text=True, check=True
        ).stdout.split()

    first = names()
    assert "Rover" in first
    (entry,) = cache.glob("*.json")
    entry.write_text(entry.read_text(encoding="utf-8").replace('"Rover"', '"Marked"'), "utf-8")
    second = names()
    assert "Marked" in second and "Rover" not in second
    assert len(second) == len(first)
