"""Course scenes the project had not seen (../shared/data/scenes/course2) doing what their own
scripts mean them to do, checked by joint angles and positions over simulated time.

- Scene_CheckPoint3: the UR3's threaded ``sysCall_threadmain`` script moves the arm through
  three configurations with ``sim.rmlMoveToJointPositions`` (velocity 180 deg/s, acceleration
  40 deg/s^2, jerk 80 deg/s^3).
- invertedPendulum: the cart-pole's script balances the pendulum with a state feedback on the
  cart (``sim.addForce``, ``sim.getObjectVelocity``), driving the cart to x = 0.5 m, then to
  -0.3 m.
"""

from __future__ import annotations

import math

import pytest
from shared_data import shared

from sims.lua.host import ScriptHost
from sims.motion import Profile
from sims.world import World

DEG = math.pi / 180
UR3_TARGETS = [
    [90, 90, -90, 90, 90, 90],
    [-90, 45, 90, 135, 90, 90],
    [0, 0, 0, 0, 0, 0],
]


def _run(scene: str, seconds: float, names: list[str], every: float = 0.05):
    world = World(str(shared("data", "scenes", "course2", scene)))
    host = ScriptHost(world)
    handles = [world.find(n) for n in names]
    samples: list[tuple[float, list[float]]] = []

    def sample(w: World) -> None:
        if w.steps % host.steps_per_pass == 0:
            samples.append((w.time, [w.joint_position(h) for h in handles]))

    world.add_step_hook(sample)
    host.start()
    world.advance(seconds)
    errors, missing = list(host.errors), list(host.missing)
    host.close()
    world.close()
    return samples, errors, missing


def _at(samples, t: float) -> list[float]:
    return min(samples, key=lambda s: abs(s[0] - t))[1]


def _durations() -> list[float]:
    """How long each move takes: the same Ruckig profile CoppeliaSim's simRuckig computes
    (the joints start at rest, time-synchronised)."""
    out, start = [], [0.0] * 6
    for target in UR3_TARGETS:
        goal = [v * DEG for v in target]
        prof = Profile(start, [0.0] * 6, [0.0] * 6, [180 * DEG] * 6, [40 * DEG] * 6,
                       [80 * DEG] * 6, goal, [0.0] * 6)  # fmt: skip
        out.append(prof.duration)
        start = goal
    return out


def test_ur3_threaded_script_moves_through_its_three_configurations():
    d1, d2, d3 = _durations()
    names = [f"UR3_joint{i}" for i in range(1, 7)]
    samples, errors, missing = _run("Scene_CheckPoint3.ttt", d1 + d2 + d3 + 1.0, names)
    assert errors == [] and missing == []
    # the motors track the profile (position control, P 0.1, max 180 deg/s): within 1.5 deg of
    # each target shortly after the profile ends, and well away from it halfway
    ends = [d1, d1 + d2, d1 + d2 + d3]
    starts = [[0.0] * 6, UR3_TARGETS[0], UR3_TARGETS[1]]
    for end, duration, start, target in zip(ends, (d1, d2, d3), starts, UR3_TARGETS, strict=True):
        there = _at(samples, end + 0.25)
        assert there == pytest.approx([v * DEG for v in target], abs=1.5 * DEG), end
        half = _at(samples, end - duration / 2)
        far = max(abs(a - b * DEG) for a, b in zip(half, target, strict=True))
        span = max(abs(a - b) for a, b in zip(start, target, strict=True)) * DEG
        assert 0.3 * span < far < 0.7 * span  # halfway of an S-curve: about half the way
    # a joint moves only while its script says so: joints 5 and 6 (90 deg in both of the
    # first two configurations) stay at 90 deg throughout the second move
    second = [s for t, s in samples if ends[0] + 0.3 < t < ends[1]]
    assert all(abs(s[4] - 90 * DEG) < 1.5 * DEG and abs(s[5] - 90 * DEG) < 1.5 * DEG
               for s in second)  # fmt: skip


def test_cart_pole_stays_upright_and_drives_the_cart_where_its_script_says():
    samples, errors, missing = _run("invertedPendulum.ttt", 25.0, ["sliderJoint", "revoluteJoint"])
    assert errors == [] and missing == []
    # upright from 1 s on (the controller catches the initial tilt): within 10 deg of the
    # upright equilibrium throughout, within 2 deg from 1.5 s on except for the 1.5 s after
    # the set point jumps (the step in the reference tilts it by ~6 deg); CoppeliaSim's
    # Bullet build and its mass properties differ slightly, so the bounds leave room
    assert all(abs(th) < 10 * DEG for t, (_x, th) in samples if t > 1.0)
    xs = [(t, x) for t, (x, _th) in samples]
    assert xs[0][1] == pytest.approx(-0.7, abs=0.01)  # the cart starts at the slider's end
    # first set point 0.5 m: the cart gets there (the script switches at x >= 0.5)...
    top_t, top = max(xs, key=lambda s: s[1])
    assert top >= 0.49 and 10.0 < top_t < 16.0
    calm = [th for t, (_x, th) in samples if t > 1.5 and not top_t - 0.5 < t < top_t + 1.5]
    assert all(abs(th) < 2 * DEG for th in calm)
    # ...then the second set point, -0.3 m: back past zero, settling near it (the LQR's
    # steady-state offset of the angle term leaves it a few cm short)
    assert _at(samples, 25.0)[0] == pytest.approx(-0.3, abs=0.08)
    assert all(x <= top + 0.02 for t, x in xs if t > top_t)


def test_ur5_picks_the_first_block_off_the_belt_and_puts_it_down():
    """The conveyor carries the blocks to its sensor and stops; the UR5's threaded script
    moves over the block (rmlMoveToJointPositions), goes down by IK (rmlMoveToPosition of its
    IK target), closes the RG2 (a string signal its script reads), lifts the block and puts it
    down at its first drop place. The IK groups, the conveyor's path and belt and the gripper's
    loops are the World's (issue 28: sims/kinematics.py, sims/path_objects.py)."""
    pytest.importorskip("sims.path_objects")  # the World's mechanisms (issue 28)
    world = World(str(shared("data", "scenes", "course2", "ur5WithRg2Grasping.ttt")))
    host = ScriptHost(world)
    blocks = [world.find(n) for n in ("Cuboid4", "Cuboid3")]
    first, second = blocks
    start = [world.object_pose(b)[0] for b in blocks]
    host.start()
    highest = 0.0
    for _ in range(25 * 4):  # 25 simulated seconds
        world.advance(0.25)
        highest = max(highest, world.object_pose(first)[0][2])
    errors = list(host.errors)
    end = [world.object_pose(b)[0] for b in blocks]
    host.close()
    world.close()
    assert errors == []
    # the first block left the belt, was lifted above it and stands at the first drop place
    # (the script's dropConfig1, then down to z = 0.025 m); the second waits on the belt
    assert highest > start[0][2] + 0.1
    assert math.dist(end[0][:2], (0.075, -0.6)) < 0.03 and end[0][2] < 0.05
    assert abs(end[1][0] - start[1][0]) < 0.02 and end[1][2] == pytest.approx(start[1][2], abs=0.03)
