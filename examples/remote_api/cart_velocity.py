"""The cart driven by wheel velocities alone: forward, a turn on the spot, then backwards.

The same kind of exercise as the course's stage 3 task 2-2 (set both wheel motors' target
velocities and watch the cart move). Written for this project (not course code). The cart
scene's server is temporary (the scene's child script starts it), so the simulation already
runs when the script connects and keeps running after it ends.

Run: sitegen remote-api run examples/remote_api/cart_velocity.py --scene cart --after 1
"""

import time

import sim

SPEED = 1.5  # rad/s on each wheel

client = sim.simxStart("127.0.0.1", 19999, True, True, 5000, 5)
if client == -1:
    raise SystemExit("could not connect to the cart scene's server on port 19999")

wait = sim.simx_opmode_oneshot_wait
_, left = sim.simxGetObjectHandle(client, "left_m", wait)
code, right = sim.simxGetObjectHandle(client, "right_m", wait)
if code != sim.simx_return_ok:
    raise SystemExit("the scene has no left_m/right_m wheel motors")
_, cart = sim.simxGetObjectHandle(client, "cart", wait)


def drive(left_speed: float, right_speed: float, seconds: float, what: str) -> None:
    sim.simxPauseCommunication(client, True)  # both wheels change in the same pass
    sim.simxSetJointTargetVelocity(client, left, left_speed, sim.simx_opmode_oneshot)
    sim.simxSetJointTargetVelocity(client, right, right_speed, sim.simx_opmode_oneshot)
    sim.simxPauseCommunication(client, False)
    time.sleep(seconds)
    _, (x, y, _z) = sim.simxGetObjectPosition(client, cart, -1, wait)
    print(f"{what}: cart at x={x:.3f} y={y:.3f} m")


drive(SPEED, SPEED, 3.0, "forward")
drive(SPEED, -SPEED, 2.0, "turn")
drive(-SPEED, -SPEED, 3.0, "backwards")
drive(0.0, 0.0, 0.5, "stopped")
sim.simxFinish(client)
