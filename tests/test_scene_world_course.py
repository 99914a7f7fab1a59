"""The course's own scripts run unchanged on their own scene files and do what they do in
CoppeliaSim (checked on positions and joint angles, with no missing names or functions)."""

from __future__ import annotations

import io
import math
import re
import subprocess
import sys
from pathlib import Path

import pytest
from shared_data import shared

from sims.remote_api.runner import run_script
from sims.world import World

REPO = Path(__file__).resolve().parents[1]
ARM = ("ShoulderMotor", "ElbowMotor", "WristMotor")


def pack(*parts: str) -> Path:
    return shared("data", "scenes", "vrep_remoteapi_ex", *parts)


def run(script: Path, scene: Path, joints=(), stdin: str | None = None, **kw):
    """Run on a World of ``scene``; returns the result, stdout and, per simulation pass, the
    named joints' positions (radians) and the simulation number."""
    log: list[tuple[int, dict[str, float]]] = []
    world = World(scene)

    def on_pass(sim):
        log.append((sim.starts, {j: sim.world.joint_position(j) for j in joints}))

    out = io.StringIO()
    saved_stdin, saved_stdout = sys.stdin, sys.stdout
    sys.stdin, sys.stdout = io.StringIO(stdin or ""), out
    try:
        result = run_script(script, str(scene), world=world, on_pass=on_pass, **kw)
    finally:
        sys.stdin, sys.stdout = saved_stdin, saved_stdout
        world.close()
    assert result.missing == [], result.missing
    return result, out.getvalue(), log


def test_2w1a_script_moves_the_robot_and_its_arm():
    result, out, log = run(pack("2w1a", "2w1a.py"), pack("2w1a", "2w1a.ttt"), joints=ARM, seed=7)
    assert result.exit_code == 0, result.message
    assert result.simulations == 3 and out.count("Motors target positions") == 15
    for run_no in (1, 2, 3):
        samples = [s for s in result.samples if s.run == run_no]
        start = samples[0]
        moved = max(math.hypot(s.x - start.x, s.y - start.y) for s in samples)
        assert moved > 0.01, f"run {run_no}: the body did not move"
    # every commanded target comes from random.randint(0, 300); the arm swings widely
    for joint in ARM:
        angles = [math.degrees(values[joint]) for _, values in log]
        assert max(angles) - min(angles) > 90, joint
        assert -1 <= min(angles) and max(angles) <= 301  # the saved range 0..300 deg


def test_bubblerob_drives_off_turning():
    result, out, _ = run(
        pack("bubble", "bubbleRob_remoteAPI.py"),
        pack("bubble", "bubbleRob_remoteAPI.ttt"),
        after=3.0,
    )
    assert result.exit_code == 0 and out.strip() == "Connected to remote server"
    first, last = result.samples[0], result.samples[-1]
    assert math.hypot(last.x - first.x, last.y - first.y) > 0.1  # right wheel 2 rad/s, left 0
    turned = math.atan2(
        math.sin(last.heading - first.heading), math.cos(last.heading - first.heading)
    )
    assert turned > 0.3  # the left wheel stands still: it turns left


def test_one_link_robot_turns_while_the_script_reads_its_keyboard():
    joint = "Revolute_joint"
    lines = "\n" * 20 + "p\n" + "\n" * 10 + "e\n"
    result, out, log = run(
        pack("onelink", "one_link_robot_remoteAPI.py"),
        pack("onelink", "one_link_robot_remoteAPI.ttt"),
        joints=(joint,),
        stdin=lines,
    )
    assert result.exit_code == 0, result.message
    assert "exiting" in out and out.count("(e to exit, p to pause and enter to exec)>") == 32
    angles = [values[joint] for _, values in log]
    # 2 rad/s while the simulation runs: each blocking call waits for a 50 ms pass
    assert angles[-1] - angles[0] == pytest.approx(2.0 * (len(angles) - 1) * 0.05, rel=0.15)


def test_one_link_robot_from_the_command_line_with_stdin(tmp_path):
    feed = tmp_path / "keys.txt"
    feed.write_text("\n" * 5 + "e\n", encoding="utf-8")
    proc = subprocess.run(
        [
            sys.executable,
            "-m",
            "sims.remote_api",
            "run",
            str(pack("onelink", "one_link_robot_remoteAPI.py")),
            "--scene",
            str(pack("onelink", "one_link_robot_remoteAPI.ttt")),
            "--stdin",
            str(feed),
            "--strict",
        ],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.count(">") == 6 and "exiting" in proc.stdout
    assert "lacks" not in proc.stderr and "127.0.0.1:19999" in proc.stderr


def test_four_bar_turns_with_its_loop_closed():
    joints = ("Revolute_joint", "Revolute_joint0", "Revolute_joint1")
    scene = pack("fourbar", "solvespace_fourbar_with_motor_on.ttt")
    result, _, log = run(pack("fourbar", "fourbar_remoteAPI.py"), scene, joints=joints, after=3.0)
    assert result.exit_code == 0, result.message
    crank = [values["Revolute_joint"] for _, values in log]
    assert crank[-1] - crank[0] == pytest.approx(2.0 * 3.0, rel=0.1)  # 2 rad/s for 3 s
    coupler = [values["Revolute_joint0"] for _, values in log]
    assert max(coupler) - min(coupler) > 0.5  # the rest of the linkage follows
    with World(scene) as w:  # the two linked dummies stay together while it turns
        w.set_joint_target_velocity("Revolute_joint", 2.0)
        for _ in range(6):
            w.advance(0.5)
            a, b = (w.object_pose(n)[0] for n in ("Dummy", "Dummy0"))
            assert math.dist(a, b) < 0.01


def test_pioneer_component_test_moves_its_joints():
    joints = ("joint_force", "joint_position", "joint_passive", "joint_spring")
    result, _, log = run(
        pack("pioneer", "testallcomponent.py"),
        pack("pioneer", "testAllComponents.ttt"),
        joints=joints,
    )
    assert result.exit_code == 0, result.message
    running = [values for n, values in log if n == log[-1][0]]  # the last simulation
    last = running[-1]
    velocity = [v["joint_force"] for v in running]
    assert velocity[-1] - velocity[0] > 10  # 2 rad/s for the whole run
    assert last["joint_position"] == pytest.approx(math.pi / 9 * 4 + 0.2, abs=0.05)
    assert last["joint_passive"] == pytest.approx(math.sin(49 / 10), abs=0.01)
    springs = [v["joint_spring"] for v in running]
    assert max(springs) - min(springs) > 0.1  # pulled towards its new rest position 2 rad


def test_pioneer_drives_and_reads_its_ultrasonic_sensors():
    motors = ("Pioneer_p3dx_leftMotor", "Pioneer_p3dx_rightMotor")
    result, _, log = run(
        pack("pioneer", "pioneer.py"), pack("pioneer", "Pioneer.ttt"), joints=motors
    )
    assert result.exit_code == 0, result.message
    assert result.final_state == "stopped" and result.sim_time > 10  # 100 steps of 0.1 s
    turned = [abs(log[-1][1][m] - log[0][1][m]) for m in motors]
    assert min(turned) > 5  # 2 rad/s, forwards or turning on the spot
    first, last = result.samples[0], result.samples[-1]
    moved = math.hypot(last.x - first.x, last.y - first.y)
    assert moved > 0.05 or abs(last.heading - first.heading) > 0.5


def test_pioneer_ultrasonic_sensor_measures_a_wall_ahead():
    with World(pack("pioneer", "Pioneer.ttt")) as w:
        names = {e.name for e in w.tree() if e.kind == "proximity_sensor"}
        assert {"Pioneer_p3dx_ultrasonicSensor3", "Pioneer_p3dx_ultrasonicSensor6"} <= names
        hits = {n: w.proximity(n) for n in names}
        assert all(d is None or 0 < d <= 1.0 for d in hits.values())


@pytest.mark.parametrize("folder", ["python", "vrep_ex"])
def test_simple_test_counts_the_objects_of_its_scene(folder):
    scene = pack("vrep_ex", "remoteApiCommandServerExample.ttt")
    result, out, _ = run(pack(folder, "simpleTest.py"), scene)
    assert result.exit_code == 0, result.message
    count = int(re.search(r"Number of objects in the scene:\s+(\d+)", out).group(1))
    with World(scene) as w:
        assert count == len(w.tree())
    assert "Program ended" in out


def test_checkpoint_ur3_arms_reach_the_commanded_angles():
    folder = shared("data", "scenes", "course")
    result, out, _ = run(folder / "Scene_CheckPoint1.py", folder / "Scene_CheckPoint1.ttt")
    assert result.exit_code == 0, result.message
    values = [float(v) for v in re.findall(r"theta = (-?[\d.]+|nan)", out)]
    assert len(values) == 24 and all(math.isfinite(v) for v in values)
    before, after = values[:12], values[12:]
    # order printed: joint1, joint1_2, joint2, joint2_2, ... joint6, joint6_2
    deltas = [
        -1 / 6,
        1 / 6,
        1 / 6,
        -1 / 6,
        -1 / 4,
        1 / 4,
        1 / 4,
        -1 / 4,
        1 / 3,
        0.0,
        1 / 2,
        -1 / 2.5,
    ]
    for b, a, d in zip(before, after, deltas, strict=True):
        assert a == pytest.approx(b + d * math.pi, abs=0.01)


def test_2w1a_scene_has_self_collision():
    """The scene's respondable masks let the arm and hand hit the body: a pose that folds the
    arm into the body is blocked (a model without them passed through to within 3 degrees)."""
    with World("2w1a") as w:
        for joint, deg in zip(ARM, (68, 291, 32), strict=True):
            w.set_joint_target_position(joint, math.radians(deg))
        w.advance(5.0)
        reached = [math.degrees(w.joint_position(j)) for j in ARM]
    assert max(abs(a - b) for a, b in zip(reached, (68, 291, 32), strict=True)) > 10
