"""``import vrep``: the V-REP name of ``sim`` (see sim.py)."""

from sim import *  # noqa: F401,F403
from sim import __all__, __getattr__  # noqa: F401
