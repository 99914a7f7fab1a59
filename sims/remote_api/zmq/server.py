"""The ZeroMQ remote API server side, in process: requests in the protocol's shape, answered on
the run's emulated World.

CoppeliaSim's ZeroMQ add-on takes a request ``{"func": "sim.getObject", "args": [...]}`` and
answers ``{"ret": [...]}`` or ``{"err": "message"}`` (``PROTOCOL.md`` of
CoppeliaRobotics/zmqRemoteApi). ``ZmqServer.handle`` does exactly that, without the CBOR and
ZeroMQ transport: the in-process client (``client.py``) calls it directly, so a script's calls
reach the same ``Simulator`` (virtual clock, simulation state, signals) the legacy API uses.

Why requests and not direct method calls: the protocol's shape fixes what a script can observe
(arguments made plain as CBOR would make them, one list of return values, errors as text) and
would let a CBOR/ZeroMQ transport be put in front of it unchanged.

Functions the emulation lacks, unknown object paths and invalid handles are errors, as in
CoppeliaSim (the client raises them); each is also noted once on stderr with the script line
that caused it; unknown objects and missing functions also go to ``Session.missing``, which the
run's summary lists with the nearest names in the scene.
"""

from __future__ import annotations

import functools
import inspect
import numbers
import threading
from typing import Any, NoReturn

from sims.simapi.ik import CONSTANTS as IK_CONSTANTS

from ..client import Session, script_site
from . import paths
from .constants import CONSTANTS
from .registry import NOT_EMULATED

#: The modules a client may ``require``: their constants (functions: the table's, by prefix).
MODULES: dict[str, dict[str, Any]] = {"sim": CONSTANTS, "simIK": IK_CONSTANTS}

#: Functions that look an object up by name or path (a success counts in Session.found_objects).
LOOKUPS = frozenset({"sim.getObject", "sim.getObjectHandle"})


WAIT_SLICE = 0.05  # s: a client waiting for a pass looks again at least this often

#: Set in the ZeroMQ wire server's own thread while it answers a request inline: a ``sim.step``
#: that would have to wait raises ``Park`` instead (zmq/wire.py answers it once the pass is done).
INLINE = threading.local()


class Park(Exception):
    """``sim.step`` must wait for pass ``target``: the wire holds the reply until then."""

    def __init__(self, uuid: str, target: int):
        super().__init__(f"{uuid} waits for pass {target}")
        self.uuid, self.target = uuid, target


class ZmqError(Exception):
    """A request failed on the server side: the reply carries ``err``."""


def plain(value: Any) -> Any:
    """An argument as CBOR would carry it: tuples and numpy arrays become lists, numpy
    scalars Python numbers."""
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if isinstance(value, dict):
        return {k: plain(v) for k, v in value.items()}
    if hasattr(value, "tolist") and not isinstance(value, (bytes, bytearray, str)):
        return plain(value.tolist())
    return value


class ZmqServer:
    """One ZeroMQ remote API server for one ``Session`` (all its clients)."""

    def __init__(self, session: Session, functions: dict[str, Any]):
        self.session = session
        self.functions = functions  # "sim.name" -> implementation (zmq/functions.py)
        self.stepping: dict[str, int] = {}  # stepping level per client uuid
        self.params: dict[int, Any] = {}  # sim.setInt32Param and friends
        self.targets: dict[int, tuple[str, float]] = {}  # last joint target per handle
        self.client_uuid = ""  # the client whose request is being handled
        self._tree_cache: tuple[Any, tuple, paths.Tree] | None = None
        self.desired: dict[str, int] = {}  # per stepping client: the pass it asked for
        self.closing = False  # the wire server is shutting down: nobody waits for a pass
        #: signalled after every simulation pass and scene reset (waiting clients look again)
        self.cond = threading.Condition(session.lock)
        if session.simulator is not None:
            session.simulator.pass_observers.append(self._wake)
            session.simulator.reset_observers.append(self._wake)

    # --- the World ------------------------------------------------------------------------
    @property
    def simulator(self):
        return self.session.simulator

    @property
    def world(self):
        return self.session.simulator.load()

    def tree(self) -> paths.Tree:
        """The World's object tree (``World.tree()``), indexed; rebuilt when the World is."""
        world = self.world
        key = tuple(world.names())
        cached = self._tree_cache
        if cached is not None and cached[0] is world and cached[1] == key:
            return cached[2]
        tree = paths.Tree(world.tree())
        self._tree_cache = (world, key, tree)
        return tree

    def entry(self, handle: Any, func: str) -> Any:
        h = self.handle_arg(handle, func, 1)
        found = self.tree().by_handle.get(h)
        if found is None:
            self.fail("handle", f"object handle {h} does not exist", func)
        return found

    # --- errors -----------------------------------------------------------------------------
    def note(self, kind: str, what: str, missing: str = "", nearest: tuple = ()) -> None:
        """Say once on stderr what went wrong, with the script line; an unknown object or a
        function the emulation lacks also goes to the run's summary (``Session.missing``)."""
        site = script_site()
        self.session.warn_once(f"zmq:{kind}:{what}:{site}", f"{site}: {what}")
        if kind == "path":
            self.session.note_missing("object", missing or what, site, nearest)
        elif kind == "function":
            self.session.note_missing("function", missing or what, site)

    def fail(self, kind: str, what: str, func: str, missing: str = "", nearest=()) -> NoReturn:
        """Raise the error CoppeliaSim would send for ``func``, noting it first."""
        message = f"{what}. (in function '{func}')"
        self.note(kind, message, missing, tuple(nearest))
        raise ZmqError(message)

    # --- arguments --------------------------------------------------------------------------
    def handle_arg(self, value: Any, func: str, position: int) -> int:
        if isinstance(value, numbers.Integral) and not isinstance(value, bool):
            return int(value)
        if isinstance(value, float) and value.is_integer():
            return int(value)
        self.fail("argument", f"argument {position}: object handle expected, got {value!r}", func)

    # --- stepping ---------------------------------------------------------------------------
    # CoppeliaSim's ZeroMQ add-on: while any client steps, a simulation pass happens once every
    # stepping client has asked for it (``sim.step``), and ``sim.step`` returns once that pass
    # is done; a client that does not step waits in ``sim.step`` for the next pass. Clients in
    # other threads (in process) or behind the wire server (one thread each) wait on ``cond``.
    def apply_stepping(self) -> None:
        sim = self.simulator
        stepped = any(level > 0 for level in self.stepping.values())
        if stepped != sim.synchronous:
            sim.sync()
            sim.synchronous = stepped
        self.advance()  # a client that stopped stepping may have held the others

    def _wake(self, _sim: Any = None) -> None:
        with self.cond:
            self.cond.notify_all()

    def advance(self) -> None:
        """Run the pass the stepping clients asked for, once all of them have."""
        sim = self.simulator
        if not sim.synchronous or sim.world is None or sim.state != "running":
            return
        steppers = [uuid for uuid, level in self.stepping.items() if level > 0]
        if steppers and all(self.desired.get(u, -1) > sim.passes for u in steppers):
            sim.trigger()

    def step(self, uuid: str | None = None) -> None:
        """``sim.step()`` for ``uuid`` (default: the client whose request this is; see above);
        a blocking function that steps inside (``sim.moveToConfig``) calls it once per pass."""
        uuid = self.client_uuid if uuid is None else uuid
        sim = self.simulator
        if sim.world is None or sim.state != "running":
            sim.call(blocking=False)
            return
        target = sim.passes + 1
        if self.stepping.get(uuid, 0) > 0 and sim.synchronous:
            self.desired[uuid] = target
            self.advance()
        elif not sim.served:
            sim.call(blocking=True)  # in process: the run's clock moves on to the next pass
            return
        if sim.passes < target and getattr(INLINE, "on", False):
            raise Park(uuid, target)  # the wire's own thread never waits: it parks the reply
        with self.cond:
            while (
                sim.passes < target
                and sim.state == "running"
                and sim.world is not None
                and not self.closing
            ):
                self.cond.wait(WAIT_SLICE)  # in slices: the script's watchdog can still stop it
            self.client_uuid = uuid

    def end_client(self, uuid: str) -> None:
        """A client left (``_*end*_``, its connection closed): it no longer holds the others."""
        self.stepping.pop(uuid, None)
        self.desired.pop(uuid, None)
        self.apply_stepping()

    # --- requests ---------------------------------------------------------------------------
    def handle(self, request: dict[str, Any]) -> dict[str, Any]:
        """Answer one request ``{"func", "args", "uuid"}`` with ``{"ret"}`` or ``{"err"}``."""
        functions = self.functions
        func = str(request.get("func", ""))
        args = plain(list(request.get("args") or []))
        with self.session.lock:
            self.client_uuid = str(request.get("uuid", ""))
            if self.simulator is None:
                return {"err": "no scene is configured (in function '" + func + "')"}
            try:
                if func == "zmqRemoteApi.info":
                    return {"ret": [self.info(str(args[0]) if args else "")]}
                if func == "zmqRemoteApi.require":
                    name = str(args[0]).split("-")[0] if args else ""
                    if name not in MODULES:
                        self.fail("function", f"module {name!r} is not emulated", func, name)
                    return {"ret": []}
                impl = functions.get(func)
                if impl is None:
                    why = "is not emulated by sitegen" if func in NOT_EMULATED else "does not exist"
                    if not func.startswith("sim."):
                        why = "does not exist"
                    self.fail("function", f"{func} {why}", func, missing=func)
                try:
                    _signature(impl).bind(self, *args)
                except TypeError:
                    self.fail("argument", f"wrong number of arguments ({len(args)})", func)
                if func != "sim.step":
                    self.simulator.call(blocking=False)
                ret = impl(self, *args)
                if func in LOOKUPS and isinstance(ret, int) and ret >= 0:
                    self.session.found_objects += 1
            except ZmqError as exc:
                return {"err": str(exc)}
            except Park:
                raise
            except Exception as exc:  # a bad value deep in an argument: still the call's error
                message = f"{type(exc).__name__}: {exc}. (in function '{func}')"
                self.note("argument", message)
                return {"err": message}
        return {"ret": list(ret) if isinstance(ret, tuple) else [ret]}

    def call_function(self, func: str, args: list[Any]) -> Any:
        """Call the ``sim.*`` function ``func`` for another API (the legacy ``simx*`` functions
        that create, remove, re-parent or load): its return value, or ``ZmqError`` with
        CoppeliaSim's message (also when the emulation lacks it)."""
        impl = self.functions.get(func)
        with self.session.lock:
            if impl is None:
                raise ZmqError(f"{func} is not emulated by sitegen. (in function '{func}')")
            try:
                _signature(impl).bind(self, *args)
            except TypeError:
                raise ZmqError(f"wrong number of arguments. (in function '{func}')") from None
            return impl(self, *plain(list(args)))

    def info(self, name: str) -> dict[str, Any]:
        """``zmqRemoteApi.info``: the module's functions and constants, as the client expects."""
        if name not in MODULES:
            return {}
        out: dict[str, Any] = {k: {"const": v} for k, v in MODULES[name].items()}
        # functions not emulated are listed too: calling one answers "not emulated" (an
        # error naming it) instead of the client's AttributeError
        prefix = name + "."
        for func in (*self.functions, *NOT_EMULATED):
            if func.startswith(prefix):
                out[func[len(prefix) :]] = {"func": {}}
        return out


@functools.cache
def _signature(fn) -> inspect.Signature:
    return inspect.signature(fn)


def release_stepping(session: Session) -> None:
    """The script has ended: its clients no longer hold the simulation in stepping mode (so
    ``--after`` lets the world run on)."""
    server = getattr(session, "zmq_server", None)
    if server is not None and session.simulator is not None:
        server.stepping.clear()
        server.apply_stepping()
