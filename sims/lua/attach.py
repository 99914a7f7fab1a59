"""A Simulator's World gets its scene's scripts: ``attach(simulator)``.

Called when the Simulator loads its World: a scene file with child or customization
scripts gets a :class:`ScriptHost` sharing the Simulator's signal store (a signal set by a
client is seen by the scripts and the other way round). A temporary server's simulation
runs from the start, so its scripts start at once and ``simRemoteApi.start(port)`` decides
which port a client may connect to; a continuous server's scripts start with the
simulation. Status messages and unemulated calls go to the Simulator's ``on_status`` and
``on_missing`` (set by the remote API session that owns it), so this imports nothing of
the remote API's session layer."""

from __future__ import annotations

from typing import Any

from .host import ScriptHost


def attach(simulator: Any) -> ScriptHost | None:
    """The scene's scripts for the Simulator's World, or None when it has none."""
    world = simulator.world
    source = getattr(world, "source", None)
    if not getattr(source, "scripts", ()):
        return None

    def status(message: str) -> None:
        simulator.statusbar.append(message)
        if simulator.on_status is not None:
            simulator.on_status(message)

    host = ScriptHost(world, signals=simulator.signals, pass_dt=simulator.pass_dt, status=status)
    if not host.scripts:
        host.close()
        return None
    simulator.lua = host
    simulator.reset_observers.append(lambda _s: host.stop())
    host.clock = simulator.clock.now  # sim.getSystemTime: the run's clock

    def stop_when_asked(sim: Any) -> None:  # a script's sim.stopSimulation, at the pass end
        if host.stop_requested and sim.can_control():
            sim.stop()

    simulator.pass_observers.append(stop_when_asked)
    if simulator.on_missing is not None:
        host.on_missing = simulator.on_missing
    if simulator.state == "running":
        host.start()
    return host
