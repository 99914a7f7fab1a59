"""The one sim.* table (sims/simapi) as scene scripts and ZeroMQ clients see it, on the project's
own demo scene (tools/lua_demo.py: Floor; Post (a model) > ArmJoint > Arm, Post > FlagJoint >
Flag): names relative to the calling script, threads and blocking calls, messages and key
presses, created and moved objects, require beside the scene, errors at the script's line."""

from __future__ import annotations

import dataclasses

import pytest

from sims.lua import keys
from sims.lua.host import ScriptHost
from sims.scene.model import Script
from sims.simapi.table import BLOCKING, FUNCTIONS
from sims.world import World
from tools.lua_demo import demo_scene

CHECK = "local function put(k, v) sim.setStringSignal(k, tostring(v)) end\n"


def _host(*scripts: Script, seconds: float = 0.3, scene=None) -> ScriptHost:
    world = World(dataclasses.replace(scene or demo_scene(), scripts=tuple(scripts)))
    host = ScriptHost(world)
    host.start()
    world.advance(seconds)
    return host


def _signals(host: ScriptHost) -> dict[str, str]:
    return {k: v.decode() for k, v in host.signals["string"].items()}


def test_names_resolve_relative_to_the_calling_scripts_object():
    host = _host(
        Script(
            "child",
            CHECK + "function sysCall_init()\n"
            "  put('self', sim.getObject('.') == sim.getObjectHandle('Arm'))\n"
            "  put('model', sim.getObject(':') == sim.getObjectHandle('Post'))\n"
            "  put('parent', sim.getObject('..') == sim.getObjectHandle('ArmJoint'))\n"
            "  put('sibling', sim.getObject(':/FlagJoint/Flag') == sim.getObjectHandle('Flag'))\n"
            "  put('abs', sim.getObject('/Post/Arm') == sim.getObject('.'))\n"
            "  put('up', pcall(sim.getObject, '::'))\n"
            "  put('none', sim.getObject('./Nothing', {noError=true}))\n"
            "end\n",
            object=4,
        )
    )
    assert host.errors == []
    got = _signals(host)
    assert got == {
        "self": "true", "model": "true", "parent": "true", "sibling": "true", "abs": "true",
        "up": "false", "none": "-1",  # '::' from Arm: no model above Post
    }  # fmt: skip


def test_a_threaded_script_waits_and_moves_with_blocking_calls():
    # 4.x threaded script: the chunk defines sysCall_threadmain, run as the coroutine
    text = (
        "function sysCall_threadmain()\n"
        "  local j = sim.getObject('/Post/ArmJoint')\n"
        "  sim.setJointMode(j, sim.jointmode_passive, 0)\n"
        "  sim.setIntegerSignal('t0', math.floor(sim.getSimulationTime() * 1000 + 0.5))\n"
        "  sim.wait(0.5)\n"
        "  sim.setIntegerSignal('t1', math.floor(sim.getSimulationTime() * 1000 + 0.5))\n"
        "  local r = sim.rmlMoveToJointPositions({j}, -1, nil, nil, {1}, {2}, {4}, {1.0}, {0})\n"
        "  sim.setIntegerSignal('t2', math.floor(sim.getSimulationTime() * 1000 + 0.5))\n"
        "  sim.setFloatSignal('q', sim.getJointPosition(j))\n"
        "  sim.waitForSignal('go')\n"
        "  sim.setIntegerSignal('t3', math.floor(sim.getSimulationTime() * 1000 + 0.5))\n"
        "end\n"
    )
    world = World(dataclasses.replace(demo_scene(), scripts=(Script("child", text, 4, True),)))
    host = ScriptHost(world)
    host.start()
    world.advance(3.0)
    assert host.errors == []
    ints = host.signals["int"]
    assert ints["t1"] - ints["t0"] == 500  # sim.wait(0.5): ten 50 ms passes
    # the move takes Ruckig's time (about 1.6 s for 1 rad at 1 rad/s, 2 rad/s^2, 4 rad/s^3)
    from sims.motion import Profile

    duration = Profile([0.0], [0.0], [0.0], [1.0], [2.0], [4.0], [1.0], [0.0]).duration
    assert (ints["t2"] - ints["t1"]) / 1000 == pytest.approx(duration, abs=0.051)
    assert host.signals["float"]["q"] == pytest.approx(1.0, abs=1e-6)  # passive: set exactly
    assert "t3" not in ints  # still waiting for its signal
    host.signals["int"]["go"] = 1
    world.advance(0.1)
    assert "t3" in host.signals["int"]


def test_simulator_messages_are_minus_one_until_a_scripted_key_press():
    keys.configure(keys.parse("0.2 0.1 a\n0.3 0.1 up\n", "keys.txt"))
    try:
        host = _host(
            Script(
                "child",
                "seen = {}\nfunction sysCall_actuation()\n"
                "  local m, aux = sim.getSimulatorMessage()\n"
                "  while m ~= -1 do\n"
                "    if m == sim.message_keypress then seen[#seen + 1] = aux[1] end\n"
                "    m, aux = sim.getSimulatorMessage()\n"
                "  end\n"
                "  sim.setStringSignal('keys', table.concat(seen, ','))\n"
                "end\n",
                object=4,
            ),
            seconds=0.5,
        )
    finally:
        keys.configure(None)
    assert host.errors == []
    assert _signals(host)["keys"] == f"{ord('a')},2007"  # 'a', then the up arrow


def test_errors_name_script_and_line_and_disable_only_that_script():
    host = _host(
        Script("child", "function sysCall_actuation()\n  local x = nil + 1\nend\n", 4),
        Script(
            "child",
            "n = 0\nfunction sysCall_actuation() n = n + 1 sim.setIntegerSignal('n', n) end\n",
            6,
        ),
        seconds=0.5,
    )
    assert len(host.errors) == 1 and "Arm:2:" in host.errors[0]
    assert host.signals["int"]["n"] >= 9  # the other script ran on


def test_created_objects_are_in_the_tree_for_every_api_and_moving_a_dummy_moves_only_it():
    world = World(demo_scene())
    arm = world.find("Arm")
    before = world.object_pose(arm)
    d = world.create_dummy(0.02)
    assert world.find("Dummy") == d and world.kind(d) == "dummy"
    world.set_parent(d, arm, keep_in_place=True)
    world.set_object_pose(d, ((0.3, 0.2, 0.9), (0.0, 0.0, 0.0, 1.0)))
    assert world.object_pose(d)[0] == pytest.approx((0.3, 0.2, 0.9), abs=1e-6)
    after = world.object_pose(arm)  # the arm it rides on stays put
    assert after[0] == pytest.approx(before[0], abs=1e-9)
    assert after[1] == pytest.approx(before[1], abs=1e-9)
    world.step(20)  # the dummy rides the arm's link from its new place
    assert world.parent(d) == arm
    world.remove_object(d)
    assert world.find("Dummy") is None and world.name_of(d) is None
    shape = world.create_primitive("cuboid", (0.1, 0.1, 0.1), mass=0.5)
    world.set_object_pose(shape, ((1.0, 1.0, 0.5), (0.0, 0.0, 0.0, 1.0)))
    world.step(200)  # it falls onto the floor (created while "stopped": kept at reset)
    assert world.object_pose(shape)[0][2] == pytest.approx(0.05, abs=0.01)
    world.close()


def test_require_finds_lua_files_beside_the_scene_only(tmp_path):
    from sims.scene.xml_write import write_xml

    scene = tmp_path / "demo.simscene.xml"
    scene.write_text(write_xml(demo_scene()), encoding="utf-8")
    (tmp_path / "helper.lua").write_text("return {twice = function(x) return 2 * x end}\n")
    text = (
        CHECK + "function sysCall_init()\n"
        "  put('twice', require('helper').twice(21))\n"
        "  put('sim', require('sim') == sim)\n"
        "  put('outside', pcall(require, '..secret'))\n"
        "  put('missing', pcall(require, 'nothere'))\n"
        "end\n"
    )
    from sims.scene.load import load_scene

    loaded = load_scene(scene)
    host = _host(Script("child", text, 4), scene=loaded)
    assert host.errors == []
    assert _signals(host) == {"twice": "42", "sim": "true", "outside": "false", "missing": "false"}


def test_one_table_blocking_functions_are_generators():
    assert {"sim.wait", "sim.moveToConfig", "sim.rmlMoveToJointPositions"} <= BLOCKING
    assert FUNCTIONS["sim.getInt32Parameter"] is FUNCTIONS["sim.getInt32Param"]
    assert all(callable(f) for f in FUNCTIONS.values())


def _zmq(tmp_path, scene: str, body: str) -> list[dict]:
    import contextlib
    import io
    import json

    from sims.remote_api.runner import run_script

    script = tmp_path / "client.py"
    script.write_text(
        "import json\nfrom coppeliasim_zmqremoteapi_client import RemoteAPIClient\n"
        "sim = RemoteAPIClient().require('sim')\n" + body,
        encoding="utf-8",
    )
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        result = run_script(script, scene, stderr=io.StringIO())
    assert result.exit_code == 0, result.message
    return [json.loads(x) for x in out.getvalue().splitlines() if x.startswith("{")]


def test_zmq_clients_create_parent_and_move_dummies_without_moving_the_rest(tmp_path):
    """Issue 29's repro: moving a dummy of the FANUC scene (it failed with "getDynamicsInfo
    failed"), with sim.createDummy, setObjectParent and removeObject of the ZeroMQ examples."""
    from shared_data import shared

    scene = shared("data", "scenes", "course", "fanuc_m710ic_50_pick_and_place.ttt")
    (got,) = _zmq(
        tmp_path,
        str(scene),
        "floor = sim.getObject('/ResizableFloor_5_25')\n"
        "others = sim.getObjectsInTree(sim.handle_scene)\n"
        "before = [sim.getObjectPosition(h, -1) for h in others]\n"
        "d = sim.createDummy(0.05)\n"
        "sim.setObjectParent(d, floor, True)\n"
        "sim.setObjectPosition(d, -1, [0.5, 0.25, 1.0])\n"
        "cam = sim.getObject('/XYZCameraProxy')\n"
        "sim.setObjectPosition(cam, -1, [1, 2, 3])\n"
        "after = [sim.getObjectPosition(h, -1) for h in others]\n"
        "moved = [sim.getObjectAlias(h) for h, a, b in zip(others, before, after) if a != b]\n"
        "info = {'d': sim.getObjectPosition(d, -1), 'alias': sim.getObjectAlias(d),\n"
        "        'parent': sim.getObjectParent(d) == floor, 'moved': sorted(moved)}\n"
        "sim.removeObject(d)\n"
        "info['gone'] = not sim.isHandle(d)\n"
        "print(json.dumps(info))\n",
    )
    assert got["d"] == pytest.approx([0.5, 0.25, 1.0], abs=1e-6)
    assert got["alias"] == "Dummy" and got["parent"] is True and got["gone"] is True
    # the camera proxy moved with its cameras, nothing else did
    assert got["moved"] == sorted(
        ["XYZCameraProxy"] + [f"Default{a}ViewCamera" for a in ("X", "Y", "Z", "NX", "NY", "NZ")]
    )


def test_zmq_move_to_config_steps_the_simulation_for_its_client(tmp_path):
    (got,) = _zmq(
        tmp_path,
        "2w1a",
        "j = sim.getObject('/2W1A/ShoulderMotor')\n"
        "sim.setStepping(True)\n"
        "sim.startSimulation()\n"
        "q0 = sim.getJointPosition(j)\n"
        "out = sim.moveToConfig({'joints': [j], 'targetPos': [q0 + 0.5], 'maxVel': [1],\n"
        "                        'maxAccel': [2], 'maxJerk': [4]})\n"
        "print(json.dumps({'t': sim.getSimulationTime(), 'end': out['pos'][0] - q0}))\n"
        "sim.stopSimulation()\n",
    )
    from sims.motion import Profile

    duration = Profile([0.0], [0.0], [0.0], [1.0], [2.0], [4.0], [0.5], [0.0]).duration
    assert got["end"] == pytest.approx(0.5, abs=1e-9)
    assert got["t"] == pytest.approx(duration, abs=0.051)  # one 50 ms step per profile step


def test_tubes_connect_two_scripts_and_uis_keep_their_values_headless():
    host = _host(
        Script(
            "child",
            "function sysCall_init()\n"
            "  t = sim.tubeOpen(0, 'chat', 4)\n"
            '  ui = simUI.create(\'<ui><hslider id="3" minimum="0" maximum="9" value="4"/>'
            '<edit id="5" value="hi"/></ui>\')\n'
            "  simUI.setEditValue(ui, 5, 'typed')\n"
            "end\n"
            "function sysCall_actuation() sim.tubeWrite(t, 'ping') end\n"
            "function sysCall_cleanup() end\n"
            "function sysCall_sensing()\n"
            "  sim.setStringSignal('ui', simUI.getSliderValue(ui, 3) .. ',' .. "
            "simUI.getEditValue(ui, 5))\n"
            "end\n",
            4,
        ),
        Script(
            "child",
            "function sysCall_init() t = sim.tubeOpen(0, 'chat', 4) got = 0 end\n"
            "function sysCall_sensing()\n"
            "  local m = sim.tubeRead(t)\n"
            "  while m do got = got + 1 m = sim.tubeRead(t) end\n"
            "  sim.setIntegerSignal('got', got)\n"
            "end\n",
            6,
        ),
        seconds=0.5,
    )
    assert host.errors == []
    assert host.signals["int"]["got"] >= 9  # one message a pass crossed the tube
    assert _signals(host)["ui"] == "4,typed"
