"""Return codes of the legacy remote API: what a script sees when something is wrong.

Run: sitegen remote-api run examples/remote_api/error_codes.py --scene 2w1a
"""

import sim

# Before simxStart: the initialize error flag (64).
print("before simxStart:", sim.simxGetObjectHandle(0, "2W1A", sim.simx_opmode_blocking))

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
second = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
print("client ids:", client, second)
sim.simxFinish(second)

# An unknown object name: remote error (8) and handle 0.
print("unknown name:", sim.simxGetObjectHandle(client, "NoSuchObject", sim.simx_opmode_blocking))
# "name#" and "name#0" mean the first instance, as in CoppeliaSim.
print("name with #0:", sim.simxGetObjectHandle(client, "2W1A#0", sim.simx_opmode_blocking)[0])

# An invalid handle: remote error and zeroed outputs.
print("invalid handle:", sim.simxGetObjectPosition(client, 9999, -1, sim.simx_opmode_blocking))
_, body = sim.simxGetObjectHandle(client, "2W1A", sim.simx_opmode_blocking)
# A joint function on an object that is not a joint: remote error.
print("not a joint:", sim.simxGetJointPosition(client, body, sim.simx_opmode_blocking))
print(
    "set on not a joint:",
    sim.simxSetJointTargetVelocity(client, body, 1.0, sim.simx_opmode_blocking),
)

# With oneshot, the error arrives with the reply: novalue first, then the error.
print("oneshot error 1:", sim.simxGetObjectPosition(client, 9999, -1, sim.simx_opmode_oneshot)[0])
print("oneshot error 2:", sim.simxGetObjectPosition(client, 9999, -1, sim.simx_opmode_oneshot)[0])

# An operation mode that does not exist: illegal opmode flag (4).
print("illegal opmode:", sim.simxGetObjectPosition(client, body, -1, 0x090000)[0])

# A closed or never-opened client id: initialize error flag.
print("bad client id:", sim.simxGetJointPosition(42, body, sim.simx_opmode_blocking)[0])

# A function this emulation does not provide: local error flag (32), outputs shaped as usual.
print(
    "unsupported:",
    sim.simxDisplayDialog(client, "t", "m", 0, "", None, None, sim.simx_opmode_blocking),
)
# A name the legacy API never had: also the local error flag, never an AttributeError.
print("unknown function:", sim.simxTeleportRobot(client, body))

# A missing signal is a remote error; server-side errors are listed by simxGetLastErrors.
print("missing signal:", sim.simxGetFloatSignal(client, "nothing", sim.simx_opmode_blocking))
code, errors = sim.simxGetLastErrors(client, sim.simx_opmode_blocking)
print("last errors:", code, len(errors), errors[0])

# Return codes are bit flags: test bits, not equality.
code = sim.simxGetObjectPosition(client, 9999, -1, sim.simx_opmode_blocking)[0]
print("remote error bit set:", bool(code & sim.simx_return_remote_error_flag))
sim.simxFinish(-1)
