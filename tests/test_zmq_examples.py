"""CoppeliaSim's own ZeroMQ remote API examples (../shared/data/scenes/zmq-examples, unchanged
from CoppeliaRobotics/zmqRemoteApi) run on the emulation, on the scenes the project writes to
match them (sims/remote_api/example_scenes.py), doing what their comments say.

``opencv.py`` is left out: it shows images in an OpenCV window (``cv2.imshow``), which a
headless run cannot open; ``synchronousImageTransmission.py`` covers the same calls.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from sims.remote_api.runner import run_script
from sims.remote_api.zmq.functions import load

EXAMPLES = Path(__file__).resolve().parents[2] / "shared" / "data" / "scenes" / "zmq-examples"
NEEDS = {
    "simpleTest.py": ["sim.createDummy", "sim.removeObject", "sim.addLog"],
    "simpleTest-nonBlocking.py": ["sim.createDummy", "sim.removeObject", "sim.addLog"],
    "pController.py": ["sim.loadScene", "sim.setJointTargetForce", "sim.getStringParam"],
    "synchronousImageTransmission.py": ["sim.loadScene", "sim.setVisionSensorImg"],
    "simpleMovement.py": ["sim.loadScene", "sim.moveToConfig", "sim.moveToPose",
                          "sim.rotateAroundAxis"],
}  # fmt: skip


def _run(name: str, capsys, timeout: float = 120.0):
    from shared_data import shared

    script = shared("data", "scenes", "zmq-examples", name)
    missing = [f for f in NEEDS[name] if f not in load()]
    if missing:
        pytest.skip(f"{name} needs {', '.join(missing)} from the sim.* table (simapi's half)")
    result = run_script(script, "2w1a", timeout=timeout)
    out = capsys.readouterr().out
    assert result.exit_code == 0, result.message
    assert not result.missing, result.missing
    assert out.splitlines()[0] == "Program started" and out.rstrip().endswith("Program ended")
    return result, out


def _times(out: str, kind: str) -> list[float]:
    return [float(t) for t in re.findall(rf"Simulation time: ([\d.]+) \[s\] \({kind}", out)]


@pytest.mark.needs_shared("data", "scenes", "zmq-examples", "simpleTest.py")
@pytest.mark.parametrize("name", ["simpleTest.py", "simpleTest-nonBlocking.py"])
def test_simple_tests_run_free_then_stepped(name, capsys):
    """50 dummies made and placed, 3 s free-running, 3 s stepped (one line per 50 ms step),
    the dummies removed."""
    result, out = _run(name, capsys)
    free = _times(out, "simulation running asynchronously")
    stepped = _times(out, "simulation running synchronously")
    assert free and max(free) < 3.0 and free == sorted(free)
    assert stepped[0] == 0.0 and len(stepped) == 60  # 0.00 .. 2.95: one line per step
    assert all(abs(b - a - 0.05) < 1e-6 for a, b in zip(stepped, stepped[1:], strict=False))
    assert result.simulations == 2


@pytest.mark.needs_shared("data", "scenes", "zmq-examples", "pController.py")
def test_p_controller_reaches_each_angle(capsys):
    """moveToAngle loops until the joint is within 0.1 degrees of 45, 90, -89 and 0 degrees:
    the run ends only when the motor got it there each time."""
    result, _ = _run("pController.py", capsys)
    assert 0.2 < result.sim_time < 30


@pytest.mark.needs_shared("data", "scenes", "zmq-examples", "synchronousImageTransmission.py")
def test_synchronous_image_transmission_runs_15_stepped_seconds(capsys):
    result, _ = _run("synchronousImageTransmission.py", capsys, timeout=300)
    assert result.sim_time == pytest.approx(15.0, abs=0.06)


@pytest.mark.needs_shared("data", "scenes", "zmq-examples", "simpleMovement.py")
def test_simple_movement_three_robots_in_lock_step(capsys):
    """Three clients in three threads, each stepping: moveToConfig on the blue and red arms,
    moveToPose of the green robot's target."""
    result, _ = _run("simpleMovement.py", capsys, timeout=300)
    assert result.sim_time > 2.0
