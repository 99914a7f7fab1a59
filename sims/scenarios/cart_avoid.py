"""cart-avoid: the cart roams the arena and steers clear of walls and obstacles.

A reactive controller reads the front proximity sensor (a 7-ray fan, 0.5 m range) 20 times a
second. Clear ahead: cruise, easing away from whichever side sees something nearer. Something
closer than ``stop_distance``: turn on the spot towards the freer side until the whole fan sees
more than ``clear_distance``. Turning on the spot keeps the footprint inside a 0.13 m circle, so
stopping 0.25 m short of anything leaves room to turn.
"""

from __future__ import annotations

from sims.recording import Recorder
from sims.scenarios import Scenario
from sims.world import World

SENSOR = "Proximity_sensor"


def run(world: World, params: dict, record: Recorder) -> None:
    reach = params["sensor_range"]
    cruise, turn = params["cruise"], params["turn"]
    turning = 0  # +1 = turning left, -1 = right, 0 = driving
    while True:
        scan = [reach if d is None else d for d in world.proximity_scan(SENSOR)]
        nearest = min(scan)
        half = len(scan) // 2
        left_room, right_room = sum(scan[:half]), sum(scan[-half:])
        if turning and nearest > params["clear_distance"]:
            turning = 0
            record.note("clear ahead")
        elif not turning and nearest < params["stop_distance"]:
            turning = 1 if left_room >= right_room else -1
            record.note(
                f"obstacle at {nearest:.2f} m: turning {'left' if turning > 0 else 'right'}"
            )
        if turning:
            left, right = -turn * turning, turn * turning
        else:
            ease = params["steer"] * (right_room - left_room) / (half * reach)
            left, right = cruise * (1 - ease), cruise * (1 + ease)
        world.set_joint_target_velocity("left_m", left)
        world.set_joint_target_velocity("right_m", right)
        record.set("proximity_m", None if nearest >= reach else nearest)
        world.advance(params["control_period"])


SCENARIO = Scenario(
    name="cart-avoid",
    description="Cart roaming a walled arena with obstacles, steering by its front proximity "
    "sensor; it never touches anything.",
    scene="cart",
    run=run,
    duration=lambda p: p["seconds"],
    seed=7,
    params={
        "cruise": 6.0,
        "turn": 3.0,
        "steer": 0.6,
        "stop_distance": 0.25,
        "clear_distance": 0.4,
        "sensor_range": 0.5,
        "control_period": 0.05,
        "seconds": 40.0,
    },
    joints=("left_m", "right_m"),
    joint_quantity="speed",
    extra_columns=("proximity_m",),
)
