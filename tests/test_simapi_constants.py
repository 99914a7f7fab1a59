"""One table of constant names for Lua scripts and ZeroMQ clients (sims/simapi/constants.py).

Lua and ZeroMQ each kept a list of their own once, and four names had different values in the
two (``handleflag_reljointbaseframe``, ``handleflag_axis``, ``modelproperty_not_visible``,
``drawing_cyclic``): a Lua script's flag was not the one ``sim.getObjectPose`` tested for.
"""

from __future__ import annotations

from sims.lua.constants import constants
from sims.remote_api import constants as legacy
from sims.remote_api.zmq.constants import CONSTANTS
from sims.simapi.constants import ADDED, named
from sims.simapi.poses import REL_JOINT_BASE


def test_the_added_names_agree_with_the_legacy_table_wherever_both_name_one():
    old = {n[4:]: v for n, v in vars(legacy).items() if n.startswith("sim_")}
    differ = {n: (v, old[n]) for n, v in ADDED.items() if n in old and old[n] != v}
    assert differ == {}


def test_lua_scripts_and_zeromq_clients_see_the_same_values():
    for new_style in (True, False):
        lua = constants(new_style)
        assert {n: lua[n] for n in CONSTANTS} == CONSTANTS == named()
    # CoppeliaSim 4.x simConst.h (32-bit handles): the flags the pose functions read
    assert CONSTANTS["handleflag_reljointbaseframe"] == REL_JOINT_BASE == 0x00400000
    assert CONSTANTS["handleflag_axis"] == 0x00400000
    assert CONSTANTS["drawing_cyclic"] == 0x001000
    assert CONSTANTS["modelproperty_not_visible"] == 0x0100
    assert (CONSTANTS["api_error_output"], CONSTANTS["api_warning_output"]) == (2, 4)
