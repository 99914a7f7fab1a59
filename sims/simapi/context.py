"""Who calls a ``sim.*`` function, and what the function may ask of its caller.

CoppeliaSim's ZeroMQ remote API is its Lua ``sim.*`` API, so this project has one
implementation of each function (``sims.simapi.table``), written against ``Caller``: plain
Python values in (numbers, ``str`` or ``bytes`` for strings, lists, dicts, None) and out (a
tuple for several results, ``bytes`` for a buffer); errors are ``SimError``. Two callers
exist: a scene script (``sims.lua.binding.LuaCaller``: it has an object, may be threaded, and
follows V-REP 3.x rules in old scenes) and a ZeroMQ client (``sims.remote_api.zmq.functions``:
no object, raises on every error). What differs between them lives in their ``Caller``
subclass, not in the functions.

``store(world)`` is what the scene keeps besides its physics and that both APIs share: custom
data blocks, user interfaces, drawing objects, collections, parameters, the message queue.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from typing import Any

from .constants import HANDLE_MASK

HANDLE_SELF = -4
HANDLE_PARENT = -11
WORLD = -1


class SimError(Exception):
    """A ``sim.*`` call failed: ``str()`` is CoppeliaSim's message. ``kind`` tells the ZeroMQ
    server how to note it ("argument", "handle", "path", "function"); ``missing``/``nearest``
    name an object the scene lacks."""

    def __init__(self, message: str, kind: str = "argument", missing: str = "", nearest=()):
        super().__init__(message)
        self.kind = kind
        self.missing = missing
        self.nearest = tuple(nearest)


@dataclass
class Store:
    """What a scene keeps besides its physics (see the module docstring)."""

    custom: dict[tuple[int, str], bytes] = field(default_factory=dict)
    uis: dict[int, dict[Any, Any]] = field(default_factory=dict)
    drawings: dict[int, dict[str, Any]] = field(default_factory=dict)
    collections: dict[int, list[tuple[int, int, int]]] = field(default_factory=dict)
    params: dict[tuple[str, int], Any] = field(default_factory=dict)
    object_params: dict[tuple[int, int], Any] = field(default_factory=dict)
    script_params: dict[tuple[int, str], Any] = field(default_factory=dict)
    special: dict[int, int] = field(default_factory=dict)
    explicit: dict[tuple[str, int], bool] = field(default_factory=dict)
    messages: list[tuple[int, list[int]]] = field(default_factory=list)
    motions: dict[int, Any] = field(default_factory=dict)  # rmlPos/rmlVel objects
    next_handle: dict[str, int] = field(default_factory=dict)
    selection: list[int] = field(default_factory=list)
    ik_envs: dict[int, Any] = field(default_factory=dict)  # simIK environments (ik.py)
    consoles: dict[int, list[str]] = field(default_factory=dict)  # [title, unfinished line]

    def new_handle(self, kind: str, first: int = 1) -> int:
        h = self.next_handle.get(kind, first)
        self.next_handle[kind] = h + 1
        return h


#: each World's Store, kept beside the World (not in it: the World's state is its own) and
#: dropped with it; a stand-in world that takes no weak reference is kept by id
_STORES: weakref.WeakKeyDictionary[Any, Store] = weakref.WeakKeyDictionary()
_PINNED: dict[int, tuple[Any, Store]] = {}


def _kept(world: Any) -> Store | None:
    try:
        return _STORES.get(world)
    except TypeError:
        pinned = _PINNED.get(id(world))
        return pinned[1] if pinned is not None and pinned[0] is world else None


def _keep(world: Any, s: Store) -> None:
    try:
        _STORES[world] = s
    except TypeError:
        _PINNED[id(world)] = (world, s)


def store(world: Any) -> Store:
    """The world's store (made on first use; it outlives ``reset()``, as CoppeliaSim keeps
    custom data and UIs across simulations)."""
    s = _kept(world)
    if s is None:
        s = Store()
        for block in getattr(getattr(world, "source", None), "custom_data", None) or ():
            h = world.handle(block.owner) if block.owner else -12  # sim.handle_scene
            if h is not None:
                s.custom[(h, block.tag)] = bytes.fromhex(block.hex)
        for param in getattr(getattr(world, "source", None), "script_parameters", None) or ():
            h = world.handle(param.owner)
            if h is not None:
                s.script_params[(h, param.tag)] = bytes.fromhex(param.hex)
        _keep(world, s)
    return s


class Caller:
    """The calling side of a ``sim.*`` function (see the module docstring)."""

    new_api = True  # CoppeliaSim 4.x rules (False: a V-REP 3.x scene's script)
    threaded = False  # may wait (a threaded script, a ZeroMQ client)
    object: int | None = None  # the calling script's object

    @property
    def done(self) -> int | None:
        """What a setter returns: nothing in 4.x (and to ZeroMQ clients), 1 in V-REP 3.x."""
        return None if self.new_api else 1

    @property
    def world(self) -> Any:
        raise NotImplementedError

    @property
    def signals(self) -> dict[str, dict[str, Any]]:
        raise NotImplementedError

    @property
    def store(self) -> Store:
        return store(self.world)

    # -- time and simulation -------------------------------------------------------------------
    @property
    def time(self) -> float:
        return float(self.world.time)

    @property
    def pass_dt(self) -> float:
        return 0.05

    def state_code(self) -> int:
        return 0x11

    def start_simulation(self) -> int:
        raise SimError("this caller cannot start a simulation")

    def stop_simulation(self) -> int:
        raise SimError("this caller cannot stop a simulation")

    def pause_simulation(self) -> int:
        raise SimError("this caller cannot pause a simulation")

    def system_time(self) -> float:
        """Seconds on the run's clock (virtual unless the run is in real time)."""
        return self.time

    def status(self, message: str) -> None:
        """A status-bar line (sim.addStatusbarMessage, sim.addLog)."""

    def set_stepping(self, enable: bool) -> int:
        return 0

    def get_stepping(self) -> bool:
        return False

    def set_auto_switch(self, on: bool) -> None:
        """A threaded script's automatic thread switches on or off."""

    def next_pass(self) -> None:
        """Wait for the next simulation pass (a blocking function's ``yield``, where the caller
        is not a coroutine: a ZeroMQ client)."""
        raise SimError("this caller cannot wait for the simulation")

    def replace_scene(self, path: str) -> None:
        raise SimError("this caller cannot load scenes")

    def key_presses(self) -> list[tuple[float, int]]:
        """(simulation time, key code) of the run's scripted key presses (``--keys``)."""
        return []

    def call(self, fn: Any, *args: Any) -> Any:
        """Call a callback the caller passed (a Lua function)."""
        raise SimError("callbacks are not supported for this caller")

    # -- scripts -------------------------------------------------------------------------------
    @property
    def lua(self) -> Any:
        """The scene's ScriptHost (None when its scripts do not run)."""
        return None

    @property
    def script(self) -> Any:
        """The calling script's ScriptRun (None for a remote client)."""
        return None

    # -- objects -------------------------------------------------------------------------------
    def handle(self, value: Any, position: int = 1) -> int:
        """An object handle argument: ``sim.handle_self`` is the calling script's object; the
        flags of a flagged handle are dropped (``handle_flags`` reads them)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SimError(f"argument {position}: object handle expected, got {value!r}")
        h = int(value)
        if h == HANDLE_SELF:
            if self.object is None:
                raise SimError("sim.handle_self names no object for this caller")
            return self.object
        if h >= 0 and h & ~HANDLE_MASK:
            return h & HANDLE_MASK
        return h

    def entry(self, h: int) -> Any:
        """The tree entry of handle ``h``; SimError when there is none."""
        e = self.world.object_tree().by_handle.get(h)
        if e is None:
            raise SimError(f"object handle {h} does not exist", "handle")
        return e

    def not_found(self, message: str, query: str) -> int:
        """An object a name or path names does not exist: -1, or an error (4.x and ZeroMQ)."""
        from sims.scene.paths import nearest

        raise SimError(message, "path", query, nearest(self.world.object_tree(), query))

    @property
    def persistent(self) -> bool:
        """Objects created now outlive the simulation (created while it is stopped)."""
        return self.state_code() == 0
