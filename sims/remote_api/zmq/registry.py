"""Which ``sim.*`` functions the ZeroMQ emulation serves (``FUNCTIONS``), and which of
CoppeliaSim's functions it knowingly does not (``NOT_EMULATED``: named in the error so that a
user reads "not emulated" rather than "does not exist" for a real CoppeliaSim function).

The function modules (``objects``, ``simulation``) fill ``FUNCTIONS`` through ``@api``;
they are listed, and imported, in one place: :mod:`sims.remote_api.zmq.functions`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

Fn = Callable[..., Any]
FUNCTIONS: dict[str, Fn] = {}

#: Functions public ZeroMQ scripts call that have no counterpart in the emulated World.
NOT_EMULATED = frozenset(
    "sim." + name
    for name in (
        "loadScene closeScene saveScene loadModel saveModel removeObject removeObjects "
        "removeModel createDummy createPrimitiveShape createShape createProximitySensor "
        "createVisionSensor createForceSensor createJoint createPointCloud "
        "insertPointsIntoPointCloud groupShapes ungroupShape alignShapeBB setShapeColor "
        "getShapeColor setObjectParent setObjectAlias setObjectInt32Param "
        "getObjectInt32Param setObjectFloatParam getObjectFloatParam getObjectFloatParameter "
        "setObjectMatrix getObjectMatrix callScriptFunction getScript getScriptHandle "
        "executeScriptString readForceSensor checkProximitySensor checkCollision "
        "checkDistance readVisionSensor getVisionSensorDepth getVisionSensorCharImage "
        "getVisionSensorImage addDrawingObject addDrawingObjectItem removeDrawingObject "
        "getShapeMass setShapeMass getShapeInertia resetDynamicObject setModelProperty "
        "getModelProperty setJointMode setJointInterval getJointInterval setObjectColor "
        "addForce addForceAndTorque copyPasteObjects setExplicitHandling "
        "getCollectionHandle createCollection addItemToCollection"
    ).split()
)


def api(name: str) -> Callable[[Fn], Fn]:
    """Register ``fn`` as ``sim.<name>``."""

    def register(fn: Fn) -> Fn:
        FUNCTIONS["sim." + name] = fn
        return fn

    return register
