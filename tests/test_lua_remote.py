"""Remote API clients and scene scripts together: simxCallScriptFunction, shared signals,
the ports scenes serve, and the course's complexCommandTest.py against its own scene."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from shared_data import shared

REPO = Path(__file__).resolve().parents[1]
ARM = REPO / "data" / "scenes" / "lua_arm.simscene.xml"


def _run(script: Path, scene: Path, *extra: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "sims.remote_api",
            "run",
            str(script),
            "--scene",
            str(scene),
            *extra,
        ],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=REPO,
    )


def test_complex_command_test_gets_its_answers_from_the_scene_lua_function():
    folder = shared("data", "scenes", "vrep_remoteapi_ex", "vrep_ex")
    done = _run(folder / "complexCommandTest.py", folder / "remoteApiCommandServerExample.ttt")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    # what it prints against CoppeliaSim (V-REP 3.3.1); the dummy's handle is the next free one
    assert lines[:3] == [
        "Program started",
        "Connected to remote API server",
        "Return string:  message was displayed",
    ]
    assert lines[3].startswith("Dummy handle:  ") and int(lines[3].split()[-1]) > 0
    assert lines[4:] == ["Code execution returned:  done", "Program ended"]
    assert "Message from the remote API client: Hello world!" in done.stderr  # the dialog
    assert "Remote function call failed" not in done.stdout


def test_a_port_no_script_started_is_refused(tmp_path):
    folder = shared("data", "scenes", "vrep_remoteapi_ex", "vrep_ex")
    script = tmp_path / "wrong_port.py"
    script.write_text(
        "import sim\n"
        "print(sim.simxStart('127.0.0.1', 19998, True, True, 5000, 5))\n"
        "print(sim.simxStart('127.0.0.1', 19999, True, True, 5000, 5))\n",
        encoding="utf-8",
    )
    done = _run(script, folder / "remoteApiCommandServerExample.ttt", "--server", "temporary")
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["-1", "0"]
    assert "no remote API server on port 19998" in done.stderr


def test_signals_are_shared_between_client_and_scene_scripts(tmp_path):
    script = tmp_path / "signals.py"
    script.write_text(
        textwrap.dedent(
            """
            import time
            import sim

            cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
            sim.simxStartSimulation(cid, sim.simx_opmode_blocking)
            time.sleep(1.0)
            code, passes = sim.simxGetIntegerSignal(cid, 'armPasses', sim.simx_opmode_blocking)
            print('passes', code, passes)
            sim.simxSetFloatSignal(cid, 'flagSpeed', 0.0, sim.simx_opmode_blocking)
            time.sleep(2.5)
            _, flag = sim.simxGetObjectHandle(cid, 'FlagJoint', sim.simx_opmode_blocking)
            _, a = sim.simxGetJointPosition(cid, flag, sim.simx_opmode_blocking)
            time.sleep(1.0)
            _, b = sim.simxGetJointPosition(cid, flag, sim.simx_opmode_blocking)
            print('flag still', abs(b - a) < 0.02)
            res = sim.simxCallScriptFunction(cid, 'Arm', sim.sim_scripttype_childscript,
                                             'sysCall_sensing', [], [], [], bytearray(),
                                             sim.simx_opmode_blocking)
            print('call', res[0])
            sim.simxStopSimulation(cid, sim.simx_opmode_blocking)
            sim.simxFinish(cid)
            """
        ),
        encoding="utf-8",
    )
    done = _run(script, ARM)
    assert done.returncode == 0, done.stderr
    words = done.stdout.split()
    assert words[:2] == ["passes", "0"] and 18 <= int(words[2]) <= 22  # one per 50 ms pass
    assert "flag still True" in done.stdout  # the client's signal reached the threaded script
    assert "call 0" in done.stdout


def test_read_vision_sensor_gives_the_default_processing_packet(tmp_path):
    script = tmp_path / "vision.py"
    script.write_text(
        textwrap.dedent(
            """
            import sim

            cid = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
            _, cam = sim.simxGetObjectHandle(cid, 'Camera', sim.simx_opmode_blocking)
            code, detected, packets = sim.simxReadVisionSensor(cid, cam, sim.simx_opmode_blocking)
            _, res, image = sim.simxGetVisionSensorImage(cid, cam, 0, sim.simx_opmode_blocking)
            rgb = [v & 255 for v in image]
            grey = [sum(rgb[i:i + 3]) / 3 / 255 for i in range(0, len(rgb), 3)]
            print(code, detected, len(packets), *packets[0])
            print(min(grey), max(grey), sum(grey) / len(grey))
            """
        ),
        encoding="utf-8",
    )
    done = _run(script, REPO / "data" / "scenes" / "rover.simscene.xml")
    assert done.returncode == 0, done.stderr
    first, second = done.stdout.splitlines()
    code, detected, count, *packet = first.split()
    assert (code, detected, count) == ("0", "False", "1")
    values = [float(v) for v in packet]
    assert len(values) == 15 and all(0.0 <= v <= 1.0 for v in values)
    lo, hi, avg = values[0:5], values[5:10], values[10:15]
    assert all(a <= m <= b for a, m, b in zip(lo, avg, hi, strict=True))
    # intensity min/max/average agree with the image simxGetVisionSensorImage returns
    g_min, g_max, g_avg = (float(v) for v in second.split())
    assert (lo[0], hi[0], avg[0]) == pytest.approx((g_min, g_max, g_avg), abs=2e-3)
