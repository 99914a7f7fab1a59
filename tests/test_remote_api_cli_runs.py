"""`sitegen remote-api run` as a new user meets it (issue 29's small things): arguments after
the options, the summary line, a script on the wrong scene, pybullet's banner, CoppeliaSim's
client modules kept in a script's own package, the asyncio client, and key files."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from sims.remote_api.cli import main, split_script_args
from sims.remote_api.run_result import RunResult, speed_note
from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parents[1]


def _script(tmp_path: Path, text: str, name: str = "s.py") -> Path:
    path = tmp_path / name
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(textwrap.dedent(text), encoding="utf-8")
    return path


def test_options_after_the_script_and_script_arguments_after_dashes(tmp_path, capsys):
    script = _script(
        tmp_path,
        """
        import sys, sim
        cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
        r, h = sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
        print('argv', sys.argv[1:], r)
        """,
    )
    assert split_script_args(["run", "s", "--scene", "x", "--", "a", "--b"]) == (
        ["run", "s", "--scene", "x"],
        ["a", "--b"],
    )
    code = main(["run", str(script), "--scene", "2w1a", "--timeout", "20", "--", "a", "--b"])
    out = capsys.readouterr().out
    assert code == 0
    assert "argv ['a', '--b'] 0" in out


def test_summary_speed_is_never_zero_or_infinite():
    assert speed_note(0.0, 0.0) == ""  # a missing script: no run, no speed
    assert speed_note(0.0, 1.3) == ""
    assert speed_note(5.0, 20.0) == " (0.2x real time)"  # slower than real time
    assert speed_note(80.0, 1.6) == " (50x real time)"
    missing = RunResult("gone.py", "2w1a", exit_code=2, message="gone.py: no such script file")
    assert "x real time" not in missing.summary() and "inf" not in missing.summary()


def test_script_on_the_wrong_scene_fails(tmp_path, capsys):
    script = _script(
        tmp_path,
        """
        import sim
        cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
        for name in ('left_m', 'right_m'):
            print(sim.simxGetObjectHandle(cid, name, sim.simx_opmode_blocking))
        """,
    )
    code = main(["run", str(script), "--scene", "2w1a"])
    err = capsys.readouterr().err
    assert code == 3
    assert "none of the 2 object(s) the script asked for is in scene 2w1a" in err
    # one object found is enough: the script may probe for optional ones
    ok = _script(
        tmp_path,
        """
        import sim
        cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
        sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
        sim.simxGetObjectHandle(cid, 'NoSuchThing', sim.simx_opmode_blocking)
        """,
        "ok.py",
    )
    assert run_script(ok, "2w1a").exit_code == 0


def test_no_pybullet_banner_on_help_or_runs(tmp_path):
    script = _script(tmp_path, "import sim\nprint('hi')\n")
    for argv in (["--help"], ["run", str(script), "--scene", "2w1a", "-q"]):
        done = subprocess.run(
            [sys.executable, "-m", "sims.remote_api", *argv],
            capture_output=True,
            text=True,
            cwd=REPO,
            timeout=120,
        )
        assert done.returncode == 0, done.stderr
        assert "pybullet build time" not in done.stdout + done.stderr


COPPELIA_SIM_PY = """\
# CoppeliaSim's sim.py, as students keep it beside their code: it loads the native library
import ctypes as ct
libsimx = ct.CDLL("./remoteApi.so")  # "The remoteApi library could not be loaded"
def simxStart(connectionAddress, connectionPort, a, b, c, d):
    return -1
"""


def test_coppeliasim_sim_py_inside_a_package_loads_the_emulation(tmp_path):
    _script(tmp_path, COPPELIA_SIM_PY, "robot/sim.py")
    _script(tmp_path, "", "robot/__init__.py")
    own = "# the student's own helpers named sim: left alone\nVALUE = 42\n"
    _script(tmp_path, own, "own/sim.py")
    _script(tmp_path, "", "own/__init__.py")
    _script(
        tmp_path,
        """
        from . import sim
        def joint():
            cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
            return sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
        """,
        "robot/arm.py",
    )
    main_script = _script(
        tmp_path,
        """
        from robot import arm
        from robot.sim import simx_return_ok
        from own.sim import VALUE
        code, handle = arm.joint()
        assert code == simx_return_ok and handle > 0, (code, handle)
        print('joint', handle, VALUE)
        """,
        "main.py",
    )
    result = run_script(main_script, "2w1a")
    assert result.exit_code == 0, result.message


def test_asyncio_client_steps_and_sleeps_in_virtual_time(tmp_path, capsys):
    script = _script(
        tmp_path,
        """
        import asyncio
        from coppeliasim_zmqremoteapi_client.asyncio import RemoteAPIClient

        async def main():
            async with RemoteAPIClient() as client:
                sim = await client.require('sim')
                a, b = await asyncio.gather(sim.getObject('/2W1A'), sim.getObject('/ShoulderMotor'))
                await sim.setStepping(True)
                await sim.startSimulation()
                await sim.setJointTargetPosition(b, 2.0)
                while (t := await sim.getSimulationTime()) < 2:
                    await sim.step()
                print('angle', round(await sim.getJointPosition(b), 2), 'at', round(t, 2))
                await sim.stopSimulation()
                await asyncio.sleep(30)  # 30 virtual seconds, not 30 wall seconds
                print('state', await sim.getSimulationState() == sim.simulation_stopped)

        asyncio.run(main())
        """,
    )
    result = run_script(script, "2w1a", timeout=60)
    out = capsys.readouterr().out
    assert result.exit_code == 0, result.message
    assert "state True" in out
    angle = float(out.split("angle ")[1].split()[0])
    assert abs(angle - 2.0) < 0.05  # the shoulder reached its target
    assert result.clock_time >= 30 and result.wall_time < 20


def test_key_file_end_is_a_clean_end_and_record_replays_arguments(tmp_path, monkeypatch):
    keys = tmp_path / "keys.txt"
    keys.write_text("0.5 1.0 z\n", encoding="utf-8")
    script = _script(
        tmp_path,
        """
        import sys, time, keyboard, sim
        cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
        _, m = sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
        sim.simxStartSimulation(cid, sim.simx_opmode_blocking)
        while True:  # ended by Ctrl+C at a real keyboard, by the key file's end here
            if keyboard.is_pressed(sys.argv[1]):
                sim.simxSetJointTargetPosition(cid, m, 2.5, sim.simx_opmode_oneshot)
            time.sleep(0.05)
        """,
    )
    seen = {}

    def fake_record(args, scene, seconds):
        seen.update(args=list(args.script_args), keys=args.keys, seconds=seconds)
        return [], None

    monkeypatch.setattr("sims.remote_api.cli.record_clip", fake_record)
    code = main(
        ["run", str(script), "--scene", "2w1a", "--keys", str(keys), "--record",
         str(tmp_path / "c.webm"), "--", "z"]
    )  # fmt: skip
    assert code == 0
    assert seen["args"] == ["z"] and seen["keys"] == str(keys)
    assert 1.4 < seen["seconds"] < 1.7  # the run ended with its key file (1.5 s)


def test_clip_keys_args_and_python_in_sitegen_yml(tmp_path):
    from sims.clips import ClipSpec
    from sims.remote_api.script_clips import script_plan
    from sitegen.config import parse_config

    (tmp_path / "keys.txt").write_text("0.2 0.6 a\n", encoding="utf-8")
    script = _script(
        tmp_path,
        """
        import sys, time, keyboard, sim
        cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
        sim.simxGetObjectHandle(cid, 'ShoulderMotor', sim.simx_opmode_blocking)
        sim.simxStartSimulation(cid, sim.simx_opmode_blocking)
        assert sys.argv[1:] == ['fast'], sys.argv
        while True:
            keyboard.is_pressed('a')
            time.sleep(0.05)
        """,
        "drive.py",
    )
    text = textwrap.dedent(
        """\
        sims:
          clips:
            - name: drive
              script: drive.py
              scene: 2w1a
              keys: keys.txt
              args: [fast]
              python: python3
        """
    )
    config = parse_config(text, tmp_path, file="sitegen.yml")
    clip = config.sims.clips[0]
    assert clip.keys == tmp_path / "keys.txt" and clip.args == ("fast",)
    assert clip.python == "python3"
    bad = text.replace("keys: keys.txt", "keys: nope.txt")
    try:
        parse_config(bad, tmp_path, file="sitegen.yml")
    except Exception as exc:  # BuildError naming the line and field
        assert "sitegen.yml:6" in str(exc.diagnostics[0].format()) or "keys" in str(exc)
    else:
        raise AssertionError("a missing key file must be an error")
    spec = ClipSpec(
        name="drive",
        scenario=str(script),
        kind="script",
        params={"scene": "2w1a", "keys": str(tmp_path / "keys.txt"), "args": ["fast"]},
    )
    plan = script_plan(spec)
    assert 0.75 < plan.length() < 1.0  # measured: the run ends with its key file (0.8 s)
    assert str(tmp_path / "keys.txt") in plan.hash_files


def test_function_listing_covers_every_function_and_the_docs_name_them():
    from sims.remote_api import api
    from sims.remote_api.functions import legacy_rows, zmq_rows

    legacy = {r.name: r for r in legacy_rows()}
    names = {n for n in api.__all__ if n.startswith("simx") and not n.startswith("simx_")}
    assert set(legacy) == names and len(names) >= 133  # every function of CoppeliaSim's sim.py
    assert legacy["simxCreateDummy"].status.startswith("via sim.createDummy")
    assert (
        legacy["simxGetJointPosition"].status == "emulated" and legacy["simxGetJointPosition"].wire
    )
    assert legacy["simxDisplayDialog"].status == "not supported"
    zmq = {r.name for r in zmq_rows()}
    assert {"sim.loadScene", "sim.createDummy", "sim.moveToConfig", "sim.step"} <= zmq
    docs = (REPO / "docs" / "remote-api.md").read_text(encoding="utf-8")
    missing = [n for n in [*legacy, *zmq] if f"| `{n}` |" not in docs]
    assert not missing, (
        f"docs/remote-api.md lacks {missing}: run python -m sims.remote_api.functions --markdown"
    )


@pytest.mark.needs_shared("data", "scenes", "course", "Scene_CheckPoint1.ttt")
def test_the_camera_follows_a_visible_robot_not_an_invisible_part():
    """--record's camera (World.model.robot): the UR3 arm, not the invisible cup it stands by;
    a scene where nothing is jointed: a visible shape of its own, not a camera or the floor."""
    from shared_data import shared

    from sims.world import World

    folder = shared("data", "scenes", "course")
    for name, expected in (
        ("Scene_CheckPoint1.ttt", "UR3"),
        ("fanuc_m710ic_50_pick_and_place.ttt", "Shape"),
    ):
        with World(str(folder / name)) as world:
            assert world.model.robot == expected, name
    with World("2w1a") as world:
        assert world.model.robot == "2W1A"


def test_the_zmq_examples_scenes_are_what_the_project_writes():
    """sims/scene/bundled/messaging/ holds exactly what example_scenes.py writes, and
    each scene has the objects CoppeliaSim's examples name."""
    from sims.remote_api.example_scenes import OUT, texts
    from sims.remote_api.zmq.paths import Tree, resolve
    from sims.world import World

    for name, text in texts().items():
        assert (OUT / name).read_text(encoding="utf-8") == text, f"regenerate {name}"
    wanted = {
        "pControllerViaRemoteApi": ["/Cuboid[0]/joint"],
        "synchronousImageTransmissionViaRemoteApi": ["/VisionSensor", "/PassiveVisionSensor"],
        "movementViaRemoteApi": ["/greenRobot/target"]
        + [f"/{c}Robot/joint{{{i}}}" for c in ("blue", "red") for i in range(7)],
    }
    for name, paths in wanted.items():
        with World(str(OUT / f"{name}.simscene.xml")) as world:
            tree = Tree(world.tree())
            for path in paths:
                assert resolve(tree, path) is not None, (name, path)
