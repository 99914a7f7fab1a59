"""The scene-script runtime (sims/lua): sandbox, budgets, dispatch, threads, reports.

Each test runs Lua scripts attached to the project's own demo scene (data/scenes/
lua_arm.simscene.xml, built by sims.lua.demo), so nothing here needs the course data.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import pytest

from sims.lua.host import ScriptHost
from sims.lua.run import run_scene
from sims.scene.model import Script
from sims.world import World
from tools.lua_demo import ARM_RADIUS, demo_scene

REPO = Path(__file__).resolve().parents[1]


def _world(*scripts: Script) -> World:
    scene = dataclasses.replace(demo_scene(), scripts=tuple(scripts))
    return World(scene)


def _run(*scripts: Script, seconds: float = 1.0) -> ScriptHost:
    world = _world(*scripts)
    host = ScriptHost(world)
    host.start()
    world.advance(seconds)
    host.world = world
    host.result_world = world
    return host


def child(text: str, threaded: bool = False, on: int = 4) -> Script:
    return Script("child", text, object=on, threaded=threaded)


def test_sandbox_refuses_processes_native_modules_and_files_outside_tmp():
    host = _run(
        child(
            "function sysCall_init()\n"
            "  local r = {}\n"
            "  r[1] = pcall(os.execute, 'touch /tmp/lua-escape')\n"
            "  r[2] = pcall(io.popen, 'ls')\n"
            "  r[3] = io.open('/etc/passwd', 'r') == nil\n"
            "  r[4] = pcall(require, 'socket')\n"
            "  r[5] = pcall(string.dump, print)\n"
            "  r[6] = python == nil\n"
            "  r[7] = load('\\27Lua') == nil\n"
            "  r[8] = io.open('/tmp/lua-escape-2', 'w') == nil\n"
            "  local name = os.tmpname()\n"
            "  local f = io.open(name, 'w'); f:write('kept'); f:close()\n"
            "  r[9] = io.open(name, 'r'):read('a') == 'kept'\n"
            "  local s = ''\n"
            "  for i = 1, 9 do s = s .. tostring(r[i]) .. ',' end\n"
            "  sim.setStringSignal('sandbox', s)\n"
            "end\n"
        )
    )
    assert host.errors == []
    assert host.signals["string"]["sandbox"] == b"false,false,true,false,false,true,true,true,true,"
    assert not Path("/tmp/lua-escape").exists()
    assert not Path("/tmp/lua-escape-2").exists()


def test_endless_loop_is_stopped_with_script_name_and_line_and_the_run_goes_on():
    host = _run(
        child("function sysCall_actuation()\n  local x = 0\n  while true do x = x + 1 end\nend\n"),
        child("function sysCall_sensing() sim.setIntegerSignal('alive', 1) end", on=6),
        seconds=0.2,
    )
    assert len(host.errors) == 1
    assert "Arm:3: stopped" in host.errors[0]
    assert "virtual steps" in host.errors[0]
    assert host.signals["int"]["alive"] == 1


def test_threaded_busy_loop_without_yield_is_stopped():
    host = _run(child("local x = 0\nwhile true do\n  x = x + 1\nend\n", threaded=True), seconds=0.2)
    assert len(host.errors) == 1 and "Arm:3: stopped" in host.errors[0]


def test_threaded_script_yields_at_switch_thread_and_waits_in_virtual_time():
    host = _run(
        child(
            "local n = 0\n"
            "for i = 1, 4 do n = n + 1; sim.setIntegerSignal('n', n); sim.switchThread() end\n"
            "sim.wait(1.0)\n"
            "sim.setFloatSignal('woke', sim.getSimulationTime())\n",
            threaded=True,
        ),
        seconds=0.1,
    )
    # resumed at start, after pass 1 and after pass 2: one increment per resume
    assert host.signals["int"]["n"] == 3
    host.world.advance(1.5)
    assert host.signals["int"]["n"] == 4
    assert host.signals["float"]["woke"] == pytest.approx(1.2, abs=0.051)


def test_threaded_script_switches_automatically_inside_xpcall():
    host = _run(
        child(
            "threadFunction = function()\n"
            "  while true do sim.setIntegerSignal('t', (sim.getIntegerSignal('t') or 0) + 1) end\n"
            "end\n"
            "xpcall(threadFunction, function(e) return debug.traceback(e) end)\n",
            threaded=True,
        ),
        seconds=0.5,
    )
    assert host.errors == []
    first = host.signals["int"]["t"]
    host.world.advance(0.5)
    assert host.signals["int"]["t"] > first > 0  # it keeps running, pass after pass


def test_old_style_sections_run_with_sim_call_type_in_coppeliasim_order():
    text = (
        "if sim_call_type == sim_childscriptcall_initialization then\n"
        "  simSetStringSignal('log', 'i')\n"
        "end\n"
        "if sim_call_type == sim_childscriptcall_actuation then\n"
        "  simSetStringSignal('log', simGetStringSignal('log') .. 'a')\n"
        "end\n"
        "if sim_call_type == sim_childscriptcall_sensing then\n"
        "  simSetStringSignal('log', simGetStringSignal('log') .. 's')\n"
        "end\n"
        "if sim_call_type == sim_childscriptcall_cleanup then\n"
        "  simSetStringSignal('log', simGetStringSignal('log') .. 'c')\n"
        "end\n"
    )
    scene = dataclasses.replace(demo_scene(), scripts=(child(text),), version="CoppeliaSim 3.3.0")
    with World(scene) as world:
        host = ScriptHost(world)
        host.start()
        world.advance(0.1)  # two passes
        host.stop()
        assert host.signals["string"]["log"] == b"iasasac"


def test_new_style_callbacks_and_positions_from_the_world():
    host = _run(
        child(
            "function sysCall_init() post = sim.getObjectHandle('Post') end\n"
            "function sysCall_sensing()\n"
            "  local p = sim.getObjectPosition(post, -1)\n"
            "  sim.setFloatSignal('z', p[3])\n"
            "  sim.setFloatSignal('t', sim.getSimulationTime())\n"
            "end\n"
        ),
        seconds=0.25,
    )
    assert host.signals["float"]["z"] == pytest.approx(0.25, abs=1e-6)
    assert host.signals["float"]["t"] == pytest.approx(0.25, abs=1e-9)


def test_unemulated_function_is_reported_once_with_scene_script_and_line():
    host = _run(
        child(
            "function sysCall_actuation()\n"
            "  for i = 1, 3 do\n"
            "    simNotAFunction(i)\n"
            "  end\n"
            "  sim.alsoMissing()\n"
            "end\n"
        ),
        seconds=0.2,
    )
    assert host.errors == []
    described = [m.describe() for m in host.missing]
    assert described == [
        "lua_arm.simscene.xml: script 'Arm' line 3: simNotAFunction",
        "lua_arm.simscene.xml: script 'Arm' line 5: sim.alsoMissing",
    ]


def test_call_function_passes_ints_floats_strings_and_buffer():
    world = _world(
        child(
            "function echo(ints, floats, strings, buffer)\n"
            "  return {ints[1] * 2, #floats}, {floats[1] + 0.5}, {strings[1] .. '!'},\n"
            "    buffer .. 'x'\n"
            "end\n"
        )
    )
    with world:
        host = ScriptHost(world)
        out = host.call_function("Arm", "child", "echo", ([21], [1.25, 2.0], ["hi"], b"\x00b"))
        assert out == ([42, 2], [1.75], [b"hi!"], b"\x00bx")
        with pytest.raises(LookupError):
            host.call_function("Arm", "child", "nope", ([], [], [], b""))


def test_demo_scene_file_is_what_the_generator_writes():
    from sims.scene.xml_write import write_xml

    shipped = (REPO / "data" / "scenes" / "lua_arm.simscene.xml").read_text(encoding="utf-8")
    assert shipped == write_xml(demo_scene())


def test_demo_scene_moves_only_through_its_scripts():
    scene = REPO / "data" / "scenes" / "lua_arm.simscene.xml"
    alive = run_scene(scene, 5.0, follow=("Arm", "Flag"))
    still = run_scene(scene, 5.0, follow=("Arm", "Flag"), scripts=False)
    assert alive.errors == [] and alive.missing == []

    def swing(run):
        ys = [p[1] for _, n, p in run.trace if n == "Arm"]
        return max(ys) - min(ys)

    # the arm's centre (ARM_RADIUS from the axis) swings to +-0.9 rad
    assert swing(alive) == pytest.approx(2 * ARM_RADIUS * math.sin(0.9), abs=0.03)
    assert swing(still) < 1e-3
    angles = [math.atan2(p[1], p[0]) for t, n, p in alive.trace if n == "Flag" and t <= 1.9]
    turned = sum(
        (b - a + math.pi) % (2 * math.pi) - math.pi
        for a, b in zip(angles, angles[1:], strict=False)
    )
    assert turned == pytest.approx(3.0 * 1.85, rel=0.1)  # 3 rad/s for the first 2 s


def test_scene_editing_and_headless_ui_functions_the_floors_use():
    host = _run(
        child(
            "function sysCall_init()\n"
            "  local post = sim.getObjectHandle('Post')\n"
            "  local copy = sim.copyPasteObjects({post}, 0)[1]\n"
            "  sim.setObjectParent(copy, post, true)\n"
            "  local p = sim.getObjectPosition(copy, -1)\n"
            "  local ok = pcall(sim.removeObject, post)\n"
            "  local ui = simGetUIHandle('ResizableFloor_5_25')\n"
            "  simSetUIProperty(ui, simBoolOr16(simGetUIProperty(ui), 2))\n"
            "  sim.setStringSignal('edit', table.concat({\n"
            "    tostring(copy > post), sim.getObjectName(copy),\n"
            "    tostring(sim.getObjectParent(copy) == post), string.format('%.2f', p[3]),\n"
            "    tostring(ok), tostring(sim.removeModel(copy)),\n"
            "    tostring(simGetUIProperty(ui)), tostring(simGetUIEventButton(ui))}, ','))\n"
            "end\n"
        ),
        seconds=0.1,
    )
    assert host.errors == []
    # the copy is named as CoppeliaSim names copies; the post carries the arm's chain, so it
    # cannot go; the copy (a whole new post and arm, built like the original) can
    assert host.signals["string"]["edit"] == b"true,Post#0,true,0.25,false,1,3,-1"
