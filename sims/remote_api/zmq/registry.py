"""Which of CoppeliaSim's ``sim.*`` functions the emulation knowingly does not serve
(``NOT_EMULATED``: named in the error so that a user reads "not emulated" rather than "does not
exist" for a real CoppeliaSim function). What it serves is the one table,
``sims.simapi.table.FUNCTIONS``."""

from __future__ import annotations

from sims.simapi.table import FUNCTIONS

#: Functions public ZeroMQ scripts call that have no counterpart in the emulated World.
NOT_EMULATED = frozenset(
    "sim." + name
    for name in (
        "loadScene closeScene saveScene loadModel saveModel createShape createProximitySensor "
        "createVisionSensor createForceSensor createJoint createPointCloud "
        "insertPointsIntoPointCloud groupShapes ungroupShape alignShapeBB setShapeColor "
        "getShapeColor getVisionSensorDepth getShapeMass setShapeMass getShapeInertia "
        "setJointInterval setObjectColor executeScriptString getScriptFunctions"
    ).split()
    if "sim." + name not in FUNCTIONS
)
