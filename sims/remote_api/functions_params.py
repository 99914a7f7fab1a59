"""The legacy remote API functions on force and vision sensors, object, model and scene
parameters and auxiliary consoles, and ``simxQuery``: carried out by the one ``sim.*`` table
like those of ``functions_scene`` (see there), whose helpers they use.
"""

from __future__ import annotations

from .client import current_session
from .execute import f32, f32s, float_arg, int_arg, str_arg
from .functions_scene import _call, _one


# --- force and vision sensors ---
def simxReadForceSensor(clientID, forceSensorHandle, operationMode):
    """(code, state, force, torque): state bit 0 = a value is there, bit 1 = broken."""
    h = int_arg(forceSensorHandle, 2)

    def shape(v):
        result, force, torque = (list(v) + [0, [0.0] * 3, [0.0] * 3])[:3]
        return int(result), f32s(force), f32s(torque)

    code, out = _call(
        clientID, operationMode, ("read_force", h), "sim.readForceSensor", [h],
        (0, [0.0] * 3, [0.0] * 3), "simxReadForceSensor", shape=shape,
    )  # fmt: skip
    return code, out[0], list(out[1]), list(out[2])


def simxBreakForceSensor(clientID, forceSensorHandle, operationMode):
    h = int_arg(forceSensorHandle, 2)
    return _call(
        clientID, operationMode, ("break_force", h), "sim.breakForceSensor", [h], (),
        "simxBreakForceSensor", True,
    )[0]  # fmt: skip


def simxGetVisionSensorDepthBuffer(clientID, sensorHandle, operationMode):
    """(code, [width, height], depths): 0..1 from the near to the far clipping plane."""
    import struct

    h = int_arg(sensorHandle, 2)

    def shape(v):
        data, res = v[0], list(v[1])
        if isinstance(data, (bytes, bytearray)):
            data = list(struct.unpack(f"<{len(data) // 4}f", bytes(data)))
        return [int(r) for r in res], f32s(data)

    code, out = _call(
        clientID, operationMode, ("depth", h), "sim.getVisionSensorDepth", [h], ([], []),
        "simxGetVisionSensorDepthBuffer", shape=shape,
    )  # fmt: skip
    return code, list(out[0]), list(out[1])


def simxSetVisionSensorImage(clientID, sensorHandle, image, options, operationMode):
    """Write an image into a (passive) vision sensor: signed bytes, RGB or grey (bit 0)."""
    h = int_arg(sensorHandle, 2)
    data = bytes(int(v) & 0xFF for v in image)
    if int_arg(options, 4) & 1:  # grey: one byte per pixel, as RGB triplets
        data = bytes(b for v in data for b in (v, v, v))
    return _call(
        clientID, operationMode, ("set_image", h), "sim.setVisionSensorImg", [h, data], (),
        "simxSetVisionSensorImage", True,
    )[0]  # fmt: skip


# --- object, model and scene parameters ---
def _object_param(clientID, h, pid, operationMode, func, legacy, zero, cast):
    h, pid = int_arg(h, 2), int_arg(pid, 3)
    code, out = _call(
        clientID, operationMode, (legacy, h, pid), func, [h, pid], (zero,), legacy,
        shape=lambda v: (cast(_one(v)),),
    )  # fmt: skip
    return code, out[0]


def simxGetObjectFloatParameter(clientID, objectHandle, parameterID, operationMode):
    return _object_param(
        clientID, objectHandle, parameterID, operationMode, "sim.getObjectFloatParam",
        "simxGetObjectFloatParameter", 0.0, f32,
    )  # fmt: skip


def simxGetObjectIntParameter(clientID, objectHandle, parameterID, operationMode):
    return _object_param(
        clientID, objectHandle, parameterID, operationMode, "sim.getObjectInt32Param",
        "simxGetObjectIntParameter", 0, int,
    )  # fmt: skip


def simxSetObjectFloatParameter(clientID, objectHandle, parameterID, parameterValue, operationMode):
    h, pid, v = int_arg(objectHandle, 2), int_arg(parameterID, 3), float_arg(parameterValue, 4)
    return _call(
        clientID, operationMode, ("set_fparam", h, pid), "sim.setObjectFloatParam", [h, pid, v],
        (), "simxSetObjectFloatParameter", True,
    )[0]  # fmt: skip


def simxSetObjectIntParameter(clientID, objectHandle, parameterID, parameterValue, operationMode):
    h, pid, v = int_arg(objectHandle, 2), int_arg(parameterID, 3), int_arg(parameterValue, 4)
    return _call(
        clientID, operationMode, ("set_iparam", h, pid), "sim.setObjectInt32Param", [h, pid, v],
        (), "simxSetObjectIntParameter", True,
    )[0]  # fmt: skip


def simxGetModelProperty(clientID, objectHandle, operationMode):
    h = int_arg(objectHandle, 2)
    code, out = _call(
        clientID, operationMode, ("model_prop", h), "sim.getModelProperty", [h], (0,),
        "simxGetModelProperty", shape=lambda v: (int(_one(v)),),
    )  # fmt: skip
    return code, out[0]


def simxSetModelProperty(clientID, objectHandle, prop, operationMode):
    h, p = int_arg(objectHandle, 2), int_arg(prop, 3)
    return _call(
        clientID, operationMode, ("set_model_prop", h), "sim.setModelProperty", [h, p], (),
        "simxSetModelProperty", True,
    )[0]  # fmt: skip


def simxGetStringParameter(clientID, paramIdentifier, operationMode):
    pid = int_arg(paramIdentifier, 2)
    code, out = _call(
        clientID, operationMode, ("string_param", pid), "sim.getStringParam", [pid], ("",),
        "simxGetStringParameter", shape=lambda v: (str(_one(v)),),
    )  # fmt: skip
    return code, out[0]


def _set_param(clientID, pid, value, operationMode, func, legacy):
    pid = int_arg(pid, 2)
    return _call(clientID, operationMode, (legacy, pid), func, [pid, value], (), legacy, True)[0]


def simxSetFloatingParameter(clientID, paramIdentifier, paramValue, operationMode):
    return _set_param(
        clientID, paramIdentifier, float_arg(paramValue, 3), operationMode, "sim.setFloatParam",
        "simxSetFloatingParameter",
    )  # fmt: skip


def simxSetIntegerParameter(clientID, paramIdentifier, paramValue, operationMode):
    return _set_param(
        clientID, paramIdentifier, int_arg(paramValue, 3), operationMode, "sim.setInt32Param",
        "simxSetIntegerParameter",
    )  # fmt: skip


def simxSetBooleanParameter(clientID, paramIdentifier, paramValue, operationMode):
    return _set_param(
        clientID, paramIdentifier, bool(paramValue), operationMode, "sim.setBoolParam",
        "simxSetBooleanParameter",
    )  # fmt: skip


def simxSetArrayParameter(clientID, paramIdentifier, paramValues, operationMode):
    values = [float_arg(v, 3) for v in list(paramValues)[:3]]
    return _set_param(
        clientID, paramIdentifier, values, operationMode, "sim.setArrayParam",
        "simxSetArrayParameter",
    )  # fmt: skip


# --- auxiliary consoles (their text goes to stderr, as the status bar's) ---
def simxAuxiliaryConsoleOpen(
    clientID, title, maxLines, mode, position, size, textColor, backgroundColor, operationMode
):
    text = str_arg(title, 2)
    code, out = _call(
        clientID, operationMode, ("console_open", text), "sim.auxiliaryConsoleOpen",
        [text, int_arg(maxLines, 3), int_arg(mode, 4)], (0,), "simxAuxiliaryConsoleOpen",
        shape=lambda h: (int(_one(h)),),
    )  # fmt: skip
    return code, out[0]


def simxAuxiliaryConsoleClose(clientID, consoleHandle, operationMode):
    h = int_arg(consoleHandle, 2)
    return _call(
        clientID, operationMode, ("console_close", h), "sim.auxiliaryConsoleClose", [h], (),
        "simxAuxiliaryConsoleClose", True,
    )[0]  # fmt: skip


def simxAuxiliaryConsolePrint(clientID, consoleHandle, txt, operationMode):
    h = int_arg(consoleHandle, 2)
    text = None if txt is None else str_arg(txt, 3)
    return _call(
        clientID, operationMode, ("console_print", h), "sim.auxiliaryConsolePrint", [h, text],
        (), "simxAuxiliaryConsolePrint", True,
    )[0]  # fmt: skip


def simxAuxiliaryConsoleShow(clientID, consoleHandle, showState, operationMode):
    h = int_arg(consoleHandle, 2)
    return _call(
        clientID, operationMode, ("console_show", h), "sim.auxiliaryConsoleShow",
        [h, bool(showState)], (), "simxAuxiliaryConsoleShow", True,
    )[0]  # fmt: skip


# --- simxQuery: the client library's request/reply over string signals ---
def simxQuery(clientID, signalName, signalValue, retSignalName, timeOutInMs):
    """Set ``signalName`` and wait (script clock) for ``retSignalName`` to be set by the scene's
    scripts; (code, reply) with the timeout flag (2) when no reply came in time."""
    from .extras import simxClearStringSignal, simxGetAndClearStringSignal, simxSetStringSignal

    blocking, streaming, buffer = 0x010000, 0x020000, 0x060000
    simxClearStringSignal(clientID, retSignalName, 0)
    simxGetAndClearStringSignal(clientID, retSignalName, streaming)
    err = simxSetStringSignal(clientID, signalName, signalValue, blocking)
    if err != 0:
        return err, bytearray()
    clock = current_session().clock  # the run's clock: virtual time lets the scene answer
    start = clock.now()
    while (clock.now() - start) * 1000 < int_arg(timeOutInMs, 5):
        code, value = simxGetAndClearStringSignal(clientID, retSignalName, buffer)
        if code == 0:
            return 0, value
        clock.advance(0.005)
    return 2, bytearray()
