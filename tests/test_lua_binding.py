"""sim.* functions and constants bound on first use (sims/lua/binding.py): what a script sees
is what it saw when every name was set up front.

Runs scripts on the project's own demo scene (no course data needed).
"""

from __future__ import annotations

import dataclasses

from sims.lua.host import ScriptHost
from sims.scene.model import Script
from sims.world import World
from tools.lua_demo import demo_scene

CHECKS = """
local function check(name, ok) sim.setIntegerSignal(name, ok and 1 or 0) end
function sysCall_init()
  check('same_function', simGetObjectHandle == sim.getObjectHandle)
  check('irregular_old_name', simGetIntegerParameter == sim.getInt32Parameter)
  check('module_function', type(simUI.create) == 'function')
  check('constant', sim.handle_self == -4 and sim_handle_self == -4)
  check('kept', rawget(sim, 'getObjectHandle') == sim.getObjectHandle)
  check('handle', simGetObjectHandle('Arm') == sim.getObjectHandle('Arm'))
  check('stub', type(simNotEmulatedAtAll) == 'function')
  simNotEmulatedAtAll(1)
end
"""


def _host(text: str, *, threaded: bool = False, seconds: float = 0.2) -> ScriptHost:
    script = Script("child", text, object=4, threaded=threaded)
    world = World(dataclasses.replace(demo_scene(), scripts=(script,)))
    host = ScriptHost(world)
    host.start()
    world.advance(seconds)
    return host


def test_both_names_are_one_function_and_constants_have_their_values():
    host = _host(CHECKS)
    assert host.errors == []
    assert host.signals["int"] == {
        "same_function": 1,
        "irregular_old_name": 1,
        "module_function": 1,
        "constant": 1,
        "kept": 1,
        "handle": 1,
        "stub": 1,  # a name the emulation lacks is still a stub, reported when called
    }
    assert [(m.function, m.line) for m in host.missing] == [("simNotEmulatedAtAll", 11)]


def test_a_function_bound_inside_a_thread_raises_at_the_scripts_line():
    host = _host(
        "sim.switchThread()\n\nlocal h = sim.getObjectHandle('no_such_object')\n",
        threaded=True,
    )
    assert len(host.errors) == 1
    assert "Arm:3: sim.getObjectHandle: " in host.errors[0]
    assert "no_such_object" in host.errors[0]


def test_unknown_constant_is_reported_with_its_line():
    host = _host("function sysCall_init()\n  local x = sim.object_not_a_type\nend\n")
    assert host.errors == []
    assert [(m.function, m.line) for m in host.missing] == [("sim.object_not_a_type (constant)", 2)]
