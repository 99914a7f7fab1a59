"""``import keyboard``: key presses played from ``--keys FILE`` (see sims/lua/keys.py).

Only ``is_pressed`` is provided (what the course's scripts use); nothing reads the real keyboard.
"""

from sims.lua.keys import is_pressed  # noqa: F401
