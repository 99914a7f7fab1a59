"""The asyncio form of the bridge client (see __init__.py): every call is awaitable."""

import asyncio

from . import RemoteAPIClient as _Blocking


class RemoteAPIClient:
    def __init__(self, host="localhost", port=23000, cntport=None, *, verbose=None):
        self._client = _Blocking(host, port, cntport, verbose=verbose)
        self.requiredItems = {}

    async def __aenter__(self):
        return self

    async def __aexit__(self, *excinfo):
        return None

    async def call(self, func, args):
        await asyncio.sleep(0)
        return self._client.call(func, list(args or []))

    async def getObject(self, name, _info=None):
        info = _info if _info is not None else await self.call("zmqRemoteApi.info", [name])
        obj = type(name, (), {})
        for key, value in info.items():
            if len(value) == 1 and "func" in value:
                setattr(obj, key, lambda *a, func=f"{name}.{key}": self.call(func, a))
            elif len(value) == 1 and "const" in value:
                setattr(obj, key, value["const"])
            else:
                setattr(obj, key, await self.getObject(f"{name}.{key}", _info=value))
        return obj

    async def require(self, name):
        if name not in self.requiredItems:
            await self.call("zmqRemoteApi.require", [name])
            self.requiredItems[name] = await self.getObject(name.split("-")[0])
        return self.requiredItems[name]

    async def setStepping(self, enable=True):
        return await self.call("sim.setStepping", [enable])

    async def step(self, *, wait=True):
        await self.call("sim.step", [wait])


__all__ = ["RemoteAPIClient"]
