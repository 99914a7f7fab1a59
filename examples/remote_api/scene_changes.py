"""Changing the scene and reading its other devices through the legacy remote API (2W1A scene).

These functions are carried out by the same sim.* functions the ZeroMQ API and the scenes'
Lua scripts use; each line prints the return code first (0: done; 8: the server could not, as
when the scene has no such object, or the emulation lacks that sim.* function).

Run: sitegen remote-api run examples/remote_api/scene_changes.py --scene 2w1a
"""

import sim

B = sim.simx_opmode_blocking
client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
_, body = sim.simxGetObjectHandle(client, "2W1A", B)
_, shoulder = sim.simxGetObjectHandle(client, "ShoulderMotor", B)

# A dummy to mark a place: made, placed above the robot, hung on its body, removed.
code, dummy = sim.simxCreateDummy(client, 0.05, None, B)
print("create dummy:", code, dummy > 0)
print("place dummy:", sim.simxSetObjectPosition(client, dummy, -1, [0.0, 0.0, 0.5], B))
print("hang it on the body:", sim.simxSetObjectParent(client, dummy, body, True, B))
print("remove dummy:", sim.simxRemoveObject(client, dummy, B))
code, copies = sim.simxCopyPasteObjects(client, [shoulder], B)
print("copy/paste:", code, len(copies))
print("remove model:", sim.simxRemoveModel(client, 999, B))
code, selection = sim.simxGetObjectSelection(client, B)
print("selection:", code)
print("select:", sim.simxSetObjectSelection(client, [body], B))

# Scenes and models come from files beside the scene; this one has none of these.
print("load scene:", sim.simxLoadScene(client, "no_such_scene.ttt", 0, B))
print("load model:", sim.simxLoadModel(client, "no_such_model.ttm", 0, B))
print("close scene:", sim.simxCloseScene(client, B))

# Collision and distance: objects of the scene (none in this one), and entity pairs.
print("collision object:", sim.simxGetCollisionHandle(client, "Collision", B))
print("distance object:", sim.simxGetDistanceHandle(client, "Distance", B))
print("collection:", sim.simxGetCollectionHandle(client, "Collection", B))
print("read collision:", sim.simxReadCollision(client, 999, B))
print("read distance:", sim.simxReadDistance(client, 999, B))
print("check collision:", sim.simxCheckCollision(client, body, shoulder, B)[0])
print("check distance:", sim.simxCheckDistance(client, body, shoulder, B)[0])

# Force and vision sensors (the 2W1A has neither).
print("force sensor:", sim.simxReadForceSensor(client, body, B)[0])
print("break force sensor:", sim.simxBreakForceSensor(client, body, B))
print("depth buffer:", sim.simxGetVisionSensorDepthBuffer(client, body, B)[0])
print("set image:", sim.simxSetVisionSensorImage(client, body, [0, 0, 0], 0, B))

# Parameters of objects, models and the scene; the 4.x names are the same functions.
print("object float:", sim.simxGetObjectFloatParameter(client, shoulder, 2012, B)[0])
print("object float (4.x):", sim.simxGetObjectFloatParam(client, shoulder, 2012, B)[0])
print("object int:", sim.simxGetObjectIntParameter(client, shoulder, 2000, B)[0])
print("object int (4.x):", sim.simxGetObjectInt32Param(client, shoulder, 2000, B)[0])
print("set object float:", sim.simxSetObjectFloatParameter(client, shoulder, 2012, 1.0, B))
print("set object float (4.x):", sim.simxSetObjectFloatParam(client, shoulder, 2012, 1.0, B))
print("set object int:", sim.simxSetObjectIntParameter(client, shoulder, 2000, 1, B))
print("set object int (4.x):", sim.simxSetObjectInt32Param(client, shoulder, 2000, 1, B))
print("model property:", sim.simxGetModelProperty(client, body, B)[0])
print("set model property:", sim.simxSetModelProperty(client, body, 0, B))
print("string parameter:", sim.simxGetStringParameter(client, 14, B)[0])
print("string parameter (4.x):", sim.simxGetStringParam(client, 14, B)[0])
step = sim.sim_floatparam_simulation_time_step
print("float parameter:", sim.simxGetFloatingParameter(client, step, B))
print("float parameter (4.x):", sim.simxGetFloatParam(client, step, B))
print("int parameter (4.x):", sim.simxGetInt32Param(client, sim.sim_intparam_program_version, B))
print("bool parameter (4.x):", sim.simxGetBoolParam(client, 25, B))
print("array parameter (4.x):", sim.simxGetArrayParam(client, sim.sim_arrayparam_gravity, B))
print("set float parameter:", sim.simxSetFloatingParameter(client, step, 0.05, B))
print("set float parameter (4.x):", sim.simxSetFloatParam(client, step, 0.05, B))
print("set int parameter:", sim.simxSetIntegerParameter(client, 26, 8, B))
print("set int parameter (4.x):", sim.simxSetInt32Param(client, 26, 8, B))
print("set bool parameter:", sim.simxSetBooleanParameter(client, 25, False, B))
print("set bool parameter (4.x):", sim.simxSetBoolParam(client, 25, False, B))
print("set array parameter:", sim.simxSetArrayParameter(client, 0, [0, 0, -9.81], B))
print("set array parameter (4.x):", sim.simxSetArrayParam(client, 0, [0, 0, -9.81], B))

# Integer signals under their 4.x names.
print("int signal (4.x):", sim.simxSetInt32Signal(client, "count", 3, B))
print("read it (4.x):", sim.simxGetInt32Signal(client, "count", B))
print("clear it (4.x):", sim.simxClearInt32Signal(client, "count", B))

# An auxiliary console: its text goes to stderr.
code, console = sim.simxAuxiliaryConsoleOpen(client, "log", 10, 0, None, None, None, None, B)
print("console:", code)
print("console print:", sim.simxAuxiliaryConsolePrint(client, console, "hello\n", B))
print("console show:", sim.simxAuxiliaryConsoleShow(client, console, True, B))
print("console close:", sim.simxAuxiliaryConsoleClose(client, console, B))

# simxQuery: a request signal, and the scene's scripts answer on another (none here: timeout).
code, reply = sim.simxQuery(client, "request", b"ping", "reply", 500)
print("query:", code, bytes(reply))
sim.simxFinish(client)
