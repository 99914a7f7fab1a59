"""The ``sim.*`` functions a scene script calls, over the World the remote API uses.

Each function is registered (``api_core.api``) under its CoppeliaSim 4.x name
(``getObjectHandle``); the V-REP 3.x name (``simGetObjectHandle``) is derived (``OLD_NAMES``
lists the irregular ones). Functions get raw Lua values (bytes, numbers, tables) and return
Python values that ``LuaState.to_lua`` converts; a failure returns ``state.fail(message)`` so
that the error is raised at the script's line. Objects and joints go through
``sims.remote_api.commands`` (the remote API's own code), so a script and a remote client see
the same world. Importing this module registers every function (api_*.py).
"""

from __future__ import annotations

from . import api_data, api_devices, api_objects, api_simulation, api_ui  # noqa: F401 (register)
from .api_core import OLD_NAMES, REGISTRY, WORLD, Context, api, old_name

__all__ = ["OLD_NAMES", "REGISTRY", "WORLD", "Context", "api", "old_name"]
