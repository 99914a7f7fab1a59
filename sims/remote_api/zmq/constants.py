"""The ``sim.*`` constants a ZeroMQ remote API client sees (``sim.handle_world``, ...).

The ZeroMQ API names CoppeliaSim's constants without the legacy ``sim_`` prefix and with the same
values: the one table of names Lua scripts see too (``sims.simapi.constants.named``).
"""

from __future__ import annotations

from sims.simapi.constants import named

CONSTANTS: dict[str, int | float | str] = named()

#: Values of getSimulationState.
SIMULATION_STOPPED = CONSTANTS["simulation_stopped"]
SIMULATION_PAUSED = CONSTANTS["simulation_paused"]
SIMULATION_RUNNING = CONSTANTS["simulation_advancing_running"]
HANDLE_WORLD = -1
HANDLE_ALL = CONSTANTS["handle_all"]
HANDLE_PARENT = CONSTANTS["handle_parent"]
HANDLE_SCENE = CONSTANTS["handle_scene"]
