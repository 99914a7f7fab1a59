"""The asyncio ``RemoteAPIClient`` (``coppeliasim_zmqremoteapi_client.asyncio``), in process.

As with the real asyncio client, ``async with RemoteAPIClient() as client`` opens it, ``sim =
await client.require('sim')`` gives the remote object, and every function of ``sim`` returns an
awaitable (``await sim.getObject('/x')``, ``asyncio.gather(*[sim.createDummy(...) ...])``);
constants are plain attributes. Each call is served by the same in-process server as the
blocking client (``client.py``), in the order the event loop runs the coroutines.

Virtual time: the event loop's clock is ``time.monotonic``, which follows the run's clock in
the script's thread; a loop that would block waiting for a timer (``await asyncio.sleep(0.1)``)
lets that much virtual time pass instead of sleeping on the wall clock (``_virtual_selector``).
"""

from __future__ import annotations

import asyncio
from typing import Any

from .client import _SIM_HELPERS
from .client import RemoteAPIClient as _BlockingClient


class RemoteAPIClient:
    """Client of CoppeliaSim's ZeroMQ remote API for asyncio code, served by the emulation."""

    def __init__(
        self,
        host: str = "localhost",
        port: int = 23000,
        cntport: int | None = None,
        *,
        verbose: int | None = None,
    ):
        self.host, self.port = host, port
        self.cntport = cntport or port + 1
        self._client = _BlockingClient(host, port, cntport, verbose=verbose)
        self.uuid = self._client.uuid
        self.requiredItems: dict[str, Any] = {}
        self.callbackFuncs: dict[str, Any] = {}
        import sys

        main = sys.modules.get("__main__")
        if main is not None:
            main.__dict__["require"] = self.require

    async def __aenter__(self) -> RemoteAPIClient:
        _virtual_selector()
        return self

    async def __aexit__(self, *excinfo: object) -> None:
        return None

    async def call(self, func: str, args: Any) -> Any:
        await asyncio.sleep(0)  # a real await point, as a socket round trip is
        return self._client.call(func, list(args or []))

    async def getObject(self, name: str, _info: dict | None = None) -> Any:
        info = _info if _info is not None else await self.call("zmqRemoteApi.info", [name])
        if not isinstance(info, dict):
            raise ValueError("found nondict")
        obj = type(name, (), {})
        for key, value in info.items():
            if not isinstance(value, dict):
                raise ValueError("found nondict")
            if len(value) == 1 and "func" in value:
                setattr(obj, key, lambda *a, func=f"{name}.{key}": self.call(func, a))
            elif len(value) == 1 and "const" in value:
                setattr(obj, key, value["const"])
            else:
                setattr(obj, key, await self.getObject(f"{name}.{key}", _info=value))
        if name == "sim":
            for helper in _SIM_HELPERS:
                setattr(obj, helper, getattr(self._client, helper))
        return obj

    async def require(self, name: str) -> Any:
        if name not in self.requiredItems:
            await self.call("zmqRemoteApi.require", [name])
            self.requiredItems[name] = await self.getObject(name.split("-")[0])
        return self.requiredItems[name]

    async def setStepping(self, enable: bool = True) -> Any:
        return await self.call("sim.setStepping", [enable])

    async def step(self, *, wait: bool = True) -> None:
        await self.call("sim.step", [wait])


def _virtual_selector() -> None:
    """On a virtual clock, make the running loop advance that clock instead of blocking in
    ``select`` while it waits for a timer (otherwise ``await asyncio.sleep(1)`` would wait one
    wall second per loop pass while virtual time hardly moves)."""
    from ..client import current_session

    session = current_session()
    loop = asyncio.get_running_loop()
    selector = getattr(loop, "_selector", None)
    if session is None or session.clock.realtime or selector is None:
        return
    if getattr(selector, "_sitegen_virtual", False):
        return
    clock, real_select = session.clock, selector.select

    def select(timeout: float | None = None):
        if timeout is None:  # nothing scheduled: only real I/O can wake the loop
            return real_select(None)
        events = real_select(0)
        if not events and timeout > 0:
            clock.advance(timeout)
        return events

    selector.select = select
    selector._sitegen_virtual = True


__all__ = ["RemoteAPIClient"]
