"""Replays from the command line: ``sitegen scene export SCENE OUT.glb`` (a scene without a
run) and ``sitegen remote-api run SCRIPT --record OUT.glb`` (a script's run); bad input is one
line and exit 1."""

from __future__ import annotations

import pygltflib as G
from gltf_kit import assert_valid
from sitegen_helpers import REPO, run_cli


def test_scene_export_bundled_and_file_scenes(tmp_path):
    for scene, name in (("cart", "cart"), (str(REPO / "data/scenes/rover.simscene.xml"), "rover")):
        out = tmp_path / f"{name}.glb"
        done = run_cli("scene", "export", scene, str(out))
        assert done.returncode == 0, done.stderr
        report = assert_valid(out)
        assert report["info"]["animationCount"] == 0 and report["info"]["drawCallCount"] > 2
    bad = run_cli("scene", "export", "nope.ttt", str(tmp_path / "x.glb"))
    assert bad.returncode == 1 and bad.stderr.strip().splitlines() == [
        "nope.ttt: no such scene file (bundled scenes: 2w1a, cart)"
    ]
    unwritable = run_cli("scene", "export", "cart", str(tmp_path / "no" / "dir" / "x.glb"))
    assert unwritable.returncode == 1 and "cannot write" in unwritable.stderr
    assert "Traceback" not in bad.stderr + unwritable.stderr


def test_record_a_script_run_as_a_replay(tmp_path):
    out = tmp_path / "run" / "cart.glb"
    script = REPO / "examples" / "remote_api" / "cart_velocity.py"
    done = run_cli(
        "remote-api", "run", str(script), "--scene", "cart", "--record", str(out), "--fps", "10"
    )
    assert done.returncode == 0, done.stderr
    report = assert_valid(out)
    assert report["info"]["animationCount"] == 1
    gltf = G.GLTF2.load_from_bytes(out.read_bytes())
    info = next(n for n in gltf.nodes if n.name == "replay").extras["sitegen"]
    samples = len(out.with_suffix(".csv").read_text(encoding="utf-8").splitlines()) - 1
    assert info["duration"] == samples / 10 and info["follow"] == "cart"
    assert sorted(p.name for p in out.parent.iterdir()) == [
        "cart.csv", "cart.glb", "cart.json", "cart.png", "cart.series.svg", "cart.svg",
    ]  # fmt: skip
