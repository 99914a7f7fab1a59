"""The registry of ``sim.*`` functions a scene script calls, over the World the remote API uses.

Each function is registered under its CoppeliaSim 4.x name (``getObjectHandle``); the V-REP 3.x
name (``simGetObjectHandle``) is derived (``OLD_NAMES`` lists the irregular ones). Functions get
raw Lua values (bytes, numbers, tables) and return Python values that ``LuaState.to_lua``
converts; a failure returns ``state.fail(message)`` so that the error is raised at the script's
line. Objects and joints go through ``sims.remote_api.commands`` (the remote API's own code), so
a script and a remote client see the same world. Objects a script creates (dummies, octrees)
live in the host's table of created objects: the pybullet world has no body for them.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from sims.remote_api import commands as cmd

from .runtime import numbers

REGISTRY: dict[str, Callable[..., Any]] = {}
#: 3.x names that are not ``sim`` + the capitalised 4.x name.
OLD_NAMES = {
    "simExtRemoteApiStart": "simRemoteApi.start",
    "simGetIntegerParameter": "getInt32Parameter",
    "simSetIntegerParameter": "setInt32Parameter",
    "simGetFloatingParameter": "getFloatParameter",
    "simSetFloatingParameter": "setFloatParameter",
    "simWait": "wait",
}
WORLD = -1


def api(name: str):
    def register(fn: Callable[..., Any]) -> Callable[..., Any]:
        REGISTRY[name] = fn
        return fn

    return register


def old_name(new: str) -> str:
    return "sim" + new[0].upper() + new[1:]


def _vec(value: Any, n: int = 3) -> list[float]:
    v = numbers(value)
    if len(v) < n:
        raise ValueError(f"expected a table of {n} numbers")
    return v[:n]


class Context:
    """What a function needs from its caller: the host (world, signals...) and the script."""

    def __init__(self, host: Any, script: Any):
        self.host = host
        self.script = script
        self.state = script.state

    @property
    def world(self) -> Any:
        return self.host.world

    def handle(self, value: Any, relative_to: bool = False) -> int:
        h = int(value)
        if h == -4:  # sim.handle_self
            return self.script.object
        if relative_to and h == -11:
            return -11
        return h

    def check(self, h: int) -> None:
        if h in self.host.created:
            return
        cmd.name(self.world, h)
