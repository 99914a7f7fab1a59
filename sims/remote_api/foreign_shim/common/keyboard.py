"""``import keyboard``: key presses played from the run's key file (``--keys``), on the
server's clock; nothing reads the real keyboard."""

import _sitegen_bridge as _bridge


def is_pressed(key):
    return bool(_bridge.request({"op": "keys", "key": str(key)}))
