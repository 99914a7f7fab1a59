"""cart-keyboard: a scripted arrow-key session with the course's keyboard child-script rules.

Rules (course keyboard script): wheel speeds change in steps of 0.5 rad/s and stay within
+-2 rad/s; up/down add/remove one step on both wheels, left/right move one step from one wheel
to the other (turn), space stops both. The key presses are a param: ``[[time_s, key], ...]``.
"""

from __future__ import annotations

from sims.recording import Recorder
from sims.scenarios import Scenario
from sims.world import World

MAX_SPEED, STEP = 2.0, 0.5
SESSION = [
    [0.5, "up"],
    [1.0, "up"],
    [1.5, "up"],
    [2.0, "up"],  # full speed ahead
    [7.0, "left"],
    [9.0, "right"],  # a left curve
    [12.0, "down"],
    [12.5, "down"],  # slow down
    [14.0, "right"],
    [14.5, "right"],
    [18.0, "left"],
    [18.5, "left"],  # a right curve
    [21.0, "space"],  # stop
    [22.0, "down"],
    [22.5, "down"],  # back up a little
    [25.0, "space"],
]


def apply_key(key: str, left: float, right: float) -> tuple[float, float]:
    """New (left, right) wheel speeds after one key press."""
    if key == "up":
        left, right = left + STEP, right + STEP
    elif key == "down":
        left, right = left - STEP, right - STEP
    elif key == "left":
        left, right = left - STEP, right + STEP
    elif key == "right":
        left, right = left + STEP, right - STEP
    elif key == "space":
        left, right = 0.0, 0.0
    else:
        raise ValueError(f"unknown key {key!r}")
    clamp = lambda v: max(-MAX_SPEED, min(MAX_SPEED, v))  # noqa: E731
    return clamp(left), clamp(right)


def run(world: World, params: dict, record: Recorder) -> None:
    left = right = 0.0
    for at, key in sorted(params["keys"], key=lambda k: k[0]):
        world.advance(max(0.0, at - world.time))
        left, right = apply_key(key, left, right)
        world.set_joint_target_velocity("left_m", left)
        world.set_joint_target_velocity("right_m", right)
        record.note(f"key {key}: left {left:+.1f} right {right:+.1f} rad/s", key=key)
    world.advance(max(0.0, params["seconds"] - world.time))


SCENARIO = Scenario(
    name="cart-keyboard",
    description="Cart driven by a scripted arrow-key session (steps of 0.5 rad/s, max 2 rad/s; "
    "up/down speed, left/right turn, space stops).",
    scene="cart",
    run=run,
    duration=lambda p: p["seconds"],
    seed=0,
    params={"keys": SESSION, "seconds": 27.0},
    joints=("left_m", "right_m"),
    joint_quantity="speed",
)
