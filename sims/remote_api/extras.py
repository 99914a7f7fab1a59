"""Signals, parameters, packing helpers and the functions this emulation does not provide.

A legacy function that exists in ``sim.py`` but has no meaning here (vision sensors, UI dialogs,
scene loading, Lua calls, ...) is still defined: it returns ``simx_return_local_error_flag`` with
outputs shaped like the real ones, and prints one message per function on stderr. A ``simx*``
name that ``sim.py`` never had is served by the module's ``__getattr__`` the same way.
"""

from __future__ import annotations

import ctypes
import struct
import sys
from typing import Any

from . import commands as cmd
from . import constants as C
from .client import current_session, script_site
from .execute import LOCAL, execute, f32, float_arg, int_arg, str_arg

# --- signals -------------------------------------------------------------------------------------
_SIGNAL_CAST = {
    "float": lambda v: f32(float_arg(v, 3)),
    "int": lambda v: ctypes.c_int32(int_arg(v, 3)).value,
    "string": lambda v: bytes(v.encode("utf-8") if isinstance(v, str) else bytes(v)),
}


def _signals(kind: str) -> dict[str, Any]:
    session = current_session()
    return session.simulator.signals[kind]


def _set_signal(kind, clientID, signalName, value, operationMode, append=False):
    name = str_arg(signalName, 2)
    v = _SIGNAL_CAST[kind](value)

    def run(world):
        table = _signals(kind)
        table[name] = (table.get(name, b"") + v) if append else v
        return ()

    return execute(clientID, operationMode, (kind + "_signal_set", name), run, (), setter=True)[0]


def _get_signal(kind, clientID, signalName, operationMode, zero, clear=False):
    name = str_arg(signalName, 2)

    def run(world):
        table = _signals(kind)
        if name not in table:
            raise cmd.CommandError(f"signal {name!r} does not exist")
        return (table.pop(name) if clear else table[name],)

    code, out = execute(clientID, operationMode, (kind + "_signal_get", name), run, (zero,))
    return code, out[0]


def _clear_signal(kind, clientID, signalName, operationMode):
    name = str_arg(signalName, 2)

    def run(world):
        table = _signals(kind)
        if name:
            table.pop(name, None)
        else:
            table.clear()
        return ()

    return execute(clientID, operationMode, (kind + "_signal_clear", name), run, (), setter=True)[0]


def simxSetFloatSignal(clientID, signalName, signalValue, operationMode):
    return _set_signal("float", clientID, signalName, signalValue, operationMode)


def simxGetFloatSignal(clientID, signalName, operationMode):
    return _get_signal("float", clientID, signalName, operationMode, 0.0)


def simxClearFloatSignal(clientID, signalName, operationMode):
    return _clear_signal("float", clientID, signalName, operationMode)


def simxSetIntegerSignal(clientID, signalName, signalValue, operationMode):
    return _set_signal("int", clientID, signalName, signalValue, operationMode)


def simxGetIntegerSignal(clientID, signalName, operationMode):
    return _get_signal("int", clientID, signalName, operationMode, 0)


def simxClearIntegerSignal(clientID, signalName, operationMode):
    return _clear_signal("int", clientID, signalName, operationMode)


def simxSetStringSignal(clientID, signalName, signalValue, operationMode):
    return _set_signal("string", clientID, signalName, signalValue, operationMode)


def simxAppendStringSignal(clientID, signalName, signalValueToAppend, operationMode):
    return _set_signal("string", clientID, signalName, signalValueToAppend, operationMode, True)


simxWriteStringStream = simxAppendStringSignal


def simxGetStringSignal(clientID, signalName, operationMode):
    code, value = _get_signal("string", clientID, signalName, operationMode, b"")
    return code, bytearray(value)


def simxGetAndClearStringSignal(clientID, signalName, operationMode):
    code, value = _get_signal("string", clientID, signalName, operationMode, b"", clear=True)
    return code, bytearray(value)


simxReadStringStream = simxGetAndClearStringSignal


def simxClearStringSignal(clientID, signalName, operationMode):
    return _clear_signal("string", clientID, signalName, operationMode)


# --- parameters ----------------------------------------------------------------------------------
def _parameter(clientID, paramIdentifier, operationMode, kind, table, zero):
    pid = int_arg(paramIdentifier, 2)

    def run(world):
        sim = current_session().simulator
        if pid not in table:
            raise cmd.CommandError(f"{kind} parameter {pid} is not available")
        return (table[pid](sim),)

    code, out = execute(clientID, operationMode, (kind + "_param", pid), run, (zero,))
    return code, out[0]


_FLOAT_PARAMS = {
    C.sim_floatparam_simulation_time_step: lambda s: f32(s.pass_dt),
    C.sim_floatparam_dynamic_step_size: lambda s: f32(s.world.timestep),
}
_INT_PARAMS = {
    C.sim_intparam_program_version: lambda s: 40200,
    C.sim_intparam_dynamic_engine: lambda s: C.sim_physics_bullet,
    C.sim_intparam_dynamic_step_divider: lambda s: s.steps_per_pass,
    C.sim_intparam_speedmodifier: lambda s: 0,
    C.sim_intparam_mouse_x: lambda s: 0,  # no window, no mouse: the origin
    C.sim_intparam_mouse_y: lambda s: 0,
}
_BOOL_PARAMS = {
    C.sim_boolparam_realtime_simulation: lambda s: s.clock.realtime,
    C.sim_boolparam_dynamics_handling_enabled: lambda s: True,
    C.sim_boolparam_hierarchy_visible: lambda s: False,
    C.sim_boolparam_console_visible: lambda s: False,
}
_ARRAY_PARAMS = {C.sim_arrayparam_gravity: lambda s: [0.0, 0.0, f32(-9.81)]}


def simxGetFloatingParameter(clientID, paramIdentifier, operationMode):
    return _parameter(clientID, paramIdentifier, operationMode, "float", _FLOAT_PARAMS, 0.0)


def simxGetIntegerParameter(clientID, paramIdentifier, operationMode):
    return _parameter(clientID, paramIdentifier, operationMode, "int", _INT_PARAMS, 0)


def simxGetBooleanParameter(clientID, paramIdentifier, operationMode):
    code, value = _parameter(clientID, paramIdentifier, operationMode, "bool", _BOOL_PARAMS, False)
    return code, bool(value)


def simxGetArrayParameter(clientID, paramIdentifier, operationMode):
    code, value = _parameter(
        clientID, paramIdentifier, operationMode, "array", _ARRAY_PARAMS, [0.0, 0.0, 0.0]
    )
    return code, list(value)


# --- packing helpers (pure, as in sim.py) ------------------------------------------------------
def simxPackInts(intList):
    return bytearray(b"".join(struct.pack("<i", int(v)) for v in intList))


def simxUnpackInts(intsPackedInString):
    data = (
        bytes(intsPackedInString, "latin-1")
        if isinstance(intsPackedInString, str)
        else bytes(intsPackedInString)
    )
    return [struct.unpack("<i", data[4 * i : 4 * i + 4])[0] for i in range(len(data) // 4)]


def simxPackFloats(floatList):
    return bytearray(b"".join(struct.pack("<f", float(v)) for v in floatList))


def simxUnpackFloats(floatsPackedInString):
    data = (
        bytes(floatsPackedInString, "latin-1")
        if isinstance(floatsPackedInString, str)
        else bytes(floatsPackedInString)
    )
    return [struct.unpack("<f", data[4 * i : 4 * i + 4])[0] for i in range(len(data) // 4)]


def simxReleaseBuffer(buffer):
    return None


def simxCreateBuffer(bufferSize):
    return ctypes.create_string_buffer(int_arg(bufferSize, 1))


# --- unsupported functions -----------------------------------------------------------------------
_warned: set[str] = set()

#: Functions of sim.py this emulation does not provide, with the outputs they would return.
UNSUPPORTED: dict[str, tuple] = {
    "simxLoadUI": ([],),
    "simxGetUIHandle": (0,),
    "simxGetUISlider": (0,),
    "simxSetUISlider": (),
    "simxGetUIEventButton": (0, [0, 0]),
    "simxGetUIButtonProperty": (0,),
    "simxSetUIButtonProperty": (),
    "simxSetUIButtonLabel": (),
    "simxRemoveUI": (),
    "simxDisplayDialog": (0, 0),
    "simxEndDialog": (),
    "simxGetDialogInput": ("",),
    "simxGetDialogResult": (0,),
    "simxTransferFile": (),
    "simxEraseFile": (),
}


def _report_unsupported(name: str, known: bool) -> None:
    """One message per function and run (per process when no run is configured)."""
    what = (
        "is not supported by the sitegen pybullet emulation"
        if known
        else "is not a legacy remote API function known to the sitegen emulation"
    )
    text = f"{name} {what}: it returns simx_return_local_error_flag (32)"
    session = current_session()
    if session is not None:
        session.note_missing("function", name, script_site())
        session.warn_once("unsupported:" + name, text)
    elif name not in _warned:
        _warned.add(name)
        print(f"[sim] {text}", file=sys.stderr, flush=True)


def make_stub(name: str, known: bool = True):
    outputs = UNSUPPORTED.get(name, ())

    def stub(*args: Any, **kwargs: Any):
        _report_unsupported(name, known)
        if not outputs:
            return LOCAL
        return (LOCAL, *[type(o)(o) if isinstance(o, (list, bytearray)) else o for o in outputs])

    stub.__name__ = stub.__qualname__ = name
    stub.__doc__ = f"{name}: not supported here; returns simx_return_local_error_flag."
    return stub


for _name in UNSUPPORTED:
    globals()[_name] = make_stub(_name)
del _name

# issue 14: served by the scene's Lua scripts and vision sensors
from sims.lua.remote import simxCallScriptFunction, simxReadVisionSensor  # noqa: E402, F401


def module_getattr(name: str):
    """For the ``sim`` module's ``__getattr__``: unknown ``simx*`` names become stubs."""
    if name.startswith("simx") and not name.startswith("simx_"):
        return make_stub(name, known=False)
    raise AttributeError(
        f"module 'sim' has no attribute {name!r} (not provided by the sitegen remote API emulation)"
    )
