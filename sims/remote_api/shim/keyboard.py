"""``import keyboard``: key presses played from ``--keys FILE`` (see sims/lua/keys.py).

Only ``is_pressed`` is provided (what the course's scripts use); nothing reads the real keyboard.
"""

from sims.lua.keys import POLL_COST, pressed_at
from sims.remote_api.client import current_session


def is_pressed(key: object) -> bool:
    """True while a scripted event holds ``key``; each poll costs ``POLL_COST`` virtual seconds
    (a polling loop lets the simulation run)."""
    session = current_session()
    clock = session.clock if session is not None else None
    if clock is not None:
        clock.advance(POLL_COST)
    return pressed_at(key, clock.now() if clock is not None else 0.0)
