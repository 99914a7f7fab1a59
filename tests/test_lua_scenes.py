"""The course scenes' own scripts (../shared/data/scenes): every scene runs 10 simulated
seconds; the function table in docs/lua.md is the scan's; the line follower and the table
football scene under their course scripts."""

from __future__ import annotations

import math
import subprocess
import sys
from pathlib import Path

import pytest
from shared_data import SHARED, shared

from tools.lua_usage import markdown_table, scan, scene_files

REPO = Path(__file__).resolve().parents[1]
SCENES = SHARED / "data" / "scenes"
ALL = [str(p.relative_to(SCENES)) for p in scene_files(SCENES)] if SCENES.is_dir() else ["none"]


@pytest.mark.parametrize("name", ALL)
def test_every_course_scene_runs_its_scripts_for_ten_seconds(name):
    from sims.lua.run import run_scene

    path = shared("data", "scenes", name)
    result = run_scene(path, 10.0)
    assert result.errors == []
    for m in result.missing:  # reported with scene, script and line
        assert m.scene == path.name and m.script and m.line > 0


def test_scripts_start_the_remote_api_servers_the_example_scripts_use():
    from sims.lua.run import run_scene

    for name in ("bubble/bubbleRob_remoteAPI.ttt", "onelink/one_link_robot_remoteAPI.ttt"):
        result = run_scene(shared("data", "scenes", "vrep_remoteapi_ex", name), 0.2)
        assert result.ports == [19999], name


def test_function_table_in_docs_is_the_scan_and_every_sim_function_is_emulated():
    rows = scan(shared("data", "scenes"))
    docs = (REPO / "docs" / "lua.md").read_text(encoding="utf-8")
    assert markdown_table(rows) in docs
    assert [u.function for u in rows if u.function.startswith("sim.") and not u.emulated] == []
    # a plug-in namespace that is not emulated is named in docs/lua.md with its reason
    for u in rows:
        if not u.emulated:
            prefix = u.function.split(".")[0].split("_")[0]
            assert f"`{prefix}_*` functions" in docs or f"`{prefix}.*` functions" in docs, u
    names = {u.function for u in rows}
    assert {"sim.getObjectHandle", "simRemoteApi.start", "sim.setJointTargetVelocity"} <= names


def _drive_line_follower(tmp_path: Path) -> list[list[float]]:
    course = shared("data", "scenes", "course")
    driver = tmp_path / "drive.py"
    driver.write_text(
        f"import sys, time\nsys.path.insert(0, {str(course)!r})\n"
        "import vrep\n"
        "from vrep_linefollower import VrepLineFollower\n"
        "lf = VrepLineFollower()\n"
        "cid = lf.clientID\n"
        "_, body = vrep.simxGetObjectHandle(cid, 'LineTracer', vrep.simx_opmode_blocking)\n"
        "def pose():\n"
        "    _, p = vrep.simxGetObjectPosition(cid, body, -1, vrep.simx_opmode_blocking)\n"
        "    print('pose', *p)\n"
        "pose()\n"
        "vrep.simxStartSimulation(cid, vrep.simx_opmode_blocking)\n"
        "time.sleep(2)\n"
        "pose()\n"
        "lf.set_motors()\n"
        "time.sleep(3)\n"
        "pose()\n"
        "for _ in range(3):\n"
        "    lf.to_direction('left')\n"
        "time.sleep(3)\n"
        "pose()\n",
        encoding="utf-8",
    )
    done = subprocess.run(
        [sys.executable, "-m", "sims.remote_api", "run", str(driver), "--scene",
         str(course / "simpleLineFollower_api.ttt")],
        capture_output=True, text=True, timeout=300, cwd=REPO,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return [
        [float(v) for v in line.split()[1:]]
        for line in done.stdout.splitlines()
        if line.startswith("pose")
    ]


def test_line_follower_sits_still_under_its_own_scripts_and_the_course_class_steers_it(tmp_path):
    start, after_own, forward, turned = _drive_line_follower(tmp_path)
    # its child script is empty (threaded, 0 lines): 2 s of its own scripts leave it in place
    assert math.dist(start, after_own) < 0.005
    # VrepLineFollower.set_motors: 0.1 m/s on both wheels (radius 0.027 m) for 3 s, along +x
    assert forward[0] - after_own[0] == pytest.approx(0.3, abs=0.03)
    assert abs(forward[1] - after_own[1]) < 0.03
    # three 'left' steps: left wheel 0.07 m/s, right 0.13 m/s: it curves to its left (+y)
    assert turned[1] - forward[1] > 0.15


def test_avsb_plays_table_football_from_scripted_key_presses(tmp_path):
    from sims.lua import keys
    from sims.remote_api.runner import run_script

    course = shared("data", "scenes", "course")
    keys_file = tmp_path / "keys.txt"
    keys_file.write_text(
        "# seconds duration key\n0.5 1.0 z\n3.0 1.0 c\n4.5 end\n", encoding="utf-8"
    )
    keys.configure(keys.load(keys_file))
    rods: list[float] = []
    try:
        result = run_script(
            course / "AvsB.py",
            str(course / "tablefootball.ttt"),
            isolate=False,
            on_pass=lambda sim: rods.append(sim.world.object_pose("BRod")[0][1]),
        )
    finally:
        keys.configure(None)
    assert result.exit_code == 0, result.message
    assert 4.4 <= result.sim_time <= 4.8  # the keyboard closed at 4.5 s: the script stopped
    # "z" drives the blue rod at +0.2 m/s (y grows), "c" brings it back at -0.2 m/s
    top = max(rods)
    assert top - rods[0] > 0.2
    assert top - rods[-1] > 0.1


def test_keys_file_errors_name_file_line_and_field(tmp_path):
    from sims.lua.keys import KeysFileError, load

    bad = tmp_path / "keys.txt"
    bad.write_text("0.5 1 z\nsoon 1 x\n", encoding="utf-8")
    with pytest.raises(KeysFileError, match=r"keys.txt:2: seconds: not a number: 'soon'"):
        load(bad)
