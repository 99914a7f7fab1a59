"""ZeroMQ scripts of our own on the course's scene files: the bubbleRob (a V-REP 3 ``.ttt``)
driven in stepping and free-running mode, and the line follower's vision sensors.

The scenes have no 4.x aliases: CoppeliaSim 4.3+ derives them from the old names, so a script
addresses ``/bubbleRob/bubbleRob_leftMotor``, as it would in CoppeliaSim.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import socket
import textwrap

import pytest
from shared_data import shared

from sims.remote_api.runner import run_script

SCRIPT = """\
import json, time
from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient('127.0.0.1', 23000)
sim = client.require('sim')
rob = sim.getObject('/bubbleRob')
left = sim.getObject('/bubbleRob/bubbleRob_leftMotor')
right = sim.getObject('/bubbleRob/bubbleRob_rightMotor')
nose = sim.getObject('/bubbleRob/bubbleRob_sensingNose')
out = {'kinds': [sim.getObjectType(h) for h in (rob, left, nose)],
       'start': sim.getObjectPosition(rob, sim.handle_world),
       'parent': sim.getObjectParent(left) == rob}
sim.setStepping(True)
sim.startSimulation()
sim.setJointTargetVelocity(left, 2.0)
sim.setJointTargetVelocity(right, 2.0)
while sim.getSimulationTime() < 5.0 - 1e-9:
    sim.step()
out['straight'] = sim.getObjectPosition(rob, sim.handle_world)
out['nose'] = sim.readProximitySensor(nose)
sim.setJointTargetVelocity(left, 0.0)
for _ in range(60):
    sim.step()
out['turned'] = sim.getObjectOrientation(rob, sim.handle_world)
out['time'] = sim.getSimulationTime()
sim.stopSimulation()
sim.startSimulation()  # stepping ended with the stop: this simulation runs free
time.sleep(1.0)
out['free'] = sim.getSimulationTime()
out['reset'] = sim.getObjectPosition(rob, sim.handle_world)
sim.stopSimulation()
try:
    sim.getObject('/bubbleRob/leftMotor')  # 4.x alias style: not in this V-REP 3 scene
except Exception as exc:
    out['error'] = str(exc)
print(json.dumps(out))
"""


class _NoSocket(socket.socket):
    def __init__(self, *a, **k):
        raise AssertionError("the ZeroMQ emulation created a socket")


@pytest.fixture(scope="module")
def bubble_run(tmp_path_factory):
    scene = shared("data", "scenes", "vrep_remoteapi_ex", "bubble", "bubbleRob_remoteAPI.ttt")
    path = tmp_path_factory.mktemp("bubble") / "drive_bubblerob.py"
    path.write_text(textwrap.dedent(SCRIPT), encoding="utf-8")
    saved, socket.socket = socket.socket, _NoSocket
    out, err = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stdout(out):
            result = run_script(path, str(scene), stderr=err)
    finally:
        socket.socket = saved
    return result, json.loads(out.getvalue().strip().splitlines()[-1]), err.getvalue()


def test_bubblerob_paths_and_kinds(bubble_run):
    result, out, _ = bubble_run
    assert result.exit_code == 0, result.message
    assert out["kinds"] == [0, 1, 5]  # shape, joint, proximity sensor
    assert out["parent"] is True
    assert "does not exist" in out["error"]
    assert [m.what for m in result.missing] == ["/bubbleRob/leftMotor"]


def test_bubblerob_drives_and_turns(bubble_run):
    result, out, _ = bubble_run
    dx = out["straight"][0] - out["start"][0]
    dy = out["straight"][1] - out["start"][1]
    # 2 rad/s on wheels of about 4 cm radius for 5 s: about 0.4 m, straight ahead
    assert 0.3 < math.hypot(dx, dy) < 0.5 and abs(dy) < 0.05
    assert out["nose"][0] == 0 and out["nose"][3] == -1  # nothing in front on the empty floor
    assert abs(out["turned"][2]) > 0.5  # one wheel stopped: it turned on the other
    assert out["time"] == pytest.approx(8.0)


def test_bubblerob_second_simulation_runs_free_from_the_reset_scene(bubble_run):
    result, out, _ = bubble_run
    assert out["free"] == pytest.approx(1.0, abs=0.051)
    assert out["reset"][:2] == pytest.approx(out["start"][:2], abs=0.02)
    assert result.simulations == 2
    assert [(c.address, c.port) for c in result.connections] == [("127.0.0.1", 23000)]


VISION = """\
import json
from coppeliasim_zmqremoteapi_client import RemoteAPIClient

client = RemoteAPIClient()
sim = client.require('sim')
left = sim.getObject('/LineTracer/LeftSensor')
img, res = sim.getVisionSensorImg(left)
grey, _ = sim.getVisionSensorImg(left, 1)
out = {'type': type(img).__name__, 'len': len(img), 'res': res, 'grey': len(grey),
       'first': list(img[:3]), 'handle': sim.handleVisionSensor(left)}
try:
    sim.getVisionSensorImg(sim.getObject('/DynamicLeftJoint'))
except Exception as exc:
    out['error'] = str(exc)
print(json.dumps(out))
"""


def test_vision_sensor_images_come_bottom_row_first(tmp_path):
    from sims.scene.camera import render_sensor
    from sims.world import World

    scene = shared("data", "scenes", "course", "simpleLineFollower_api.ttt")
    path = tmp_path / "vision.py"
    path.write_text(VISION, encoding="utf-8")
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        result = run_script(path, str(scene), stderr=io.StringIO())
    assert result.exit_code == 0, result.message
    got = json.loads(out.getvalue().strip().splitlines()[-1])
    width, height = got["res"]
    assert got["type"] == "bytes" and got["len"] == width * height * 3
    assert got["grey"] == width * height and width > 0 and height > 0
    # (detection count, the default image processing's packet: min, max, average of intensity,
    # red, green, blue and depth), the same as sim.readVisionSensor in the scene's scripts
    count, packet = got["handle"]
    assert count == 0 and len(packet) == 15 and all(0.0 <= v <= 1.0 for v in packet)
    assert "not a vision sensor" in got["error"]
    with World(str(scene)) as world:  # the same pixels the scene renders, last row first
        rgb = render_sensor(world, "LeftSensor")
    assert got["first"] == [int(v) for v in rgb[-1, 0]]
