"""How the emulated ``sim.*`` functions and constants reach one script's Lua state.

A scene can hold dozens of scripts (the Pioneer scene: 25, most a few lines long), each in its own
Lua state, while the emulation offers some 130 functions and 300 constants under two names each
(``sim.getObjectHandle`` / ``simGetObjectHandle``, ``sim.handle_self`` / ``sim_handle_self``).
Filling every state with all of them made the scene's start cost 36-62 ms of CPU, about half of
what its scripts cost in a 10 s run (bench/lua_bench.py), so members are bound on first use: the
``sim`` table (and ``simUI``...) and the globals ask ``Binder`` for a name they lack, and keep
the answer (``RT.module`` and the ``_G`` metatable in prelude.py). A name the emulation lacks
still becomes a reported stub there. The same Lua function serves both names of a function, as
when they were set eagerly.
"""

from __future__ import annotations

from collections.abc import Callable
from struct import error as struct_error
from typing import Any

from .constants import constants
from .simapi import OLD_NAMES, REGISTRY, Context, old_name

PLAIN = frozenset((int, float))  # passed to Lua as they are (bool is not: to_lua keeps it)
#: 3.x global name -> 4.x target ("getObjectHandle", or "simRemoteApi.start")
_OLD_TARGETS: dict[str, str] = {}


def old_targets() -> dict[str, str]:
    if not _OLD_TARGETS:
        _OLD_TARGETS.update({old_name(n): n for n in REGISTRY if "." not in n})
        _OLD_TARGETS.update(OLD_NAMES)
    return _OLD_TARGETS


class Binder:
    """Binds the registry's functions to one script (its Context) when the script names them."""

    def __init__(self, state: Any, ctx: Context, threaded: bool, new_api: bool):
        self.state = state
        self.ctx = ctx
        self.threaded = threaded
        self.consts = constants(new_api)
        self.modules: dict[str, Any] = {}

    def install(self) -> None:
        state = self.state
        sim = self.module("sim")
        for name in REGISTRY:
            if "." in name:
                self.module(name.partition(".")[0])
        rt = state.rt
        rt.resolve_global = self.resolve_global
        rt.threaded = self.threaded
        sim[b"switchThread"] = rt.switch
        state.g[b"simSwitchThread"] = rt.switch
        now = sim[b"getSimulationTime"]
        waiter = state.lua.eval(b"function(rt, now) return function(dt) rt.wait(dt, now) end end")
        sim[b"wait"] = waiter(rt, now)
        state.g[b"simWait"] = sim[b"wait"]

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
        Lua to wrap, or None."""
        k = key.decode("utf-8", "replace")
        if module == "sim":
            if k in self.consts:
                return self.consts[k]
            label = "sim." + k
            fn = REGISTRY.get(k)
        else:
            label = module + "." + k
            fn = REGISTRY.get(label)
        if fn is None:
            return None
        return bind(fn, self.ctx), True  # Lua wraps it (RT.wrap): no call into Lua from here

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
        mod = mod or "sim"
        return (mod.encode(), member.encode()) if mod in self.modules else None


def bind(fn: Callable[..., Any], ctx: Context) -> Callable[..., Any]:
    """``fn`` as the Python side of a sim.* function: errors become the script's Lua error."""
    state = ctx.state
    to_lua = state.to_lua
    err = state.err

    def call(*args: Any) -> Any:
        try:
            out = fn(ctx, *args)
        except (ValueError, TypeError, KeyError, IndexError, struct_error) as exc:
            return state.fail(str(exc) or type(exc).__name__)
        except Exception as exc:  # a command error from the remote API layer
            return state.fail(str(exc) or type(exc).__name__)
        if isinstance(out, tuple):
            if out and out[0] is err:
                return out
            return tuple([v if type(v) in PLAIN else to_lua(v) for v in out])
        return out if type(out) in PLAIN else to_lua(out)

    return call
