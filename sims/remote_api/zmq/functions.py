"""The ZeroMQ edge of the one ``sim.*`` table (``sims.simapi.table``), and the servers.

CoppeliaSim's ZeroMQ remote API is its Lua ``sim.*`` API; so is this one: every function a
client calls is the table's, called with a ``ZmqCaller`` (no script object; errors raised, as
the client expects; stepping per client as CoppeliaSim's add-on keeps it). Arguments arrive as
CBOR would carry them (``server.plain``), results go back as they are (a tuple is several
results). A blocking function (``sim.moveToConfig``, ``sim.wait``...) steps the simulation once
per pass for its client (``ZmqCaller.next_pass``). A :class:`ZmqServer` is handed the adapted
table when it is made (:func:`server_for`), so the server module imports no function.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from typing import Any

from sims.simapi.context import Caller, SimError
from sims.simapi.table import BLOCKING, FUNCTIONS

from ..client import Session
from ..server import RUNNING
from .registry import NOT_EMULATED
from .server import ZmqServer

__all__ = ["FUNCTIONS", "NOT_EMULATED", "ZmqCaller", "load", "server_for"]

#: results a ZeroMQ client receives as text, not as a buffer
TEXT_RESULTS = frozenset(("sim.getStringSignal",))


class ZmqCaller(Caller):
    """A ZeroMQ client as the caller of ``sim.*`` functions (one per server)."""

    threaded = True  # a client may wait (blocking functions step the simulation for it)

    def __init__(self, srv: ZmqServer):
        self.srv = srv

    @property
    def world(self) -> Any:
        return self.srv.world

    @property
    def signals(self) -> dict[str, dict[str, Any]]:
        return self.srv.simulator.signals

    @property
    def time(self) -> float:
        return float(self.srv.simulator.sim_time)

    @property
    def pass_dt(self) -> float:
        return float(self.srv.simulator.pass_dt)

    def state_code(self) -> int:
        return int(self.srv.simulator.state_code())

    def start_simulation(self) -> int:
        sim = self.srv.simulator
        sim.load()
        if sim.state == RUNNING:
            return 0
        sim.start()
        return 1

    def pause_simulation(self) -> int:
        sim = self.srv.simulator
        if sim.state != RUNNING:
            return 0
        sim.pause()
        return 1

    def stop_simulation(self) -> int:
        """Back to the initial state, every client's stepping level to 0 (the add-on's rule)."""
        srv, sim = self.srv, self.srv.simulator
        for uuid in srv.stepping:
            srv.stepping[uuid] = 0
        srv.apply_stepping()
        if sim.state == "stopped":
            return 0
        sim.stop()
        srv.targets.clear()
        return 1

    def system_time(self) -> float:
        return float(self.srv.session.clock.now())

    def replace_scene(self, path: str) -> None:
        """sim.loadScene: the session's scene becomes ``path`` (loaded at once)."""
        sim = self.srv.simulator
        sim.close()
        sim.scene = path
        sim.load()
        self.srv._tree_cache = None

    def status(self, message: str) -> None:
        self.srv.simulator.statusbar.append(message)
        self.srv.session.status(message)

    @property
    def lua(self) -> Any:
        return getattr(self.srv.simulator, "lua", None)

    def set_stepping(self, enable: bool) -> int:
        srv = self.srv
        previous = srv.stepping.get(srv.client_uuid, 0)
        srv.stepping[srv.client_uuid] = previous + 1 if enable else max(0, previous - 1)
        srv.apply_stepping()
        return previous

    def get_stepping(self) -> bool:
        return self.srv.stepping.get(self.srv.client_uuid, 0) > 0

    def next_pass(self) -> None:
        """One simulation pass for this client: in stepping mode the step it triggers, else
        the wait for the next pass. A stopped or paused simulation does not move."""
        srv = self.srv
        step = getattr(srv, "step", None)
        if step is not None:  # multi-client stepping (zmq/server.py)
            step(srv.client_uuid)
            return
        sim = srv.simulator
        if sim.world is None or sim.state != RUNNING:
            sim.call(blocking=False)
        elif srv.stepping.get(srv.client_uuid, 0) > 0 and sim.synchronous:
            sim.trigger()
            sim.call(blocking=False)
        else:
            sim.call(blocking=True)


def caller_for(srv: ZmqServer) -> ZmqCaller:
    c = getattr(srv, "caller", None)
    if c is None:
        c = srv.caller = ZmqCaller(srv)  # type: ignore[attr-defined]
    return c


def adapt(name: str, fn: Callable[..., Any]) -> Callable[..., Any]:
    """The table's ``fn`` as the server calls it: ``impl(server, *args)``."""
    blocking = name in BLOCKING
    text = name in TEXT_RESULTS

    def impl(srv: ZmqServer, *args: Any) -> Any:
        c = caller_for(srv)
        try:
            out = fn(c, *args)
            if blocking:
                gen = out
                try:
                    while True:
                        next(gen)
                        c.next_pass()
                except StopIteration as stop:
                    out = stop.value
        except SimError as exc:
            srv.fail(exc.kind, str(exc), name, exc.missing, exc.nearest)
        except (ValueError, KeyError, IndexError) as exc:
            srv.fail("argument", str(exc).strip("'\""), name)
        if text and isinstance(out, bytes):
            try:
                return out.decode("utf-8")
            except UnicodeDecodeError:
                return out
        return out

    impl.__signature__ = inspect.signature(fn)  # type: ignore[attr-defined]
    impl.__name__ = fn.__name__
    return impl


ADAPTED: dict[str, Callable[..., Any]] = {
    n: adapt(n, f) for n, f in FUNCTIONS.items() if n.startswith(("sim.", "simIK."))
}


def load() -> dict[str, Callable[..., Any]]:
    """Every emulated function by its ``sim.*`` name, as the server calls them."""
    return ADAPTED


def server_for(session: Session) -> ZmqServer:
    """The session's ZeroMQ server (created on first use)."""
    server = getattr(session, "zmq_server", None)
    if server is None:
        server = ZmqServer(session, ADAPTED)
        session.zmq_server = server  # type: ignore[attr-defined]
    return server
