"""Objects, frames, signals and parameters through the legacy remote API (2W1A scene).

Run: sitegen remote-api run examples/remote_api/objects_and_signals.py --scene 2w1a
"""

import math

import sim

B = sim.simx_opmode_blocking
client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)

# The scene's objects and its tree: 2W1A > ShoulderMotor > ArmRespondable > ElbowMotor ...
code, everything = sim.simxGetObjects(client, sim.sim_handle_all, B)
print("objects:", code, len(everything))
_, body = sim.simxGetObjectHandle(client, "2W1A", B)
_, shoulder = sim.simxGetObjectHandle(client, "ShoulderMotor", B)
_, arm = sim.simxGetObjectHandle(client, "ArmRespondable", B)
code, parent = sim.simxGetObjectParent(client, arm, B)
print("parent of ArmRespondable is ShoulderMotor:", parent == shoulder)
code, parent = sim.simxGetObjectParent(client, body, B)
print("parent of 2W1A:", parent)
code, child = sim.simxGetObjectChild(client, shoulder, 0, B)
print("first child of ShoulderMotor is ArmRespondable:", child == arm)
code, child = sim.simxGetObjectChild(client, shoulder, 5, B)
print("no sixth child:", child)

# Frames: the body's z axis points along world +x (beta = 90 degrees).
code, euler = sim.simxGetObjectOrientation(client, body, -1, B)
print("body orientation (deg):", [round(math.degrees(a)) for a in euler])
code, quat = sim.simxGetObjectQuaternion(client, body, -1, B)
print("body quaternion:", [round(q, 3) for q in quat])
code, rel = sim.simxGetObjectPosition(client, shoulder, body, B)
print("shoulder in the body frame (mm):", [round(v * 1000) for v in rel])
code, rel = sim.simxGetObjectPosition(client, arm, sim.sim_handle_parent, B)
print("arm relative to its parent (mm):", [round(v * 1000) for v in rel])
code, rel = sim.simxGetObjectOrientation(client, body, body, B)
print("body relative to itself:", [round(a, 6) + 0.0 for a in rel])

# Moving the model: set the base's pose (a link of the chain cannot be moved on its own).
print("set position:", sim.simxSetObjectPosition(client, body, -1, [0.5, 0.2, 0.07], B))
print("set orientation:", sim.simxSetObjectOrientation(client, body, -1, [0, math.pi / 2, 0], B))
print("set quaternion:", sim.simxSetObjectQuaternion(client, body, -1, quat, B))
code, pos = sim.simxGetObjectPosition(client, body, -1, B)
print("body now at:", [round(v, 3) for v in pos])
print("move a link:", sim.simxSetObjectPosition(client, arm, -1, [0, 0, 0], B))
print("set joint position:", sim.simxSetJointPosition(client, shoulder, math.radians(100), B))
code, angle = sim.simxGetJointPosition(client, shoulder, B)
print("shoulder now (deg):", round(math.degrees(angle)))
code, max_torque = sim.simxGetJointMaxForce(client, shoulder, B)
print("shoulder max torque:", round(max_torque, 2))
code, torque = sim.simxJointGetForce(client, shoulder, B)
print("joint torque read:", code)
code, lin, ang = sim.simxGetObjectVelocity(client, body, B)
print("body at rest:", code, all(abs(v) < 1e-6 for v in lin + ang))

# Signals: named values shared with the simulator.
sim.simxSetFloatSignal(client, "gain", 0.25, B)
sim.simxSetIntegerSignal(client, "mode", 3, B)
sim.simxSetStringSignal(client, "name", "2W1A", B)
sim.simxAppendStringSignal(client, "name", "-robot", B)
print("float signal:", sim.simxGetFloatSignal(client, "gain", B))
print("integer signal:", sim.simxGetIntegerSignal(client, "mode", B))
print("string signal:", sim.simxGetStringSignal(client, "name", B))
print("get and clear:", sim.simxGetAndClearStringSignal(client, "name", B))
print("cleared:", sim.simxGetStringSignal(client, "name", B)[0])
sim.simxClearFloatSignal(client, "gain", B)
sim.simxClearIntegerSignal(client, "mode", B)
sim.simxClearStringSignal(client, "", B)
print("float cleared:", sim.simxGetFloatSignal(client, "gain", B)[0])
print("integer cleared:", sim.simxGetIntegerSignal(client, "mode", B)[0])
packed = sim.simxPackFloats([1.5, -2.0])
sim.simxWriteStringStream(client, "stream", packed, B)
sim.simxWriteStringStream(client, "stream", sim.simxPackInts([7]), B)
code, data = sim.simxReadStringStream(client, "stream", B)
print("stream:", sim.simxUnpackFloats(data[:8]), sim.simxUnpackInts(data[8:]))

# Parameters.
print("version:", sim.simxGetIntegerParameter(client, sim.sim_intparam_program_version, B))
print("real-time:", sim.simxGetBooleanParameter(client, sim.sim_boolparam_realtime_simulation, B))
code, gravity = sim.simxGetArrayParameter(client, sim.sim_arrayparam_gravity, B)
print("gravity z:", round(gravity[2], 2))
buffer = sim.simxCreateBuffer(8)
sim.simxReleaseBuffer(buffer)
sim.simxFinish(client)
