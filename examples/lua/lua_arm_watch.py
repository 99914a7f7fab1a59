"""Watch data/scenes/lua_arm.simscene.xml move by its own Lua scripts (a clip of sitegen's site).

The client only starts the simulation, reads the arm scripts' pass counter (the integer signal
``armPasses``), slows the flag down through the float signal ``flagSpeed`` half way, and stops:
everything that moves is moved by the scene's child scripts (sims/lua).

    sitegen remote-api run examples/lua/lua_arm_watch.py --scene data/scenes/lua_arm.simscene.xml
"""

import time

import sim

client = sim.simxStart("127.0.0.1", 19997, True, True, 5000, 5)
if client == -1:
    raise SystemExit("could not connect")
sim.simxStartSimulation(client, sim.simx_opmode_blocking)
time.sleep(6)
code, passes = sim.simxGetIntegerSignal(client, "armPasses", sim.simx_opmode_blocking)
print(f"the arm's script ran its sensing section {passes} times")
sim.simxSetFloatSignal(client, "flagSpeed", 1.0, sim.simx_opmode_blocking)
time.sleep(6)
sim.simxStopSimulation(client, sim.simx_opmode_blocking)
sim.simxFinish(client)
print("done")
