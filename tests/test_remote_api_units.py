"""Unit tests of the legacy remote API emulation: rotations, clock, op modes, return codes.

Everything runs against the real pybullet World; no socket is involved anywhere.
"""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pybullet as p
import pytest

from sims.remote_api import api as sim
from sims.remote_api import geometry as g
from sims.remote_api.client import Session, set_session
from sims.remote_api.clock import ScriptTimeout, VirtualClock, WallClock, patch_time
from sims.remote_api.execute import mode_of

B = sim.simx_opmode_blocking


def _rx(a):
    return np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])


def _ry(b):
    return np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])


def _rz(c):
    return np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])


@pytest.fixture
def session():
    """A configured 2W1A session on a virtual clock, made current for the sim functions."""
    s = Session("2w1a", clock=VirtualClock())
    previous = set_session(s)
    yield s
    set_session(previous)
    s.close()


@pytest.fixture
def client(session):
    cid = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
    assert cid == 0
    return cid


def handle(client, name):
    code, h = sim.simxGetObjectHandle(client, name, B)
    assert code == 0, name
    return h


# --- rotations -----------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "euler",
    [(0.3, -0.7, 1.9), (-2.5, 0.2, -0.4), (1.0, 1.2, 3.0), (0.0, 0.0, 0.0), (3.1, -1.5, -3.1)],
)
def test_euler_is_coppeliasim_xyz(euler):
    expected = _rx(euler[0]) @ _ry(euler[1]) @ _rz(euler[2])
    assert np.allclose(np.array(g.euler_to_matrix(euler)), expected)
    q = g.euler_to_quat(euler)
    assert np.allclose(np.array(g.quat_to_matrix(q)), expected)
    assert np.allclose(g.quat_to_euler(q), euler, atol=1e-9)
    # and pybullet agrees on what the quaternion means
    m = np.array(p.getMatrixFromQuaternion(q)).reshape(3, 3)
    assert np.allclose(m, expected, atol=1e-9)


def test_euler_gimbal_lock_still_reproduces_the_rotation():
    e = g.quat_to_euler(g.euler_to_quat((0.4, math.pi / 2, 0.3)))
    assert e[1] == pytest.approx(math.pi / 2)
    target = _rx(0.4) @ _ry(math.pi / 2) @ _rz(0.3)
    assert np.allclose(np.array(g.euler_to_matrix(e)), target, atol=1e-6)


def test_relative_frames_round_trip():
    ref_p, ref_q = (0.3, -0.2, 0.1), g.euler_to_quat((0.2, 0.4, -1.0))
    point = (1.0, 2.0, 3.0)
    rel = g.relative_position(point, ref_p, ref_q)
    assert np.allclose(g.to_world_position(rel, ref_p, ref_q), point)


# --- op modes and clock --------------------------------------------------------------------------
def test_operation_modes():
    assert mode_of(sim.simx_opmode_oneshot_wait) == sim.simx_opmode_blocking
    assert mode_of(sim.simx_opmode_streaming + 100) == sim.simx_opmode_streaming
    assert mode_of(sim.simx_opmode_oneshot_split + 200) == sim.simx_opmode_oneshot
    assert mode_of(sim.simx_opmode_continuous) == sim.simx_opmode_streaming
    assert mode_of(0x090000) is None and mode_of(-1) is None and mode_of(1.5) is None


def test_constants_match_the_reference():
    assert (
        sim.simx_return_ok,
        sim.simx_return_novalue_flag,
        sim.simx_return_timeout_flag,
        sim.simx_return_illegal_opmode_flag,
        sim.simx_return_remote_error_flag,
        sim.simx_return_split_progress_flag,
        sim.simx_return_local_error_flag,
        sim.simx_return_initialize_error_flag,
    ) == (0, 1, 2, 4, 8, 16, 32, 64)
    assert (
        sim.simx_opmode_oneshot,
        sim.simx_opmode_blocking,
        sim.simx_opmode_streaming,
        sim.simx_opmode_oneshot_split,
        sim.simx_opmode_streaming_split,
        sim.simx_opmode_discontinue,
        sim.simx_opmode_buffer,
        sim.simx_opmode_remove,
    ) == (0, 0x010000, 0x020000, 0x030000, 0x040000, 0x050000, 0x060000, 0x070000)


def test_virtual_clock_patches_only_the_script_thread():
    clock = VirtualClock()
    seen = []
    with patch_time(clock):
        t0 = time.time()
        time.sleep(100)
        seen.append(time.time() - t0)
        other = []
        th = threading.Thread(target=lambda: other.append(time.monotonic()))
        th.start()
        th.join()
    assert seen[0] == pytest.approx(100, abs=0.01)
    assert clock.now() == pytest.approx(100, abs=0.01)
    assert abs(other[0] - time.monotonic()) < 5  # the other thread saw the real clock
    with pytest.raises(ValueError):
        with patch_time(clock):
            time.sleep(-1)


def test_clock_limit_raises_script_timeout():
    clock = VirtualClock(limit=10)
    clock.advance(5)
    with pytest.raises(ScriptTimeout):
        clock.advance(6)
    wall = WallClock(limit=0.05)
    with pytest.raises(ScriptTimeout):
        wall.advance(1.0)


# --- connection and return codes ------------------------------------------------------------------
def test_start_needs_a_scene_and_never_opens_sockets(monkeypatch):
    import socket

    class NoSocket(socket.socket):
        def __init__(self, *a, **k):
            raise AssertionError("a socket was created")

    monkeypatch.setattr(socket, "socket", NoSocket)
    previous = set_session(None)
    try:
        monkeypatch.setattr("sims.remote_api.client._env_checked", True)
        assert sim.simxStart("192.168.192.1", 19997, True, True, 5000, 5) == -1
        s = Session("2w1a", clock=VirtualClock())
        set_session(s)
        assert [sim.simxStart("10.0.0.1", 19997, True, True, 5000, 5) for _ in range(3)] == [
            0,
            1,
            2,
        ]
        sim.simxFinish(1)
        assert sim.simxStart("x", 1, True, True, 5000, 5) == 1  # first free slot
        sim.simxFinish(-1)
        assert sim.simxGetConnectionId(0) == -1
        assert [(c.address, c.port) for c in s.connections][:1] == [("10.0.0.1", 19997)]
        s.close()
    finally:
        set_session(previous)


def test_calls_before_start_and_bad_arguments(session):
    assert sim.simxGetObjectHandle(0, "2W1A", B) == (64, 0)
    assert sim.simxGetObjectPosition(0, 1, -1, B) == (64, [0.0, 0.0, 0.0])
    assert sim.simxStartSimulation(0, B) == 64
    cid = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
    import ctypes

    with pytest.raises(ctypes.ArgumentError):
        sim.simxGetObjectPosition(cid, "2W1A", -1, B)


def test_streaming_buffer_and_oneshot_semantics(session, client):
    body = handle(client, "2W1A")
    code, pos = sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_streaming)
    assert (code, pos) == (1, [0.0, 0.0, 0.0])
    code, pos = sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_buffer)
    assert code == 0 and pos[0] == pytest.approx(-0.0201, abs=1e-4)
    assert pos[0] == float(np.float32(pos[0]))  # values travel as 32-bit floats
    # blocking replies are not kept
    elbow = handle(client, "ElbowMotor")
    assert sim.simxGetJointPosition(client, elbow, B)[0] == 0
    assert sim.simxGetJointPosition(client, elbow, sim.simx_opmode_buffer) == (1, 0.0)
    # oneshot setters: novalue the first time, then the previous reply
    assert sim.simxSetJointTargetPosition(client, elbow, 1.0, sim.simx_opmode_oneshot) == 1
    assert sim.simxSetJointTargetPosition(client, elbow, 1.0, sim.simx_opmode_oneshot) == 0
    # remove
    assert sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_remove)[0] == 0
    assert sim.simxGetObjectPosition(client, body, -1, sim.simx_opmode_remove)[0] == 1


def test_streamed_values_follow_the_running_simulation(session, client):
    wrist = handle(client, "WristMotor")
    sim.simxGetJointPosition(client, wrist, sim.simx_opmode_streaming)
    assert session.simulator.state == "stopped"
    sim.simxSetJointTargetPosition(client, wrist, math.radians(100), B)
    session.clock.advance(1.0)
    code, before = sim.simxGetJointPosition(client, wrist, sim.simx_opmode_buffer)
    assert code == 0 and math.degrees(before) == pytest.approx(250, abs=0.5)  # not running yet
    assert sim.simxStartSimulation(client, B) == 0
    session.clock.advance(3.0)  # the scene caps the wrist at 60 deg/s: 150 deg take 2.5 s
    code, after = sim.simxGetJointPosition(client, wrist, sim.simx_opmode_buffer)
    assert math.degrees(after) == pytest.approx(100, abs=3)
    assert session.simulator.sim_time == pytest.approx(3.05, abs=0.06)
    assert sim.simxStopSimulation(client, B) == 0  # resets the scene
    code, reset = sim.simxGetJointPosition(client, wrist, sim.simx_opmode_buffer)
    assert math.degrees(reset) == pytest.approx(250, abs=0.5)
    assert session.simulator.sim_time == 0.0


def test_remote_errors(session, client):
    assert sim.simxGetObjectHandle(client, "Nope", B) == (8, 0)
    assert sim.simxGetObjectHandle(client, "ElbowMotor#", B)[0] == 0
    assert sim.simxGetObjectHandle(client, "ElbowMotor#1", B) == (8, 0)
    assert sim.simxGetJointPosition(client, 12345, B) == (8, 0.0)
    body = handle(client, "2W1A")
    assert sim.simxSetJointTargetVelocity(client, body, 1.0, B) == 8
    assert sim.simxReadProximitySensor(client, body, B)[0] == 8
    assert sim.simxGetObjectPosition(client, body, -1, 0x090000)[0] == 4
    code, errors = sim.simxGetLastErrors(client, B)
    assert code == 0 and any("Nope" in e for e in errors)


def test_unsupported_and_unknown_functions(session, client, capsys):
    assert sim.simxDisplayDialog(client, "t", "m", 0, "", None, None, B) == (32, 0, 0)
    assert sim.simxTransferFile(client, "a", "b", 1000, B) == 32
    assert sim.simxTransferFile(client, "a", "b", 1000, B) == 32
    assert sim.simxSomethingNew(client) == 32
    err = capsys.readouterr().err
    assert err.count("simxTransferFile") == 1 and "simxSomethingNew" in err
    # scene changes go through the sim.* table: a scene file that is not there is an error
    assert sim.simxLoadScene(client, "x.ttt", 0, B) == 8
    with pytest.raises(AttributeError):
        sim.not_a_constant  # noqa: B018


def test_temporary_server_refuses_control():
    s = Session("cart", clock=VirtualClock())
    previous = set_session(s)
    try:
        cid = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
        assert s.simulator.server == "temporary" and s.simulator.state == "running"
        assert sim.simxStartSimulation(cid, B) == 8
        assert sim.simxStopSimulation(cid, B) == 8
        assert sim.simxSynchronous(cid, True) == 8
        left = handle(cid, "left_m")
        sim.simxSetJointTargetVelocity(cid, left, 2.0, B)
        s.clock.advance(1.0)
        assert sim.simxGetObjectVelocity(cid, handle(cid, "left_wheel"), B)[0] == 0
        code, speed = sim.simxGetJointPosition(cid, left, B)
        assert code == 0 and speed > 1.0  # the wheel turned about 2 rad
    finally:
        set_session(previous)
        s.close()


def test_proximity_sensor_sees_an_obstacle_ahead():
    s = Session("cart", clock=VirtualClock(), scene_options={"obstacles": 0, "start": (1.2, 0, 0)})
    previous = set_session(s)
    try:
        cid = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
        sensor = handle(cid, "Proximity_sensor")
        code, detected, point, obj, normal = sim.simxReadProximitySensor(cid, sensor, B)
        assert code == 0 and detected  # the arena wall is 0.3 m ahead
        assert point[2] == pytest.approx(1.5 - 1.2 - 0.047, abs=0.03)  # z = sensing direction
        assert obj == 0 and normal[2] < -0.9
        code, euler = sim.simxGetObjectOrientation(cid, sensor, handle(cid, "cart"), B)
        assert np.allclose(g.euler_to_matrix(euler), [[0, 0, 1], [1, 0, 0], [0, 1, 0]], atol=1e-5)
    finally:
        set_session(previous)
        s.close()


def test_group_data_types(session, client):
    code, handles, ints, floats, strings = sim.simxGetObjectGroupData(
        client, sim.sim_appobj_object_type, 0, B
    )
    assert code == 0 and "2W1A" in strings and len(handles) == len(strings)
    n = len(handles)
    sizes = {
        1: (n, 0),
        2: (n, 0),
        3: (0, 3 * n),
        4: (0, 3 * n),
        5: (0, 3 * n),
        7: (0, 4 * n),
        9: (0, 6 * n),
        11: (0, 7 * n),
        13: (2 * n, 6 * n),
        15: (0, 2 * n),
        16: (2 * n, 2 * n),
        17: (0, 3 * n),
        18: (0, 3 * n),
        19: (0, 6 * n),
    }
    for data_type, (ni, nf) in sizes.items():
        code, _, ints, floats, _ = sim.simxGetObjectGroupData(
            client, sim.sim_appobj_object_type, data_type, B
        )
        assert (code, len(ints), len(floats)) == (0, ni, nf), data_type
    code, joints, _, floats, _ = sim.simxGetObjectGroupData(
        client, sim.sim_object_joint_type, 15, B
    )
    assert code == 0 and len(joints) == 5
    assert sim.simxGetObjectGroupData(client, sim.sim_appobj_object_type, 99, B)[0] == 8


def test_pause_communication_applies_setters_together(session, client):
    wrist, elbow = handle(client, "WristMotor"), handle(client, "ElbowMotor")
    # hold the saved pose (the scene's saved targets would move the arm at start)
    sim.simxSetJointTargetPosition(client, wrist, math.radians(250), B)
    sim.simxSetJointTargetPosition(client, elbow, math.radians(120), B)
    sim.simxStartSimulation(client, B)
    sim.simxPauseCommunication(client, True)
    sim.simxSetJointTargetPosition(client, wrist, math.radians(200), sim.simx_opmode_oneshot)
    sim.simxSetJointTargetPosition(client, elbow, math.radians(60), sim.simx_opmode_oneshot)
    session.clock.advance(1.0)
    assert math.degrees(sim.simxGetJointPosition(client, wrist, B)[1]) == pytest.approx(250, abs=1)
    sim.simxPauseCommunication(client, False)
    session.clock.advance(1.5)
    assert math.degrees(sim.simxGetJointPosition(client, wrist, B)[1]) == pytest.approx(200, abs=3)
    assert math.degrees(sim.simxGetJointPosition(client, elbow, B)[1]) == pytest.approx(60, abs=3)


def test_streaming_setter_is_reapplied_after_a_reset(session, client):
    wrist = handle(client, "WristMotor")
    sim.simxStartSimulation(client, B)
    sim.simxSetJointTargetPosition(client, wrist, math.radians(150), sim.simx_opmode_streaming)
    session.clock.advance(1.0)
    sim.simxStopSimulation(client, B)
    sim.simxStartSimulation(client, B)
    session.clock.advance(2.5)  # 250 -> 150 deg at the scene's 60 deg/s
    assert math.degrees(sim.simxGetJointPosition(client, wrist, B)[1]) == pytest.approx(150, abs=3)


def test_synchronous_trigger_steps_one_pass(session, client):
    assert sim.simxSynchronousTrigger(client) == 8  # not in synchronous mode
    assert sim.simxSynchronous(client, True) == 0
    sim.simxStartSimulation(client, B)
    session.clock.advance(3.0)
    assert session.simulator.sim_time == 0.0  # waits for triggers
    for _ in range(4):
        assert sim.simxSynchronousTrigger(client) == 0
    sim.simxGetPingTime(client)
    assert sim.simxGetLastCmdTime(client) == 200


def test_setting_a_base_pose_and_reading_it_back(session, client):
    body = handle(client, "2W1A")
    target = [0.3, -0.4, 0.2]
    assert sim.simxSetObjectPosition(client, body, -1, target, B) == 0
    assert np.allclose(sim.simxGetObjectPosition(client, body, -1, B)[1], target, atol=1e-6)
    euler = [0.1, 0.5, -0.3]
    assert sim.simxSetObjectOrientation(client, body, -1, euler, B) == 0
    assert np.allclose(sim.simxGetObjectOrientation(client, body, -1, B)[1], euler, atol=1e-5)
    shoulder = handle(client, "ShoulderMotor")
    rel = sim.simxGetObjectPosition(client, shoulder, body, B)[1]
    assert np.allclose(rel, [0.020, 0.0, 0.0876], atol=1e-3)  # rides along with the body
