"""``import vrepConst``: the legacy remote API's constants, from the sitegen server."""

import _sitegen_bridge as _bridge

globals().update(_bridge.hello()["constants"])
