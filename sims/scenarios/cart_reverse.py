"""cart-reverse: course task 2-2 (shared/seeds/scripts/task2-2_cart_velocity.py).

The script sets both wheel motors ``left_m`` and ``right_m`` to -1 rad/s and leaves them: the
cart backs up straight along its heading at 1 rad/s * 28 mm = 28 mm/s.
"""

from __future__ import annotations

from sims.recording import Recorder
from sims.scenarios import Scenario
from sims.world import World


def run(world: World, params: dict, record: Recorder) -> None:
    for motor in ("left_m", "right_m"):
        world.set_joint_target_velocity(motor, params["speed"])
    record.note(f"both wheels at {params['speed']} rad/s")
    world.advance(params["seconds"])


SCENARIO = Scenario(
    name="cart-reverse",
    description="Cart, course task 2-2: both wheel motors at -1 rad/s, the cart reverses straight.",
    scene="cart",
    run=run,
    duration=lambda p: p["seconds"],
    seed=0,
    params={"speed": -1.0, "seconds": 10.0},
    joints=("left_m", "right_m"),
    joint_quantity="speed",
)
