"""``sitegen scene show`` lists the IK groups, paths and loop closures of a scene with what is
made of them, and takes the bundled scene names ``remote-api run`` takes (issues 26, 28)."""

from __future__ import annotations

import json

from sims.scene.show import main
from tests.shared_data import shared


def show(capsys, *args: str) -> tuple[int, str, str]:
    code = main(["show", *args])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_show_takes_bundled_scene_names(capsys):
    code, out, err = show(capsys, "2w1a")
    assert code == 0 and err == ""
    assert "ShoulderMotor" in out and "Physics: bullet" in out
    code, out, _ = show(capsys, "cart", "--json")
    doc = json.loads(out)
    assert code == 0 and doc["format"] == "hand-built"
    assert {"cart", "left_m", "right_m"} <= {o["name"] for o in doc["objects"]}
    code, out, err = show(capsys, "no-such-scene")
    assert code == 1 and out == "" and err.count("\n") == 1 and "no-such-scene" in err


def test_show_lists_ik_groups_paths_and_loop_closures(capsys):
    path = shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt")
    code, out, _ = show(capsys, str(path), "--json")
    doc = json.loads(out)
    (group,) = doc["ik_groups"]
    assert group["name"] == "UR5" and group["explicit"]
    (element,) = group["elements"]
    assert (element["tip"], element["target"], element["base"]) == (
        "UR5_ikTip",
        "UR5_ikTarget",
        "UR5",
    )
    assert element["constraints"] == ["x", "y", "z", "alpha-beta", "gamma"]
    assert [j.split()[0] for j in element["joints"]] == [f"UR5_joint{i}" for i in range(1, 7)]
    (belt,) = doc["paths"]
    assert belt["closed"] and belt["followers"] == 74 and abs(belt["length"] - 3.279) < 0.01
    built = {tuple(loop["dummies"]): loop["built_as"] for loop in doc["loops"]}
    assert len(built) == 4 and any("RG2_leftJoint4 (spherical)" in b for b in built.values())
    code, text, _ = show(capsys, str(shared("data", "scenes", "course2", "jansen_solvespace.ttt")))
    assert "Loop closures:" in text
    assert text.count("two point constraints on its axis") == 3
    assert "Dummy5 <-> Dummy6: both fixed in the world" in text
