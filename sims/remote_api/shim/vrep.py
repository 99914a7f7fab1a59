"""``import vrep``: V-REP's name for the same legacy remote API (see ``sim.py`` here)."""

from sims.remote_api.api import *  # noqa: F403
from sims.remote_api.api import __all__, __getattr__  # noqa: F401
