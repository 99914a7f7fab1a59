"""The bundled ``2w1a`` scene is package data: an installed wheel builds the same robot as a
checkout, and a missing bundled file is an error, never a silent fall back to the hand model."""

from __future__ import annotations

import subprocess
import sys
import zipfile

import pytest
from sitegen_helpers import REPO

from sims.scene import resolve

PROBE = """
from sims.scene.resolve import open_scene
import sims
scene = open_scene("2w1a")
print(sims.__file__)
print(type(scene).__name__, len(scene.objects))
"""


def test_the_bundled_scene_lives_in_the_package_with_its_source_named():
    path = resolve.bundled_file("2w1a")
    assert path.parent == REPO / "sims" / "scene" / "bundled"
    readme = (path.parent / "README.md").read_text(encoding="utf-8")
    assert "2w1a.scene.json" in readme and "2w1a.ttt" in readme and "mdecourse/cad2020" in readme
    assert not (REPO / "data" / "scenes" / "2w1a.scene.json").exists()


def test_a_missing_bundled_file_is_an_error_naming_it(tmp_path, monkeypatch):
    monkeypatch.setattr(resolve, "BUNDLED_SCENES", tmp_path)
    with pytest.raises(resolve.SceneFileError, match=r"2w1a\.scene\.json.*bundled scene '2w1a'"):
        resolve.open_scene("2w1a")


def test_an_installed_wheel_builds_2w1a_from_its_own_package_data(tmp_path):
    built = subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(tmp_path), str(REPO)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert built.returncode == 0, built.stderr[-2000:]
    wheel = next(tmp_path.glob("*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    assert {"sims/scene/bundled/2w1a.scene.json", "sims/scene/bundled/README.md"} <= names
    target = tmp_path / "installed"
    zipfile.ZipFile(wheel).extractall(target)  # what a non-editable install puts on sys.path
    run = subprocess.run(
        [sys.executable, "-I", "-c", f"import sys; sys.path.insert(0, {str(target)!r})\n{PROBE}"],
        capture_output=True,
        text=True,
        cwd=tmp_path,
        timeout=120,
    )
    assert run.returncode == 0, run.stderr[-2000:]
    where, what = run.stdout.splitlines()[-2:]
    assert where.startswith(str(target))
    assert what.startswith("Scene ") and int(what.split()[1]) > 10
