"""The legacy remote API functions that change the scene (creating, removing and re-parenting
objects, copying, the selection, loading scenes and models) and collision and distance
(``functions_params`` has sensors, parameters, consoles and ``simxQuery``).

Each is carried out by the one ``sim.*`` table the ZeroMQ API and the scene's Lua scripts share
(``ZmqServer.call_function``): no second implementation. A ``sim.*`` function that table lacks,
or that fails, makes the legacy call return the remote error flag (8) with zeroed outputs, as
CoppeliaSim's server reports a failed command; a missing one is also listed in the run's
summary. Signatures and return shapes are those of CoppeliaSim 4.2's ``sim.py``.
"""

from __future__ import annotations

from typing import Any

from . import commands as cmd
from .client import current_session, script_site
from .execute import execute, f32, float_arg, int_arg, str_arg

#: Which sim.* function carries out each legacy function of this module (the listing's table).
VIA = {
    "simxCreateDummy": "sim.createDummy",
    "simxRemoveObject": "sim.removeObject",
    "simxRemoveModel": "sim.removeModel",
    "simxSetObjectParent": "sim.setObjectParent",
    "simxCopyPasteObjects": "sim.copyPasteObjects",
    "simxGetObjectSelection": "sim.getObjectSel",
    "simxSetObjectSelection": "sim.setObjectSel",
    "simxLoadScene": "sim.loadScene",
    "simxLoadModel": "sim.loadModel",
    "simxCloseScene": "sim.closeScene",
    "simxGetCollisionHandle": "sim.getCollisionHandle",
    "simxGetDistanceHandle": "sim.getDistanceHandle",
    "simxGetCollectionHandle": "sim.getCollectionHandle",
    "simxReadCollision": "sim.readCollision",
    "simxReadDistance": "sim.readDistance",
    "simxCheckCollision": "sim.checkCollision",
    "simxCheckDistance": "sim.checkDistance",
    "simxReadForceSensor": "sim.readForceSensor",
    "simxBreakForceSensor": "sim.breakForceSensor",
    "simxGetVisionSensorDepthBuffer": "sim.getVisionSensorDepth",
    "simxSetVisionSensorImage": "sim.setVisionSensorImg",
    "simxGetObjectFloatParameter": "sim.getObjectFloatParam",
    "simxGetObjectIntParameter": "sim.getObjectInt32Param",
    "simxSetObjectFloatParameter": "sim.setObjectFloatParam",
    "simxSetObjectIntParameter": "sim.setObjectInt32Param",
    "simxGetModelProperty": "sim.getModelProperty",
    "simxSetModelProperty": "sim.setModelProperty",
    "simxGetStringParameter": "sim.getStringParam",
    "simxSetFloatingParameter": "sim.setFloatParam",
    "simxSetIntegerParameter": "sim.setInt32Param",
    "simxSetBooleanParameter": "sim.setBoolParam",
    "simxSetArrayParameter": "sim.setArrayParam",
    "simxAuxiliaryConsoleOpen": "sim.auxiliaryConsoleOpen",
    "simxAuxiliaryConsoleClose": "sim.auxiliaryConsoleClose",
    "simxAuxiliaryConsolePrint": "sim.auxiliaryConsolePrint",
    "simxAuxiliaryConsoleShow": "sim.auxiliaryConsoleShow",
}


def _sim(func: str, *args: Any, legacy: str, site: str) -> Any:
    """``func(*args)`` from the sim.* table, for the legacy function ``legacy``."""
    from .zmq.functions import server_for
    from .zmq.server import ZmqError

    session = current_session()
    server = server_for(session)
    if func not in server.functions:
        session.note_missing("function", f"{legacy} (needs {func})", site)
        raise cmd.CommandError(f"{legacy}: {func} is not emulated by sitegen")
    try:
        return server.call_function(func, list(args))
    except ZmqError as exc:
        raise cmd.CommandError(str(exc)) from None


def _call(clientID, operationMode, key, func, args, zero, legacy, setter=False, shape=None):
    site = script_site()

    def run(world):
        value = _sim(func, *args, legacy=legacy, site=site)
        return shape(value) if shape is not None else ()

    return execute(clientID, operationMode, key, run, zero, setter=setter)


def _one(value: Any) -> Any:
    return value[0] if isinstance(value, (list, tuple)) else value


# --- objects: create, remove, re-parent, copy -----------------------------------------------------
def simxCreateDummy(clientID, size, colors, operationMode):
    """(code, handle): a dummy of ``size`` at the world origin; ``colors``: 12 bytes (ambient,
    diffuse, specular and emission RGB, 0-255) or None."""
    s = float_arg(size, 2)
    color = None if colors is None else [int(c) / 255.0 for c in list(colors)[:12]]
    args = [s] if color is None else [s, color]
    code, out = _call(
        clientID,
        operationMode,
        ("create_dummy",),
        "sim.createDummy",
        args,
        (0,),
        "simxCreateDummy",
        shape=lambda h: (int(_one(h)),),
    )
    return code, out[0]


def simxRemoveObject(clientID, objectHandle, operationMode):
    h = int_arg(objectHandle, 2)
    key, name = ("remove", h), "simxRemoveObject"
    return _call(clientID, operationMode, key, "sim.removeObject", [h], (), name, True)[0]


def simxRemoveModel(clientID, objectHandle, operationMode):
    h = int_arg(objectHandle, 2)
    key, name = ("remove_model", h), "simxRemoveModel"
    return _call(clientID, operationMode, key, "sim.removeModel", [h], (), name, True)[0]


def simxSetObjectParent(clientID, objectHandle, parentObject, keepInPlace, operationMode):
    h, parent = int_arg(objectHandle, 2), int_arg(parentObject, 3)
    return _call(
        clientID,
        operationMode,
        ("set_parent", h),
        "sim.setObjectParent",
        [h, parent, bool(keepInPlace)],
        (),
        "simxSetObjectParent",
        True,
    )[0]


def simxCopyPasteObjects(clientID, objectHandles, operationMode):
    handles = [int_arg(h, 2) for h in objectHandles]
    code, out = _call(
        clientID,
        operationMode,
        ("copy_paste",),
        "sim.copyPasteObjects",
        [handles, 0],
        ([],),
        "simxCopyPasteObjects",
        shape=lambda v: ([int(h) for h in v],),
    )
    return code, list(out[0])


def simxGetObjectSelection(clientID, operationMode):
    code, out = _call(
        clientID,
        operationMode,
        ("selection",),
        "sim.getObjectSel",
        [],
        ([],),
        "simxGetObjectSelection",
        shape=lambda v: ([int(h) for h in (v or [])],),
    )
    return code, list(out[0])


def simxSetObjectSelection(clientID, objectHandles, operationMode):
    handles = [int_arg(h, 2) for h in objectHandles]
    return _call(
        clientID, operationMode, ("set_selection",), "sim.setObjectSel", [handles], (),
        "simxSetObjectSelection", True,
    )[0]  # fmt: skip


# --- scenes and models ---
def simxLoadScene(clientID, scenePathAndName, options, operationMode):
    """Load a scene file (``options`` bit 0, "the file is on the client", changes nothing here:
    client and server share one file system)."""
    path = str_arg(scenePathAndName, 2)
    return _call(
        clientID, operationMode, ("load_scene", path), "sim.loadScene", [path], (),
        "simxLoadScene", True,
    )[0]  # fmt: skip


def simxLoadModel(clientID, modelPathAndName, options, operationMode):
    path = str_arg(modelPathAndName, 2)
    code, out = _call(
        clientID,
        operationMode,
        ("load_model", path),
        "sim.loadModel",
        [path],
        (0,),
        "simxLoadModel",
        shape=lambda h: (int(_one(h)),),
    )
    return code, out[0]


def simxCloseScene(clientID, operationMode):
    return _call(
        clientID, operationMode, ("close_scene",), "sim.closeScene", [], (), "simxCloseScene", True
    )[0]


# --- collision, distance, collections ---
def _named_handle(clientID, name, operationMode, func, legacy):
    text = str_arg(name, 2)
    code, out = _call(
        clientID, operationMode, (legacy, text), func, [text], (0,), legacy,
        shape=lambda h: (int(_one(h)),),
    )  # fmt: skip
    return code, out[0]


def simxGetCollisionHandle(clientID, collisionObjectName, operationMode):
    return _named_handle(
        clientID, collisionObjectName, operationMode, "sim.getCollisionHandle",
        "simxGetCollisionHandle",
    )  # fmt: skip


def simxGetDistanceHandle(clientID, distanceObjectName, operationMode):
    return _named_handle(
        clientID, distanceObjectName, operationMode, "sim.getDistanceHandle",
        "simxGetDistanceHandle",
    )  # fmt: skip


def simxGetCollectionHandle(clientID, collectionName, operationMode):
    return _named_handle(
        clientID, collectionName, operationMode, "sim.getCollectionHandle",
        "simxGetCollectionHandle",
    )  # fmt: skip


def simxReadCollision(clientID, collisionObjectHandle, operationMode):
    h = int_arg(collisionObjectHandle, 2)
    code, out = _call(
        clientID, operationMode, ("read_collision", h), "sim.readCollision", [h], (False,),
        "simxReadCollision", shape=lambda v: (bool(_one(v)),),
    )  # fmt: skip
    return code, out[0]


def simxReadDistance(clientID, distanceObjectHandle, operationMode):
    h = int_arg(distanceObjectHandle, 2)

    def shape(v):  # sim.readDistance: (result, distance)
        return (f32(v[1] if isinstance(v, (list, tuple)) and len(v) > 1 else v),)

    code, out = _call(
        clientID, operationMode, ("read_distance", h), "sim.readDistance", [h], (0.0,),
        "simxReadDistance", shape=shape,
    )  # fmt: skip
    return code, out[0]


def simxCheckCollision(clientID, entity1, entity2, operationMode):
    a, b = int_arg(entity1, 2), int_arg(entity2, 3)
    code, out = _call(
        clientID, operationMode, ("check_collision", a, b), "sim.checkCollision", [a, b],
        (False,), "simxCheckCollision", shape=lambda v: (bool(_one(v)),),
    )  # fmt: skip
    return code, out[0]


def simxCheckDistance(clientID, entity1, entity2, operationMode):
    a, b = int_arg(entity1, 2), int_arg(entity2, 3)

    def shape(v):  # sim.checkDistance: (result, [p1 xyz, p2 xyz, distance], ...)
        data = v[1] if isinstance(v, (list, tuple)) and len(v) > 1 else v
        if isinstance(data, (list, tuple)):  # no pair of shapes to measure: no distance
            data = data[6] if len(data) > 6 else 0.0
        return (f32(data),)

    code, out = _call(
        clientID, operationMode, ("check_distance", a, b), "sim.checkDistance", [a, b, 0.0],
        (0.0,), "simxCheckDistance", shape=shape,
    )  # fmt: skip
    return code, out[0]
