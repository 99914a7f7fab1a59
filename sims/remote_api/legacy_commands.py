"""What the legacy remote API server does with each command code: the arguments it reads from a
command, the emulated ``simx*`` function it calls, the values it writes back.

Each command is carried out by the same function an in-process script calls (``api``), on a
connection slot of the session that stands for the network client, in blocking mode; its
return code decides the reply's error bit (0: values follow; anything else: the remote error
flag, as CoppeliaSim's server reports a failed command). Command codes are those of
CoppeliaSim's ``simConst.h`` (``simx_cmd_*``); value layouts are those the client library
reads (``extApi.c``). A code the table lacks is answered with the error bit.
"""

from __future__ import annotations

import struct
from collections.abc import Callable

from . import api
from .legacy_codec import (
    Command,
    ProtocolError,
    cstrings,
    floats,
    ints,
    pack_floats,
    pack_ints,
)

B = api.simx_opmode_blocking
Handler = Callable[[int, Command], tuple[int, bytes]]
TABLE: dict[int, tuple[str, Handler]] = {}


def _code(result) -> int:
    return int(result[0] if isinstance(result, tuple) else result)


def _i(cmd: Command, k: int = 0) -> int:
    return ints(cmd.ident[4 * k : 4 * k + 4], 1)[0]


def _s(cmd: Command) -> str:
    return cmd.ident.split(b"\0", 1)[0].decode("utf-8", "replace")


def _cstr(text) -> bytes:
    data = text.encode("utf-8") if isinstance(text, str) else bytes(text)
    return data + b"\0"


def _reg(code: int, name: str):
    def register(fn: Handler) -> Handler:
        TABLE[code] = (name, fn)
        return fn

    return register


def _simple(code: int, name: str, args: Callable, out: Callable | None = None) -> None:
    """A command whose reply is ``out(result)`` (nothing when ``out`` is None)."""

    def run(cid: int, cmd: Command) -> tuple[int, bytes]:
        result = getattr(api, name)(cid, *args(cmd), B)
        rc = _code(result)
        return rc, (out(result) if out is not None and rc == 0 else b"")

    TABLE[code] = (name, run)


_f1 = lambda r: pack_floats([r[1]])  # noqa: E731
_i1 = lambda r: pack_ints([int(r[1])])  # noqa: E731
_fl = lambda r: pack_floats(r[1])  # noqa: E731
_il = lambda r: pack_ints([len(r[1]), *r[1]])  # noqa: E731
_bytes = lambda r: bytes(r[1])  # noqa: E731
_h = lambda c: (_i(c),)  # noqa: E731
_hh = lambda c: (_i(c), _i(c, 1))  # noqa: E731
_hf = lambda c: (_i(c), floats(c.pure, 1)[0])  # noqa: E731
_name = lambda c: (_s(c),)  # noqa: E731
_none = lambda c: ()  # noqa: E731

# --- simulation and connection ------------------------------------------------------------------
TABLE[0x0001] = ("simxSynchronous", lambda cid, c: (api.simxSynchronous(cid, True), b""))
TABLE[0x0002] = ("simxSynchronous", lambda cid, c: (api.simxSynchronous(cid, False), b""))
TABLE[0x0003] = ("simxSynchronousTrigger", lambda cid, c: (api.simxSynchronousTrigger(cid), b""))


@_reg(0x1007, "simxStartSimulation")
def _start_pause_stop(cid: int, cmd: Command) -> tuple[int, bytes]:
    which = _i(cmd)
    fn = {0: api.simxStartSimulation, 1: api.simxPauseSimulation, 2: api.simxStopSimulation}
    if which not in fn:
        return api.simx_return_remote_error_flag, b""
    return fn[which](cid, B), b""


_simple(
    0x0004,
    "simxGetLastErrors",
    _none,
    lambda r: pack_ints([len(r[1])]) + b"".join(_cstr(e) for e in r[1]),
)
_simple(0x0005, "simxCloseScene", _none)
_simple(0x0006, "simxGetObjectSelection", _none, _il)
_simple(0x3008, "simxAddStatusbarMessage", _name)


@_reg(0x0009, "simxCreateDummy")
def _create_dummy(cid: int, cmd: Command) -> tuple[int, bytes]:
    if len(cmd.pure) < 5:
        raise ProtocolError("simxCreateDummy: arguments cut short")
    size = floats(cmd.pure, 1)[0]
    colors = list(cmd.pure[5:17]) if cmd.pure[4] else None
    result = api.simxCreateDummy(cid, size, colors, B)
    return _code(result), (_i1(result) if _code(result) == 0 else b"")


# --- joints -------------------------------------------------------------------------------------
_simple(0x1001, "simxGetJointPosition", _h, _f1)
_simple(0x1002, "simxSetJointPosition", _hf)
_simple(0x1008, "simxSetJointTargetVelocity", _hf)
_simple(0x100C, "simxSetJointTargetPosition", _hf)
_simple(0x100D, "simxGetJointForce", _h, _f1)
_simple(0x100E, "simxSetJointMaxForce", _hf)
_simple(0x1038, "simxGetJointMaxForce", _h, _f1)
_simple(0x100A, "simxGetJointMatrix", _h, _fl)
_simple(0x100B, "simxSetSphericalJointMatrix", lambda c: (_i(c), floats(c.pure, 12)))

# --- sensors ------------------------------------------------------------------------------------
_simple(
    0x1009,
    "simxReadProximitySensor",
    _h,
    lambda r: bytes([1 if r[1] else 0]) + pack_floats(r[2]) + pack_ints([r[3]]) + pack_floats(r[4]),
)
_simple(
    0x100F,
    "simxReadForceSensor",
    _h,
    lambda r: bytes([int(r[1]) & 0xFF]) + pack_floats(r[2]) + pack_floats(r[3]),
)
_simple(0x1010, "simxBreakForceSensor", _h)


def _vision_aux(r) -> bytes:
    packets = [list(p) for p in (r[2] or [])]
    flat = [v for p in packets for v in p]
    counts = [len(p) for p in packets]
    return bytes([1 if r[1] else 0]) + pack_ints([len(counts), *counts]) + pack_floats(flat)


_simple(0x1011, "simxReadVisionSensor", _h, _vision_aux)
for _code_, _grey in ((0x1003, 1), (0x1004, 0)):
    _simple(
        _code_,
        "simxGetVisionSensorImage",
        lambda c, g=_grey: (_i(c), g),
        lambda r: pack_ints(r[1][:2]) + bytes(v & 0xFF for v in r[2]),
    )
for _code_, _grey in ((0x1005, 1), (0x1006, 0)):
    _simple(
        _code_,
        "simxSetVisionSensorImage",
        lambda c, g=_grey: (_i(c), [b - 256 if b > 127 else b for b in c.pure], g),
    )
_simple(
    0x1017,
    "simxGetVisionSensorDepthBuffer",
    _h,
    lambda r: pack_ints(r[1][:2]) + pack_floats(r[2]),
)
_simple(0x1026, "simxReadCollision", _h, lambda r: pack_ints([1 if r[1] else 0]))
_simple(0x1027, "simxReadDistance", _h, _f1)
_simple(0x200F, "simxCheckCollision", _hh, lambda r: pack_ints([1 if r[1] else 0]))
_simple(0x2010, "simxCheckDistance", _hh, _f1)
_simple(0x300A, "simxGetCollisionHandle", _name, _i1)
_simple(0x300B, "simxGetDistanceHandle", _name, _i1)
_simple(0x3019, "simxGetCollectionHandle", _name, _i1)

# --- objects ------------------------------------------------------------------------------------
_simple(0x3001, "simxGetObjectHandle", _name, _i1)
_simple(0x1012, "simxGetObjectParent", _h, _i1)
_simple(0x200B, "simxGetObjectChild", _hh, _i1)
_simple(0x102A, "simxGetObjects", _h, _il)
_simple(0x200D, "simxGetObjectOrientation", _hh, _fl)
_simple(0x200E, "simxGetObjectPosition", _hh, _fl)
_simple(0x2801, "simxGetObjectQuaternion", _hh, _fl)
_rel3 = lambda c: (_i(c), ints(c.pure, 1)[0], floats(c.pure, 3, 4))  # noqa: E731
_simple(0x101A, "simxSetObjectOrientation", _rel3)
_simple(0x101B, "simxSetObjectPosition", _rel3)
_simple(
    0x1801, "simxSetObjectQuaternion", lambda c: (_i(c), ints(c.pure, 1)[0], floats(c.pure, 4, 4))
)
_simple(
    0x101C,
    "simxSetObjectParent",
    lambda c: (_i(c), ints(c.pure, 1)[0], bool(c.pure[4:5] and c.pure[4])),
)
_simple(0x1036, "simxGetObjectVelocity", _h, lambda r: pack_floats([*r[1], *r[2]]))
_simple(0x1028, "simxRemoveObject", _h)
_simple(0x1037, "simxRemoveModel", _h)
_simple(0x102E, "simxCopyPasteObjects", lambda c: (ints(c.pure),), _il)
_simple(0x102F, "simxSetObjectSelection", lambda c: (ints(c.pure),))
_simple(0x1034, "simxGetModelProperty", _h, _i1)
_simple(0x1035, "simxSetModelProperty", lambda c: (_i(c), ints(c.pure, 1)[0]))
_simple(0x2007, "simxGetObjectFloatParameter", _hh, _f1)
_simple(0x2008, "simxGetObjectIntParameter", _hh, _i1)
_simple(0x2009, "simxSetObjectFloatParameter", lambda c: (*_hh(c), floats(c.pure, 1)[0]))
_simple(0x200A, "simxSetObjectIntParameter", lambda c: (*_hh(c), ints(c.pure, 1)[0]))


def _group(r) -> bytes:
    handles, int_data, float_data, strings = r[1], r[2], r[3], r[4]
    return (
        pack_ints([len(handles), len(int_data), len(float_data), len(strings)])
        + pack_ints(handles)
        + pack_ints(int_data)
        + pack_floats(float_data)
        + b"".join(_cstr(s) for s in strings)
    )


_simple(0x200C, "simxGetObjectGroupData", _hh, _group)

# --- scenes, models, files ----------------------------------------------------------------------
_simple(0x3002, "simxLoadScene", lambda c: (_s(c), 0))
_simple(0x3003, "simxLoadModel", lambda c: (_s(c), 0), _i1)
_simple(0x3005, "simxLoadUI", lambda c: (_s(c), 0), _il)
_simple(0x3004, "simxTransferFile", lambda c: (_s(c), _s(c), 0))
_simple(0x3006, "simxEraseFile", _name)

# --- parameters ---------------------------------------------------------------------------------
_simple(0x101D, "simxGetArrayParameter", _h, _fl)
_simple(0x101E, "simxSetArrayParameter", lambda c: (_i(c), floats(c.pure, 3)))
_simple(0x101F, "simxGetBooleanParameter", _h, lambda r: pack_ints([1 if r[1] else 0]))
_simple(0x1020, "simxSetBooleanParameter", lambda c: (_i(c), bool(ints(c.pure, 1)[0])))
_simple(0x1021, "simxGetIntegerParameter", _h, _i1)
_simple(0x1022, "simxSetIntegerParameter", lambda c: (_i(c), ints(c.pure, 1)[0]))
_simple(0x1023, "simxGetFloatingParameter", _h, _f1)
_simple(0x1024, "simxSetFloatingParameter", _hf)
_simple(0x1025, "simxGetStringParameter", _h, lambda r: _cstr(r[1]))

# --- signals ------------------------------------------------------------------------------------
_simple(0x300D, "simxClearFloatSignal", _name)
_simple(0x300E, "simxClearIntegerSignal", _name)
_simple(0x300F, "simxClearStringSignal", _name)
_simple(0x3010, "simxGetFloatSignal", _name, _f1)
_simple(0x3011, "simxGetIntegerSignal", _name, _i1)
_simple(0x3012, "simxGetStringSignal", _name, _bytes)
_simple(0x3017, "simxGetAndClearStringSignal", _name, _bytes)
_simple(0x3018, "simxReadStringStream", _name, _bytes)
_simple(0x3013, "simxSetFloatSignal", lambda c: (_s(c), floats(c.pure, 1)[0]))
_simple(0x3014, "simxSetIntegerSignal", lambda c: (_s(c), ints(c.pure, 1)[0]))
_simple(0x3015, "simxSetStringSignal", lambda c: (_s(c), bytes(c.pure)))
_simple(0x3016, "simxAppendStringSignal", lambda c: (_s(c), bytes(c.pure)))

# --- user interface: dialogs, consoles, the old custom UIs (answered with the error bit) ---
_simple(0x3009, "simxAuxiliaryConsoleOpen", lambda c: (_s(c), 0, 0, None, None, None, None), _i1)
_simple(0x1014, "simxAuxiliaryConsoleClose", _h)
_simple(0x1015, "simxAuxiliaryConsolePrint", lambda c: (_i(c), (cstrings(c.pure) or [""])[0]))
_simple(0x1016, "simxAuxiliaryConsoleShow", lambda c: (_i(c), bool(ints(c.pure, 1)[0])))
_simple(0x300C, "simxDisplayDialog", lambda c: (_s(c), "", 0, "", None, None), _i1)
_simple(0x102B, "simxEndDialog", _h)
_simple(0x102C, "simxGetDialogInput", _h, lambda r: _cstr(r[1]))
_simple(0x102D, "simxGetDialogResult", _h, _i1)
_simple(0x3007, "simxGetUIHandle", _name, _i1)
_simple(0x2001, "simxGetUISlider", _hh, _i1)
_simple(0x2002, "simxSetUISlider", lambda c: (*_hh(c), ints(c.pure, 1)[0]))
_simple(0x2003, "simxGetUIEventButton", _h, lambda r: pack_ints([r[1], *r[2]]))
_simple(0x2004, "simxGetUIButtonProperty", _hh, _i1)
_simple(0x2005, "simxSetUIButtonProperty", lambda c: (*_hh(c), ints(c.pure, 1)[0]))
_simple(0x2006, "simxSetUIButtonLabel", lambda c: (*_hh(c), *(cstrings(c.pure) + ["", ""])[:2]))
_simple(0x1029, "simxRemoveUI", _h)


# --- scripts ------------------------------------------------------------------------------------
@_reg(0x3401, "simxCallScriptFunction")
def _call_script(cid: int, cmd: Command) -> tuple[int, bytes]:
    options = _i(cmd)
    names = cstrings(cmd.ident[4:])
    if len(names) < 2:
        raise ProtocolError("simxCallScriptFunction: script or function name missing")
    n_int, n_float, n_str, n_buf = ints(cmd.pure, 4)
    at = 16
    in_ints = ints(cmd.pure[at:], n_int)
    at += 4 * n_int
    in_floats = floats(cmd.pure, n_float, at)
    at += 4 * n_float
    rest = cmd.pure[at:]
    strings: list[str] = []
    for _ in range(n_str):
        end = rest.find(b"\0")
        if end < 0:
            raise ProtocolError("simxCallScriptFunction: unterminated string")
        strings.append(rest[:end].decode("utf-8", "replace"))
        rest = rest[end + 1 :]
    buffer = bytearray(rest[:n_buf])
    result = api.simxCallScriptFunction(
        cid, names[0], options, names[1], in_ints, in_floats, strings, buffer, B
    )
    rc = _code(result)
    if rc != 0:
        return rc, b""
    out_ints, out_floats, out_strings, out_buffer = result[1:5]
    out_buffer = bytes(out_buffer or b"")
    return rc, (
        pack_ints([len(out_ints), len(out_floats), len(out_strings), len(out_buffer)])
        + pack_ints(out_ints)
        + pack_floats(out_floats)
        + b"".join(_cstr(s) for s in out_strings)
        + out_buffer
    )


def run_command(cid: int, cmd: Command) -> tuple[bool, bytes]:
    """(error, reply values) for one command; an unknown code or bad arguments: error."""
    entry = TABLE.get(cmd.code)
    if entry is None:
        return True, b""
    try:
        rc, pure = entry[1](cid, cmd)
    except (ProtocolError, struct.error, IndexError, ValueError, TypeError):
        return True, b""
    return rc != 0, pure


#: simx functions served on the wire, by command code (for the function listing)
SERVED = sorted(
    {name for name, _ in TABLE.values()}
    | {"simxPauseSimulation", "simxStopSimulation"}  # one command code with start (0x1007)
    | {"simxJointGetForce", "simxSetJointForce", "simxWriteStringStream"}  # the library's aliases
)
