"""The legacy remote API's side of the scene scripts: ``simxCallScriptFunction`` and
``simxReadVisionSensor`` (the Simulator's ScriptHost comes from :mod:`sims.lua.attach`).
"""

from __future__ import annotations

from typing import Any

from sims.remote_api import commands as cmd
from sims.remote_api import constants as C
from sims.remote_api.client import current_session
from sims.remote_api.execute import execute, f32, f32s, int_arg, str_arg

from .host import ScriptHost
from .runtime import LuaScriptError

SCRIPT_KINDS = {
    C.sim_scripttype_childscript: "child",
    C.sim_scripttype_customizationscript: "customization",
}


def _host(world: Any) -> ScriptHost:
    session = current_session()
    host = getattr(session.simulator, "lua", None) if session is not None else None
    if host is None or host.world is not world:
        raise cmd.CommandError("the scene has no scripts running")
    return host


def simxCallScriptFunction(
    clientID,
    scriptDescription,
    options,
    functionName,
    inputInts,
    inputFloats,
    inputStrings,
    inputBuffer,
    operationMode,
):
    """Call ``functionName`` of the script attached to ``scriptDescription`` with
    (ints, floats, strings, buffer); returns (code, ints, floats, strings, buffer)."""
    script = str_arg(scriptDescription, 2)
    kind = SCRIPT_KINDS.get(int_arg(options, 3), "child")
    function = str_arg(functionName, 4)
    ints = [int_arg(v, 5) for v in inputInts]
    floats = [f32(v) for v in inputFloats]
    strings = [str_arg(v, 7) for v in inputStrings]
    buffer = bytes(inputBuffer.encode() if isinstance(inputBuffer, str) else inputBuffer)

    def run(world: Any) -> tuple:
        host = _host(world)
        try:
            out = host.call_function(script, kind, function, (ints, floats, strings, buffer))
        except (LookupError, LuaScriptError) as exc:
            host.status(f"simxCallScriptFunction: {exc}")
            raise cmd.CommandError(str(exc)) from exc
        out = tuple(out) + (None,) * (4 - len(out))
        r_ints = [int(v) for v in (out[0] or []) if isinstance(v, (int, float))]
        r_floats = f32s(v for v in (out[1] or []) if isinstance(v, (int, float)))
        r_strings = [
            v.decode("utf-8", "replace") if isinstance(v, bytes) else str(v) for v in (out[2] or [])
        ]
        r_buffer = bytearray(out[3] if isinstance(out[3], bytes) else b"")
        return r_ints, r_floats, r_strings, r_buffer

    key = ("call_script", script, function, len(ints), len(floats), len(strings))
    code, out = execute(clientID, operationMode, key, run, ([], [], [], bytearray()))
    return code, list(out[0]), list(out[1]), list(out[2]), bytearray(out[3])


def simxReadVisionSensor(clientID, sensorHandle, operationMode):
    """(code, detectionState, auxPackets): the default image processing's packet of
    min/max/average intensity, red, green, blue and depth (one packet of 15 values)."""
    from sims.simapi.vision import read_vision_sensor

    h = int_arg(sensorHandle, 2)

    def run(world: Any) -> tuple:
        try:
            detected, packet = read_vision_sensor(world, h)
        except (KeyError, ValueError) as exc:
            raise cmd.CommandError(str(exc)) from exc
        return bool(detected), [f32s(packet)]

    code, out = execute(clientID, operationMode, ("read_vision", h), run, (False, []))
    return code, bool(out[0]), [list(p) for p in out[1]]
