"""Connections (clients), their reply buffers, and the session that holds them.

A ``Session`` is one configured run: the scene to load, the clock, the ``Simulator`` and the
connection slots. ``simxStart`` opens a slot (no socket: the address and port are only recorded).
The module-level current session is what the ``sim`` functions talk to.

Reply buffers follow the client library (extApi.c): a command is identified by its function and
its object arguments; each connection keeps the latest reply of each command; a blocking call's
reply is taken out of the buffer once returned; a stream keeps a command's reply current.
"""

from __future__ import annotations

import os
import sys
import threading
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

from .clock import Clock, WallClock
from .constants import MAX_CONNECTIONS
from .server import Simulator


@dataclass
class Reply:
    code: int
    values: tuple
    sim_time: float = 0.0


@dataclass
class Client:
    id: int
    address: str
    port: int
    connection_id: int
    options: dict[str, Any] = field(default_factory=dict)
    replies: dict[tuple, Reply] = field(default_factory=dict)
    streams: dict[tuple, Any] = field(default_factory=dict)  # key -> recompute callable
    paused: bool = False
    queued: list = field(default_factory=list)  # setters held while communication is paused
    last_cmd_time: float = 0.0
    calls: int = 0


@dataclass(frozen=True)
class Missing:
    """Something a script asked for that this run could not give: ``kind`` "object" (a name
    the scene lacks, with the nearest names in it) or "function" (a simx function the
    emulation does not implement); ``site`` is "file.py:line" in the script."""

    kind: str
    what: str
    site: str
    nearest: tuple[str, ...] = ()


#: Where calls of this thread come from when it serves a client over a socket (its label).
SERVING = threading.local()


def script_site() -> str:
    """``file:line`` of the innermost caller outside sitegen's own ``sims`` package (for a
    thread serving a client over a socket: that client's label)."""
    from .clock import LIBRARY_DIR

    label = getattr(SERVING, "label", None)
    if label:
        return label
    frame = sys._getframe(1)
    while frame is not None:
        name = frame.f_code.co_filename
        if not name.startswith(LIBRARY_DIR) and not name.startswith("<frozen"):
            return f"{os.path.basename(name)}:{frame.f_lineno}"
        frame = frame.f_back
    return "?"


def missing_report(missing: list) -> list[str]:
    """Lines naming each object the scene lacks and each function not implemented."""
    lines: list[str] = []
    objects = [m for m in missing if m.kind == "object"]
    functions = [m for m in missing if m.kind == "function"]
    if objects:
        lines.append("[remote-api] objects the script asked for that the scene lacks:")
        for m in objects:
            near = ", ".join(m.nearest) if m.nearest else "no similar name"
            lines.append(f"  {m.site}: {m.what!r} (nearest in the scene: {near})")
    if functions:
        lines.append("[remote-api] functions the emulation does not implement:")
        for m in functions:
            # ZeroMQ (sim.*) calls raise; legacy simx* calls return the flag
            legacy = not m.what.startswith("sim.")
            how = "returned simx_return_local_error_flag" if legacy else "raised an error"
            if legacy and "(needs sim." in m.what:  # carried out by the sim.* table
                how = "returned simx_return_remote_error_flag"
            if m.what.startswith("Lua "):  # a scene script's call (sims/lua): returned nothing
                how = "called by the scene's Lua script; returned nothing"
            lines.append(f"  {m.site}: {m.what} ({how})")
    return lines


@dataclass
class Connection:
    """A connection the script asked for: recorded, never contacted."""

    address: str
    port: int
    client_id: int


class Session:
    """One run: a scene, a clock, a simulator and up to 255 connection slots."""

    def __init__(
        self,
        scene: str | None,
        *,
        seed: int = 0,
        server: str | None = None,
        clock: Clock | None = None,
        timestep: float = 0.005,
        scene_options: dict[str, Any] | None = None,
        world_factory=None,
        stderr=None,
    ):
        self.scene = scene
        self.clock = clock or WallClock()
        self.simulator = (
            Simulator(
                scene,
                seed=seed,
                server=server,
                clock=self.clock,
                timestep=timestep,
                scene_options=scene_options,
                world_factory=world_factory,
            )
            if scene
            else None
        )
        if self.simulator is not None:
            self.simulator.reset_observers.append(self._after_reset)
            self.simulator.on_status = self.status
            self.simulator.on_missing = lambda m: self.note_missing(
                "function", f"Lua {m.function}", f"{m.scene}: script {m.script!r} line {m.line}"
            )
        self.clients: dict[int, Client] = {}
        self.connections: list[Connection] = []
        self._next_connection_id = 1
        self._warned: set[str] = set()
        self._stderr = stderr
        self.lock = threading.RLock()
        self.missing: list[Missing] = []  # in call order, one per (kind, what, site)
        self.found_objects = 0  # object look-ups by name or path that found something
        self.reset_hooks: list[Callable[[Session], None]] = []  # after a scene reset

    def _after_reset(self, _sim) -> None:
        for hook in list(self.reset_hooks):  # execute.py: re-run streaming setters
            hook(self)

    # --- messages ------------------------------------------------------------------------------
    def warn_once(self, key: str, message: str) -> None:
        if key in self._warned:
            return
        self._warned.add(key)
        stream = self._stderr or sys.stderr
        print(f"[sim] {message}", file=stream, flush=True)

    def note_missing(self, kind: str, what: str, site: str, nearest: tuple = ()) -> None:
        item = Missing(kind, what, site, tuple(nearest))
        if all((m.kind, m.what, m.site) != (kind, what, site) for m in self.missing):
            self.missing.append(item)

    def status(self, text: str) -> None:
        """A status bar message: CoppeliaSim shows it in its window; we print it to stderr."""
        stream = self._stderr or sys.stderr
        print(f"[sim status bar] {text}", file=stream, flush=True)

    # --- connections -------------------------------------------------------------------------
    def connect(self, address: str, port: int, **options: Any) -> int:
        with self.lock:
            if self.simulator is None:
                return -1
            for cid in range(MAX_CONNECTIONS):
                if cid not in self.clients:
                    break
            else:
                return -1
            self.simulator.choose_server(port)
            self.simulator.load()
            if self.simulator.refuses(port):  # no simRemoteApi.start(port) in the scene
                self.warn_once(
                    f"port:{port}",
                    f"no remote API server on port {port}: the "
                    f"scene's scripts started {self.simulator.lua.ports}",
                )
                return -1
            client = Client(cid, address, port, self._next_connection_id, dict(options))
            self._next_connection_id += 1
            self.clients[cid] = client
            self.connections.append(Connection(address, port, cid))
            return cid

    def finish(self, client_id: int) -> None:
        with self.lock:
            if client_id == -1:
                self.clients.clear()
            else:
                self.clients.pop(client_id, None)

    def client(self, client_id: Any) -> Client | None:
        try:
            return self.clients.get(int(client_id))
        except (TypeError, ValueError):
            return None

    def close(self) -> None:
        self.clients.clear()
        if self.simulator is not None:
            self.simulator.close()


_current: Session | None = None
_env_checked = False

#: Environment variable naming the scene when a script imports the shim outside the runner.
ENV_SCENE = "SITEGEN_REMOTE_API_SCENE"
ENV_SEED = "SITEGEN_REMOTE_API_SEED"
ENV_SERVER = "SITEGEN_REMOTE_API_SERVER"


def set_session(session: Session | None) -> Session | None:
    """Make ``session`` the current one; returns the previous."""
    global _current
    previous, _current = _current, session
    return previous


def current_session() -> Session | None:
    """The configured session; without one, a wall-clock session from the environment
    (``SITEGEN_REMOTE_API_SCENE``) if that is set."""
    global _current, _env_checked
    if _current is None and not _env_checked:
        _env_checked = True
        scene = os.environ.get(ENV_SCENE)
        if scene:
            seed = int(os.environ.get(ENV_SEED, "0") or 0)
            _current = Session(scene, seed=seed, server=os.environ.get(ENV_SERVER) or None)
    return _current


def configure(scene: str | None, **kwargs: Any) -> Session:
    """Start a new current session (closing the previous one) and return it."""
    previous = set_session(None)
    if previous is not None:
        previous.close()
    session = Session(scene, **kwargs)
    set_session(session)
    return session
