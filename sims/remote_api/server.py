"""The simulator side: one scene, its simulation state and time, as CoppeliaSim keeps them.

``Simulator`` owns the ``World`` (loaded when the first client connects) and lets the world's
time follow the run's clock: while the simulation runs (and is not in synchronous mode), every
``pass_dt`` of clock time is one simulation pass of ``pass_dt`` simulated seconds (CoppeliaSim's
simulation step, 50 ms), made of ``pass_dt / timestep`` physics steps.

Server kinds (CoppeliaSim's remoteApiServerSide):
- ``continuous``: started with the simulator; serves while the simulation is stopped; the only
  kind that starts, pauses and stops simulations. The simulation starts stopped.
- ``temporary``: started by a child script (``simRemoteApi.start(19999)``), so it exists only while
  a simulation runs: the simulation is already running when the client connects, and requests to
  start, pause or stop it are refused (remote error).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import sims.quiet  # noqa: F401  (pybullet's banner silenced before anything imports it)
from sims.lua.attach import attach

from .clock import Clock, WallClock

STOPPED, RUNNING, PAUSED = "stopped", "running", "paused"
CONTINUOUS, TEMPORARY = "continuous", "temporary"
SERVER_KINDS = (CONTINUOUS, TEMPORARY)

#: Default server kind per scene: the 2W1A example uses the continuous server on port 19997;
#: the course's cart scene starts a temporary server from its child script (port 19999).
DEFAULT_SERVER = {"2w1a": CONTINUOUS, "cart": TEMPORARY}

#: Clock seconds one non-blocking API call takes (the client's communication cycle is ~5 ms;
#: a small cost keeps busy-wait loops of buffer reads moving).
CALL_COST = 0.001


#: Passes a served (wall-clock) simulation may owe at most (see ``Simulator.sync``).
MAX_BACKLOG = 4

#: The port CoppeliaSim's continuous server listens on (remoteApiConnections.txt).
CONTINUOUS_PORT = 19997


def default_server(scene: str) -> str:
    return DEFAULT_SERVER.get(scene, CONTINUOUS)


def server_for_port(port: int) -> str:
    """A scene file's server kind, from the port the script connects to: 19997 is the
    continuous server; any other port is one a child script started (temporary)."""
    return CONTINUOUS if port == CONTINUOUS_PORT else TEMPORARY


def default_world_factory(scene: str, seed: int, timestep: float, options: dict[str, Any]):
    from sims.world import World

    return World(scene, seed=seed, timestep=timestep, **options)


class Simulator:
    """A CoppeliaSim instance with one scene loaded (lazily: ``load()``)."""

    def __init__(
        self,
        scene: str,
        *,
        seed: int = 0,
        server: str | None = None,
        clock: Clock | None = None,
        timestep: float = 0.005,
        pass_dt: float = 0.05,
        scene_options: dict[str, Any] | None = None,
        world_factory: Callable[..., Any] | None = None,
    ):
        #: a scene file without a configured server kind: decided by the first connection's port
        self.server_auto = server is None and scene not in DEFAULT_SERVER
        server = server or default_server(scene)
        if server not in SERVER_KINDS:
            raise ValueError(f"server must be one of {', '.join(SERVER_KINDS)}, not {server!r}")
        self.scene = scene
        self.seed = seed
        self.server = server
        self.clock = clock or WallClock()
        self.clock.listener = self.sync
        self.timestep = timestep
        self.pass_dt = pass_dt
        self.scene_options = dict(scene_options or {})
        self._factory = world_factory or default_world_factory
        self.world: Any = None
        self.state = STOPPED
        self.synchronous = False
        self.steps_per_pass = 1
        self._debt = 0.0
        self._synced_at = 0.0
        self.passes = 0  # simulation passes run, over all simulations
        self.starts = 0  # simulations started (a temporary server's counts as one)
        self.pass_observers: list[Callable[[Simulator], None]] = []
        self.reset_observers: list[Callable[[Simulator], None]] = []
        self.statusbar: list[str] = []
        self.errors: list[str] = []  # server-side errors, for simxGetLastErrors
        self.signals: dict[str, dict[str, Any]] = {"float": {}, "int": {}, "string": {}}
        self.last_reply_time = 0.0
        self.lua: Any = None  # sims.lua.ScriptHost running the scene's scripts, if it has any
        self.on_status: Callable[[str], None] | None = None  # set by the owning Session
        self.on_missing: Callable[[Any], None] | None = None  # an Unemulated Lua call
        #: served to clients over sockets (``sitegen remote-api serve``): time is the wall
        #: clock's, so a call costs no clock time and a blocking call does not wait for a pass
        self.served = False

    # --- scene -------------------------------------------------------------------------------
    def choose_server(self, port: int) -> None:
        """Before the scene loads: a scene file's server kind follows the port (see
        ``server_for_port``); a configured kind or a bundled scene's default stays."""
        if self.server_auto and self.world is None:
            self.server = server_for_port(port)
            self.server_auto = False

    def load(self) -> Any:
        if self.world is None:
            self.world = self._factory(self.scene, self.seed, self.timestep, self.scene_options)
            dt = float(getattr(self.world, "timestep", self.timestep) or self.timestep)
            self.steps_per_pass = max(1, round(self.pass_dt / dt))
            self._synced_at = self.clock.now()
            self._debt = 0.0
            if self.server == TEMPORARY:
                self.state = RUNNING
                self.starts += 1
            self.lua = attach(self)  # the scene's own Lua scripts (issue 14)
        return self.world

    def refuses(self, port: int) -> bool:
        """A temporary server exists only on the ports the scene's scripts started."""
        host = self.lua
        return (
            host is not None
            and self.server == "temporary"
            and bool(host.ports)
            and port not in host.ports
        )

    def close(self) -> None:
        if self.world is not None:
            self.world.close()
            self.world = None

    @property
    def sim_time(self) -> float:
        return float(self.world.time) if self.world is not None else 0.0

    # --- time --------------------------------------------------------------------------------
    def sync(self, most: int | None = None) -> None:
        """Catch the world up with the clock (the clock's listener); at most ``most`` passes
        (None: all it owes). A served simulation never owes more than ``MAX_BACKLOG`` passes:
        on a machine too slow to keep pace it runs slower than the wall clock, as CoppeliaSim
        does, instead of holding its clients back to catch up."""
        now = self.clock.now()
        elapsed, self._synced_at = now - self._synced_at, now
        if self.world is None or self.state != RUNNING or self.synchronous:
            self._debt = 0.0
            return
        self._debt += max(0.0, elapsed)
        if self.served:
            self._debt = min(self._debt, MAX_BACKLOG * self.pass_dt)
        done = 0
        while self._debt >= self.pass_dt - 1e-9 and (most is None or done < most):
            self._debt -= self.pass_dt
            self._pass()
            done += 1

    def _pass(self) -> None:
        self.world.step(self.steps_per_pass)
        self.passes += 1
        for fn in list(self.pass_observers):
            fn(self)

    def call(self, blocking: bool) -> float:
        """Account for one API call; returns the clock seconds it took (its ping time).

        A blocking call while the simulation runs waits for the reply, which the server sends
        at its next simulation pass.
        """
        if self.served:
            self.last_reply_time = self.sim_time
            return 0.0
        start = self.clock.now()
        if blocking and self.world is not None and self.state == RUNNING and not self.synchronous:
            wait = self.pass_dt - self._debt
            self.clock.advance(wait if wait > 1e-9 else self.pass_dt)
        else:
            self.clock.advance(CALL_COST)
        self.last_reply_time = self.sim_time
        return self.clock.now() - start

    def trigger(self) -> None:
        """One synchronous step (simxSynchronousTrigger)."""
        if self.world is not None and self.state == RUNNING:
            self._pass()

    # --- simulation state ----------------------------------------------------------------------
    def can_control(self) -> bool:
        return self.server == CONTINUOUS

    def start(self) -> None:
        if self.state == RUNNING:
            return
        if self.state == STOPPED:
            self.starts += 1
        self.sync()
        self.state = RUNNING
        self._synced_at = self.clock.now()
        self._debt = 0.0

    def pause(self) -> None:
        if self.state == RUNNING:
            self.sync()
            self.state = PAUSED

    def stop(self) -> None:
        """Stop and restore the scene as loaded (CoppeliaSim restores the initial state)."""
        if self.state == STOPPED:
            return
        self.sync()
        self.state = STOPPED
        self.world.reset()
        self._debt = 0.0
        for fn in list(self.reset_observers):
            fn(self)

    def state_code(self) -> int:
        return {STOPPED: 0x00, PAUSED: 0x08, RUNNING: 0x11}[self.state]
