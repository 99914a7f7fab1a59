"""The Lua edge of the one ``sim.*`` table (``sims.simapi.table``): a script's calls, converted.

A scene can hold dozens of scripts (the Pioneer scene: 25, most a few lines long), each in its own
Lua state, while the table offers some 290 functions and 500 constants under two names each
(``sim.getObjectHandle`` / ``simGetObjectHandle``, ``sim.handle_self`` / ``sim_handle_self``).
Filling every state with all of them made the scene's start cost 36-62 ms of CPU, about half of
what its scripts cost in a 10 s run (bench/lua_bench.py), so members are bound on first use: the
``sim`` table (and ``simUI``...) and the globals ask ``Binder`` for a name they lack, and keep
the answer (``RT.module`` and the ``_G`` metatable in prelude.py). A name the emulation lacks
still becomes a reported stub there.

Values: Lua strings arrive as bytes (the functions take ``str`` or ``bytes``), tables as lupa
tables, converted to lists/dicts only when present (numbers pass as they are: the hot path of a
sensor read or a motor command converts nothing); results go back through ``LuaState.to_lua``.
A blocking function (a generator) returns (done, results...) or (False, id) and Lua yields the
script's coroutine between passes (``RT.blocking`` in prelude.py).
"""

from __future__ import annotations

from collections.abc import Callable
from struct import error as struct_error
from typing import Any

import lupa.lua54 as lua54

from sims.scene.paths import name_suffix
from sims.simapi.context import Caller, SimError
from sims.simapi.ik import CONSTANTS as IK_CONSTANTS
from sims.simapi.table import BLOCKING, FUNCTIONS, OLD_NAMES, old_name

from .constants import constants
from .runtime import to_py

PLAIN = frozenset((int, float))  # passed to Lua as they are (bool is not: to_lua keeps it)
_TABLE = type(lua54.LuaRuntime().table())
#: 3.x global name -> 4.x name ("sim.getObjectHandle", or "simRemoteApi.start")
_OLD_TARGETS: dict[str, str] = {}


def old_targets() -> dict[str, str]:
    if not _OLD_TARGETS:
        _OLD_TARGETS.update({old_name(n): n for n in FUNCTIONS if n.startswith("sim.")})
        _OLD_TARGETS.update(OLD_NAMES)
    return _OLD_TARGETS


class LuaCaller(Caller):
    """A scene script as the caller of ``sim.*`` functions."""

    def __init__(self, host: Any, run: Any):
        self.host = host
        self.run = run
        self.new_api = host.new_api
        self.threaded = run.threaded
        self.object = run.object if run.object > 0 else None
        owner = host.world.name_of(run.object) if run.object > 0 else None
        self.suffix = name_suffix(owner) if owner else None

    @property
    def world(self) -> Any:
        return self.host.world

    @property
    def signals(self) -> dict[str, dict[str, Any]]:
        return self.host.signals

    @property
    def time(self) -> float:
        return float(self.host.world.time)

    @property
    def pass_dt(self) -> float:
        return self.host.pass_dt

    def state_code(self) -> int:
        return self.host.state_code()

    def stop_simulation(self) -> int:
        self.host.stop_requested = True
        return 1

    def pause_simulation(self) -> int:
        self.host.stop_requested = True
        return 1

    def start_simulation(self) -> int:
        return 0

    def system_time(self) -> float:
        return self.host.system_time()

    def status(self, message: str) -> None:
        self.host.status(message)

    @property
    def lua(self) -> Any:
        return self.host

    @property
    def script(self) -> Any:
        return self.run

    @property
    def persistent(self) -> bool:
        return False  # scripts run while the simulation runs

    def not_found(self, message: str, query: str) -> int:
        if self.new_api or self.store.params.get(("int", 0), 1) & 1 == 0:
            return super().not_found(message, query)
        self.host.status(f"Lua API warning: {message}")
        return -1

    def set_stepping(self, enable: bool) -> int:
        before = 0 if self.run.auto_switch else 1
        self.set_auto_switch(not enable)
        return before

    def get_stepping(self) -> bool:
        return not self.run.auto_switch

    def set_auto_switch(self, on: bool) -> None:
        self.run.auto_switch = on
        if self.run.state is not None:
            self.run.state.rt[b"auto_switch"] = on

    def key_presses(self) -> list[tuple[float, int]]:
        from .keys import current, key_code

        return [(e.start, key_code(e.key)) for e in current().events]

    def call(self, fn: Any, *args: Any) -> Any:
        if fn is None:
            return None
        return self.run.state.call(fn, *args)


class Binder:
    """Binds the table's functions to one script (its Caller) when the script names them."""

    def __init__(self, state: Any, caller: LuaCaller, threaded: bool, new_api: bool):
        self.state = state
        self.caller = caller
        self.threaded = threaded
        self.consts = constants(new_api)
        self.modules: dict[str, Any] = {}

    def install(self) -> None:
        state = self.state
        sim = self.module("sim")
        for name in FUNCTIONS:
            if not name.startswith("sim."):
                self.module(name.partition(".")[0])
        rt = state.rt
        rt.resolve_global = self.resolve_global
        rt.threaded = self.threaded
        rt.auto_switch = True
        sim[b"switchThread"] = rt.switch
        state.g[b"simSwitchThread"] = rt.switch

    def module(self, name: str) -> Any:
        if name not in self.modules:
            t = self.state.rt.module(
                name.encode(), self.state.lua.table(), lambda key: self.resolve(name, key)
            )
            self.state.g[name.encode()] = t
            self.modules[name] = t
        return self.modules[name]

    def resolve(self, module: str, key: bytes) -> Any:
        """A member of ``module`` the script asked for: a constant, (bound function, True) for
        Lua to wrap, (start, True, step) for a blocking function, or None."""
        k = key.decode("utf-8", "replace")
        if module == "sim" and k in self.consts:
            return self.consts[k]
        if module == "simIK" and k in IK_CONSTANTS:
            return IK_CONSTANTS[k]
        label = module + "." + k
        fn = FUNCTIONS.get(label)
        if fn is None:
            return None
        if label in BLOCKING:
            start, step = bind_blocking(fn, self.caller)
            return start, True, step
        return bind(fn, self.caller), True  # Lua wraps it (RT.wrap): no call into Lua here

    def resolve_global(self, key: bytes) -> Any:
        """A 3.x global: ``sim_handle_self`` (its value) or ``simGetObjectHandle`` (the module
        and member names of the 4.x function, which Lua looks up)."""
        k = key.decode("utf-8", "replace")
        if k.startswith("sim_"):
            return self.consts.get(k[4:])
        target = old_targets().get(k)
        if target is None:
            return None
        mod, _, member = target.rpartition(".")
        return (mod.encode(), member.encode()) if mod in self.modules else None


def _args(args: tuple) -> tuple:
    """Lua tables as lists/dicts; everything else as it came."""
    for a in args:
        if type(a) is _TABLE:
            return tuple(to_py(v) if type(v) is _TABLE else v for v in args)
    return args


def bind(fn: Callable[..., Any], caller: LuaCaller) -> Callable[..., Any]:
    """``fn`` as the Python side of a sim.* function: errors become the script's Lua error."""
    state = caller.run.state
    to_lua = state.to_lua
    fail = state.fail

    def call(*args: Any) -> Any:
        try:
            out = fn(caller, *_args(args))
        except (SimError, ValueError, TypeError, KeyError, IndexError, struct_error) as exc:
            return fail(str(exc).strip("'\"") or type(exc).__name__)
        except Exception as exc:  # an emulation error: still the script's error, at its line
            return fail(f"{type(exc).__name__}: {exc}")
        if type(out) is tuple:
            return tuple([v if type(v) in PLAIN else to_lua(v) for v in out])
        return out if type(out) in PLAIN else to_lua(out)

    return call


def bind_blocking(fn: Callable[..., Any], caller: LuaCaller) -> tuple[Callable, Callable]:
    """(start, step) of a blocking function: each returns (True, results...), (False, id) to
    wait for the next pass, or the error marker."""
    state = caller.run.state
    to_lua = state.to_lua
    waiting: dict[int, Any] = {}
    counter = [0]

    def advance(gen: Any) -> Any:
        try:
            while True:
                next(gen)
                if caller.threaded:
                    counter[0] += 1
                    waiting[counter[0]] = gen
                    return False, counter[0]
        except StopIteration as stop:
            out = stop.value
        except Exception as exc:
            return state.fail(str(exc).strip("'\"") or type(exc).__name__)
        if out is None:
            return (True,)
        if type(out) is tuple:
            return (True, *[v if type(v) in PLAIN else to_lua(v) for v in out])
        return True, out if type(out) in PLAIN else to_lua(out)

    def start(*args: Any) -> Any:
        try:
            gen = fn(caller, *_args(args))
        except Exception as exc:
            return state.fail(str(exc))
        return advance(gen)

    def step(key: int) -> Any:
        gen = waiting.pop(int(key), None)
        if gen is None:
            return state.fail("blocking call lost its state")
        return advance(gen)

    return start, step
