"""ZeroMQ remote API scripts (CoppeliaSim 4.3+) run unchanged on the emulated scenes.

Each test writes a script as a user would, runs it with ``run_script`` (virtual time, sockets
refused) and checks what the script saw and where the robot went.
"""

from __future__ import annotations

import io
import json
import math
import re
import socket
import textwrap
from pathlib import Path

import pytest

from sims.remote_api.cli import main
from sims.remote_api.runner import run_script

REPO = Path(__file__).resolve().parent.parent
EXAMPLE = REPO / "examples" / "zmq" / "2w1a_drive_stepped.py"

HEADER = """\
import json, math, time
from coppeliasim_zmqremoteapi_client import RemoteAPIClient
client = RemoteAPIClient()
sim = client.require('sim')
def show(**values):
    print(json.dumps(values))
"""


class _NoSocket(socket.socket):
    def __init__(self, *a, **k):
        raise AssertionError("the ZeroMQ emulation created a socket")


def _run(tmp_path: Path, body: str, scene: str = "2w1a", header: str = HEADER, **kw):
    """Run the script; returns (result, the JSON lines it printed, stderr text)."""
    path = tmp_path / "script.py"
    path.write_text(header + textwrap.dedent(body), encoding="utf-8")
    err = io.StringIO()
    out = io.StringIO()
    import contextlib

    with contextlib.redirect_stdout(out):
        result = run_script(path, scene, stderr=err, **kw)
    lines = [json.loads(x) for x in out.getvalue().splitlines() if x.startswith(("{", "["))]
    return result, lines, err.getvalue()


@pytest.fixture(autouse=True)
def no_sockets(monkeypatch):
    monkeypatch.setattr(socket, "socket", _NoSocket)


def test_stepping_mode_advances_only_on_step(tmp_path):
    # The 2W1A's wheels roll freely (0.01 N·m, as in the scene): it moves by its arm.
    result, out, _ = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        arm = [sim.getObject('/2W1A/' + n) for n in ('ShoulderMotor', 'ElbowMotor', 'WristMotor')]
        start = sim.getObjectPosition(body, sim.handle_world)
        before = [math.degrees(sim.getJointPosition(j)) for j in arm]
        levels = [sim.setStepping(True)]
        sim.startSimulation()
        for joint, degrees in zip(arm, (200, 60, 200)):
            sim.setJointTargetPosition(joint, math.radians(degrees))
        for _ in range(60):
            sim.step()
        t1 = sim.getSimulationTime()
        time.sleep(5)  # the client's own time: no simulation step happens
        show(start=start, before=before, t1=t1, t2=sim.getSimulationTime(),
             after=[math.degrees(sim.getJointPosition(j)) for j in arm],
             end=sim.getObjectPosition(body, sim.handle_world), levels=levels,
             state=sim.getSimulationState(), running=sim.simulation_advancing_running)
        """,
    )
    assert result.exit_code == 0, result.message
    (v,) = out
    assert v["levels"] == [0]  # setStepping returns the previous stepping level
    assert v["t1"] == pytest.approx(3.0) and v["t2"] == v["t1"]
    assert v["state"] == v["running"] == 17
    assert v["before"] == pytest.approx([150, 120, 250], abs=0.5)  # the scene's initial pose
    assert v["after"] == pytest.approx([200, 60, 200], abs=1.0)  # the arm reached its targets
    assert math.dist(v["end"], v["start"]) > 0.01  # and moved the body


def test_free_running_mode_follows_the_clock(tmp_path):
    result, out, _ = _run(
        tmp_path,
        """
        show(state=sim.getSimulationState(), stopped=sim.simulation_stopped)
        sim.startSimulation()
        time.sleep(2.0)
        t1 = sim.getSimulationTime()
        client.step()  # without stepping: waits for the next simulation step
        t2 = sim.getSimulationTime()
        sim.pauseSimulation()
        time.sleep(1.0)
        show(t1=t1, t2=t2, paused=sim.getSimulationTime(), state=sim.getSimulationState())
        sim.startSimulation()
        time.sleep(1.0)
        show(resumed=sim.getSimulationTime())
        sim.stopSimulation()
        show(stopped=sim.getSimulationTime(), state=sim.getSimulationState())
        """,
    )
    assert result.exit_code == 0, result.message
    first, mid, resumed, last = out
    assert first["state"] == first["stopped"] == 0
    assert mid["t1"] == pytest.approx(2.0, abs=0.051)
    assert mid["t2"] == pytest.approx(mid["t1"] + 0.05)
    assert mid["paused"] == pytest.approx(mid["t2"], abs=0.051) and mid["state"] == 8
    assert resumed["resumed"] == pytest.approx(mid["paused"] + 1.0, abs=0.051)
    assert last == {"stopped": 0.0, "state": 0}
    assert result.simulations == 1 and result.clock_time < 5


def test_stop_resets_the_scene_and_the_stepping_level(tmp_path):
    result, out, _ = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        shoulder = sim.getObject('/2W1A/ShoulderMotor')
        start = sim.getObjectPosition(body, -1)
        client.setStepping(True)
        sim.startSimulation()
        sim.setJointTargetPosition(shoulder, math.radians(220))
        for _ in range(20):
            client.step()
        moved = sim.getObjectPosition(body, -1)
        sim.stopSimulation()
        back = sim.getObjectPosition(body, -1)
        angle = math.degrees(sim.getJointPosition(shoulder))
        sim.startSimulation()  # stepping was reset by the stop: runs free now
        time.sleep(1.0)
        show(start=start, moved=moved, back=back, angle=angle, t=sim.getSimulationTime(),
             stepping=sim.setStepping(False))
        sim.stopSimulation()
        """,
    )
    assert result.exit_code == 0, result.message
    (v,) = out
    assert math.dist(v["moved"], v["start"]) > 0.005 and v["back"] == v["start"]
    assert v["angle"] == pytest.approx(150, abs=0.5)  # the arm is back to the scene's pose
    assert v["t"] == pytest.approx(1.0, abs=0.051) and v["stepping"] == 0
    assert result.simulations == 2


def test_return_values_have_the_real_clients_shapes(tmp_path):
    result, out, _ = _run(
        tmp_path,
        """
        prox = sim.getObject('/cart/Proximity_sensor')
        cart = sim.getObject('/cart')
        motor = sim.getObject('/cart/left_m')
        reading = sim.readProximitySensor(prox)
        pose = sim.getObjectPose(cart, sim.handle_world)
        show(handle=[type(cart).__name__, cart],
             position=[type(sim.getObjectPosition(cart, -1)).__name__,
                       len(sim.getObjectPosition(cart, -1))],
             reading=[type(reading).__name__, len(reading), reading[0], reading[3]],
             pose=len(pose), quaternion=len(sim.getObjectQuaternion(cart, -1)),
             none=sim.setJointTargetVelocity(motor, 1.0), signal=sim.getInt32Signal('x'),
             alias=sim.getObjectAlias(motor), path=sim.getObjectAlias(motor, 1),
             parent=sim.getObjectParent(motor) == cart,
             joints=sim.getObjectsInTree(cart, sim.object_joint_type, 0),
             kind=sim.getObjectType(motor) == sim.object_joint_type,
             version=sim.getInt32Param(sim.intparam_program_version),
             module=__import__('coppeliasim_zmqremoteapi_client').__file__)
        sim.setInt32Signal('x', 7)
        sim.setStringSignal('s', 'text')
        sim.setFloatSignal('f', 0.25)
        show(signals=[sim.getInt32Signal('x'), sim.getStringSignal('s'), sim.getFloatSignal('f')])
        sim.clearInt32Signal('x')
        show(cleared=sim.getInt32Signal('x'))
        """,
        scene="cart",
    )
    assert result.exit_code == 0, result.message
    v, signals, cleared = out
    assert v["handle"][0] == "int" and v["position"] == ["list", 3]
    assert v["reading"] == ["tuple", 5, 0, -1]  # nothing in front of the cart at the start
    assert v["pose"] == 7 and v["quaternion"] == 4 and v["none"] is None
    assert v["signal"] is None and signals == {"signals": [7, "text", 0.25]}
    assert cleared == {"cleared": None}
    assert v["alias"] == "left_m" and v["path"] == "/cart/left_m" and v["parent"] and v["kind"]
    assert len(v["joints"]) == 2 and v["version"] >= 40300
    # the shim wins over a real client installed on the machine
    assert REPO / "sims" / "remote_api" / "shim" in Path(v["module"]).parents


def test_unknown_path_raises_with_the_script_line(tmp_path):
    result, out, err = _run(
        tmp_path,
        """
        show(missing=sim.getObject('/2W1A/Nothing', {'noError': True}))
        try:
            sim.getObject('/2W1A/Nothing')
        except Exception as exc:
            show(caught=str(exc))
        sim.getObject('/2W1A/LeftWheel/Nothing')
        print('not reached')
        """,
    )
    assert out[0] == {"missing": -1}
    assert "object does not exist" in out[1]["caught"] and "sim.getObject" in out[1]["caught"]
    assert result.exit_code == 1 and "not reached" not in err
    text = (tmp_path / "script.py").read_text().splitlines()
    line = text.index("sim.getObject('/2W1A/LeftWheel/Nothing')") + 1
    assert result.message.startswith(f"{tmp_path / 'script.py'}:{line}: Exception:")
    assert "/2W1A/LeftWheel/Nothing" in result.message
    assert f"script.py:{line}: object does not exist" in err  # noted on stderr too
    missing = [(m.kind, m.what, m.site) for m in result.missing]
    assert ("object", "/2W1A/LeftWheel/Nothing", f"script.py:{line}") in missing
    nearest = [m.nearest for m in result.missing if m.site == f"script.py:{line}"][0]
    assert "/2W1A/LeftWheel" in nearest[0]


def test_invalid_handle_and_wrong_object_kind_raise(tmp_path):
    result, out, _ = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        for call in (lambda: sim.getObjectPosition(9999, -1),
                     lambda: sim.getJointPosition(body),
                     lambda: sim.setJointTargetVelocity(-5, 1.0),
                     lambda: sim.getObjectPosition(body, 4242),
                     lambda: sim.readProximitySensor(body),
                     lambda: sim.setJointTargetVelocity(body, 'fast'),
                     lambda: sim.getObjectPosition(body, -1, 5)):
            try:
                call()
                show(error=None)
            except Exception as exc:
                show(error=str(exc))
        """,
    )
    assert result.exit_code == 0, result.message
    errors = [v["error"] for v in out]
    assert all(errors), errors
    assert "9999 does not exist" in errors[0] and "sim.getObjectPosition" in errors[0]
    assert "not a joint" in errors[1] and "-5" in errors[2] and "4242" in errors[3]
    assert "not a proximity sensor" in errors[4] and "number expected" in errors[5]
    assert "wrong number of arguments (3)" in errors[6]


def test_missing_functions_are_named(tmp_path):
    result, out, err = _run(
        tmp_path,
        """
        for name in ('createShape', 'getObjec'):
            try:
                getattr(sim, name)(0.1)
            except Exception as exc:
                show(error=str(exc))
        sim.groupShapes([1, 2])
        """,
    )
    assert "sim.createShape is not emulated" in out[0]["error"]
    assert "sim.getObjec does not exist" in out[1]["error"]
    assert result.exit_code == 1 and "sim.groupShapes is not emulated" in result.message
    assert "script.py:" in err and "sim.createShape" in err
    assert {m.what for m in result.missing if m.kind == "function"} == {
        "sim.createShape",
        "sim.getObjec",
        "sim.groupShapes",
    }


def test_old_module_name_and_client_stepping(tmp_path):
    header = "import json\nfrom zmqRemoteApi import RemoteAPIClient\n"
    result, out, _ = _run(
        tmp_path,
        """
        client = RemoteAPIClient('10.0.0.9', 23002)
        sim = client.getObject('sim')
        left, right = sim.getObject('/left_m'), sim.getObject('/right_m')
        client.setStepping(True)
        sim.startSimulation()
        for h in (left, right):
            sim.setJointTargetVelocity(h, -2.0)
        for _ in range(40):
            client.step()
        cart = sim.getObjectPosition(sim.getObject('/cart'), -1)
        print(json.dumps([sim.getSimulationTime(), cart]))
        sim.stopSimulation()
        """,
        scene="cart",
        header=header,
    )
    assert result.exit_code == 0, result.message
    ((t, pos),) = out
    assert t == pytest.approx(2.0) and pos[0] < -0.05  # -2 rad/s drives the cart backwards
    assert [(c.address, c.port) for c in result.connections] == [("10.0.0.9", 23002)]


def test_setters_take_both_argument_orders(tmp_path):
    result, out, _ = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        z = sim.getObjectPosition(body, -1)[2]
        sim.setObjectPosition(body, -1, [0.5, 0.25, z])          # before 4.7
        a = sim.getObjectPosition(body, sim.handle_world)
        sim.setObjectPosition(body, [-0.5, 0.1, z], sim.handle_world)  # 4.7 and later
        b = sim.getObjectPosition(body)
        show(a=a, b=b)
        """,
    )
    assert result.exit_code == 0, result.message
    (v,) = out
    assert v["a"][:2] == pytest.approx([0.5, 0.25], abs=1e-6)
    assert v["b"][:2] == pytest.approx([-0.5, 0.1], abs=1e-6)


def test_zmq_and_legacy_scripts_drive_the_same_world(tmp_path):
    """Stepping through the ZeroMQ API and synchronous mode through the legacy API give the
    same pose: both talk to one emulated simulator."""
    _, zmq_out, _ = _run(
        tmp_path,
        """
        body = sim.getObject('/2W1A')
        start = sim.getObjectPosition(body, -1)
        sim.setStepping(True)
        sim.startSimulation()
        sim.setJointTargetPosition(sim.getObject('/2W1A/ShoulderMotor'), math.radians(200))
        sim.setJointTargetPosition(sim.getObject('/2W1A/ElbowMotor'), math.radians(60))
        for _ in range(50):
            sim.step()
        show(pos=sim.getObjectPosition(body, -1), start=start)
        """,
    )
    legacy = tmp_path / "legacy.py"
    legacy.write_text(
        textwrap.dedent(
            """
            import json, math, sim
            c = sim.simxStart('127.0.0.1', 19997, True, True, 5000, 5)
            b = sim.simx_opmode_blocking
            _, body = sim.simxGetObjectHandle(c, '2W1A', b)
            sim.simxSynchronous(c, True)
            sim.simxStartSimulation(c, b)
            for name, degrees in (('ShoulderMotor', 200), ('ElbowMotor', 60)):
                _, h = sim.simxGetObjectHandle(c, name, b)
                sim.simxSetJointTargetPosition(c, h, math.radians(degrees), b)
            for _ in range(50):
                sim.simxSynchronousTrigger(c)
            print(json.dumps({'pos': sim.simxGetObjectPosition(c, body, -1, b)[1]}))
            """
        ),
        encoding="utf-8",
    )
    out = io.StringIO()
    import contextlib

    with contextlib.redirect_stdout(out):
        assert run_script(legacy, "2w1a", stderr=io.StringIO()).exit_code == 0
    legacy_pos = json.loads(out.getvalue().splitlines()[-1])["pos"]
    assert zmq_out[0]["pos"] == pytest.approx(legacy_pos, abs=1e-5)  # legacy: 32-bit floats
    assert math.dist(zmq_out[0]["pos"], zmq_out[0]["start"]) > 0.01


def test_the_example_runs_through_the_cli(capsys):
    code = main(["run", str(EXAMPLE), "--scene", "2w1a"])
    captured = capsys.readouterr()
    assert code == 0, captured.err
    assert "simulation stopped" in captured.out
    strokes = re.findall(r"stroke (\d+): t=\s*([\d.]+) s .*\(([\d.]+) m from start\)", captured.out)
    assert [int(n) for n, _, _ in strokes] == list(range(1, 9))
    assert [float(t) for _, t, _ in strokes] == pytest.approx([1.6 * n for n in range(1, 9)])
    assert float(strokes[-1][2]) > 0.5  # the arm strokes crawl the body along the floor
    assert "localhost:23000" in captured.err  # recorded, not contacted


def test_a_script_split_over_modules_gets_the_zeromq_server(tmp_path):
    """The client is imported by a module beside the script: the run still serves it as the
    ZeroMQ add-on does (simulation stopped until the script starts it, even on the cart)."""
    (tmp_path / "robot.py").write_text(
        textwrap.dedent(
            """
            from coppeliasim_zmqremoteapi_client import RemoteAPIClient

            class Cart:
                def __init__(self):
                    self.sim = RemoteAPIClient().require('sim')
                    self.left = self.sim.getObject('/cart/left_m')
            """
        ),
        encoding="utf-8",
    )
    result, out, _ = _run(
        tmp_path,
        """
        from robot import Cart
        cart = Cart()
        show(state=cart.sim.getSimulationState(), started=cart.sim.startSimulation())
        """,
        scene="cart",
        header="import json\ndef show(**v):\n    print(json.dumps(v))\n",
    )
    assert result.exit_code == 0, result.message
    assert out == [{"state": 0, "started": 1}]
    assert result.simulations == 1


def test_after_lets_the_world_run_once_a_stepping_script_ends(tmp_path):
    result, _, _ = _run(
        tmp_path,
        """
        sim.setStepping(True)
        sim.startSimulation()
        for _ in range(10):
            sim.step()
        """,
        after=2.0,
    )
    assert result.exit_code == 0, result.message
    assert result.sim_time == pytest.approx(0.5 + 2.0, abs=0.051)
    assert result.final_state == "running"
