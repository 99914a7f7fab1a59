"""What a remote API run gives back (``RunResult``, its ``Sample``s, the speed note of its
summary): its own module so that the runner and the foreign-interpreter runner (foreign.py),
which the runner calls, both import it without importing each other."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .client import Connection


@dataclass
class Sample:
    """The robot body at the end of one simulation pass."""

    clock: float  # script clock (s)
    sim_time: float  # simulation time of the current simulation (s)
    run: int  # 1 for the first simulation, 2 after the first restart...
    x: float
    y: float
    z: float
    heading: float  # rad


@dataclass
class RunResult:
    script: str
    scene: str
    exit_code: int
    message: str | None = None
    message_printed: bool = False  # sys.exit("text") printed its text already
    timed_out: bool = False
    sim_time: float = 0.0  # simulated seconds run, over all simulations
    wall_time: float = 0.0
    clock_time: float = 0.0  # the script's clock at the end (virtual or wall)
    connections: list[Connection] = field(default_factory=list)
    statusbar: list[str] = field(default_factory=list)
    samples: list[Sample] = field(default_factory=list)
    simulations: int = 0
    final_state: str = "stopped"  # the simulation's state when the run ended
    isolation: str = "in-process"  # how the run was fenced in (see isolate.py)
    missing: list[Any] = field(default_factory=list)  # client.Missing: names/functions lacking
    keys_ended: bool = False  # ended by the end of its key file (--keys), as planned
    probe: Any = None  # what ``probe(simulator)`` returned at the last pass (run_script)

    @property
    def ok(self) -> bool:
        return self.exit_code == 0

    def summary(self) -> str:
        addresses = ", ".join(sorted({f"{c.address}:{c.port}" for c in self.connections})) or "none"
        return (
            f"{self.script}: exit {self.exit_code}; simulated {self.sim_time:.2f} s in "
            f"{self.simulations} simulation(s); script clock {self.clock_time:.2f} s; wall "
            f"{self.wall_time:.2f} s{speed_note(self.sim_time, self.wall_time)}; "
            + (
                f"connections (served on loopback): {addresses}"
                if self.isolation.startswith("own Python")
                else f"connections asked for (recorded, not contacted): {addresses}"
            )
        ) + (f"; isolation: {self.isolation}" if self.isolation.endswith(" only") else "")


def speed_note(sim_time: float, wall_time: float) -> str:
    """`` (49x real time)``, `` (0.4x real time)``; nothing when no simulation ran or no time
    passed (a missing script, a script that never started its simulation)."""
    if sim_time <= 0 or wall_time <= 0:
        return ""
    speed = sim_time / wall_time
    digits = 0 if speed >= 10 else 1 if speed >= 0.1 else 3
    return f" ({speed:.{digits}f}x real time)"


def sample_of(sim: Any) -> Sample:
    """The robot body of the simulator's world now."""
    world = sim.world
    robot = world.model.robot
    (x, y, z), _ = world.object_pose(robot)
    return Sample(sim.clock.now(), world.time, sim.starts, x, y, z, world.heading(robot))
