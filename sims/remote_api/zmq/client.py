"""``RemoteAPIClient``: the ZeroMQ remote API client as scripts use it, talking in process.

It behaves as the PyPI package ``coppeliasim-zmqremoteapi-client`` (and the ``zmqRemoteApi``
module of CoppeliaSim 4.3-4.5) does from a script's side, without a socket:

- ``RemoteAPIClient(host='localhost', port=23000, cntport=None, *, verbose=None)`` records the
  address (shown in the run's summary, never contacted) and connects to the run's session;
- ``client.require('sim')`` and ``client.getObject('sim')`` return an object whose attributes
  are the server's functions and constants (from ``zmqRemoteApi.info``), as the real client
  builds it; the real client also puts ``require`` in ``__main__``'s globals, and so does this;
- a call returns ``None`` for no value, the value itself for one, a tuple for several;
- an error is raised as ``Exception(message)``, as the real client raises it;
- ``client.setStepping(enable)`` and ``client.step()`` call ``sim.setStepping``/``sim.step``.
"""

from __future__ import annotations

import array
import copy
import itertools
import sys
from typing import Any

from ..client import current_session
from .functions import server_for
from .server import ZmqServer

NO_SCENE = (
    "Failed connecting to CoppeliaSim: no scene is configured for the sitegen emulation "
    "(run the script with `sitegen remote-api run SCRIPT --scene NAME`)"
)


_COUNTER = itertools.count(1)


class _Module(type):
    """The class of a remote module object: unknown function names still reach the server, so
    the answer ("not emulated" / "does not exist") names the function and the script line."""

    def __getattr__(cls, name: str) -> Any:
        client: RemoteAPIClient | None = cls.__dict__.get("_client")
        if client is None or name.startswith("_"):
            raise AttributeError(name)
        if "_" in name or not name[:1].islower():
            message = f"type object '{cls.__name__}' has no attribute '{name}'"
            server = client._server()
            if server is not None:
                what = f"{cls.__name__}.{name}"
                server.note("function", f"{what}: no such constant in the emulation", what)
            raise AttributeError(message)
        func = f"{cls.__name__}.{name}"
        return lambda *args: client.call(func, list(args))


class RemoteAPIClient:
    """Client of CoppeliaSim's ZeroMQ remote API, served by the sitegen emulation."""

    def __init__(
        self,
        host: str = "localhost",
        port: int = 23000,
        cntport: int | None = None,
        *,
        verbose: int | None = None,
    ):
        self.host, self.port, self.cntport = str(host), int(port), cntport
        self.verbose = int(verbose or 0)
        self.uuid = f"sitegen-client-{next(_COUNTER)}"
        self.requiredItems: dict[str, Any] = {}
        self.callbackFuncs: dict[str, Any] = {}
        self._session = current_session()
        self._client_id = -1
        if self._session is not None and self._session.simulator is not None:
            self._client_id = self._session.connect(self.host, self.port, api="zmq")
        main = sys.modules.get("__main__")
        if main is not None:
            main.__dict__["require"] = self.require

    def __del__(self) -> None:
        """Free the connection slot (scripts that make a client per call would exhaust them)."""
        try:
            if self._session is not None and self._client_id >= 0:
                self._session.finish(self._client_id)
        except Exception:
            pass

    def _server(self) -> ZmqServer | None:
        if self._session is None or self._session.simulator is None or self._client_id < 0:
            return None
        return server_for(self._session)

    # --- calls -----------------------------------------------------------------------------
    def call(self, func: str, args: Any) -> Any:
        """Call ``func`` on the server with ``args``; returns as the real client does."""
        server = self._server()
        if server is None:
            raise Exception(NO_SCENE)
        if any(callable(a) for a in (args or [])):
            raise Exception(f"Python callbacks are not supported by the sitegen emulation ({func})")
        request = {"func": func, "args": list(args or []), "uuid": self.uuid}
        if self.verbose > 0:
            print("Sending:", request)
        reply = server.handle(request)
        if self.verbose > 0:
            print("Received:", reply)
        if "err" in reply:
            raise Exception(reply["err"])
        ret = reply.get("ret", [])
        if len(ret) == 1:
            return ret[0]
        if len(ret) > 1:
            return tuple(ret)
        return None

    def getObject(self, name: str, _info: dict | None = None) -> Any:
        """The remote object ``name`` (``'sim'``): its functions and constants as attributes."""
        info = _info if _info is not None else self.call("zmqRemoteApi.info", [name])
        if not isinstance(info, dict):
            raise ValueError("found nondict")
        obj = _Module(name, (), {"_client": self})
        for key, value in info.items():
            if not isinstance(value, dict):
                raise ValueError("found nondict")
            if len(value) == 1 and "func" in value:
                setattr(obj, key, lambda *a, func=f"{name}.{key}": self.call(func, list(a)))
            elif len(value) == 1 and "const" in value:
                setattr(obj, key, value["const"])
            else:
                setattr(obj, key, self.getObject(f"{name}.{key}", _info=value))
        if name == "sim":
            for helper in _SIM_HELPERS:
                setattr(obj, helper, getattr(self, helper))
        return obj

    def require(self, name: str) -> Any:
        vname = name.split("-")[0]
        if vname not in self.requiredItems:
            self.call("zmqRemoteApi.require", [name])
            self.requiredItems[vname] = self.getObject(vname)
        return self.requiredItems[vname]

    def setStepping(self, enable: bool = True) -> Any:
        return self.call("sim.setStepping", [enable])

    def step(self, *, wait: bool = True) -> None:
        self.call("sim.step", [wait])

    # --- helpers the real client adds to ``sim`` (pure, no server call) ---------------------
    def copyTable(self, table: Any) -> Any:
        return copy.deepcopy(table)

    def getScriptFunctions(self, scriptHandle: int) -> Any:
        raise Exception("sim.getScriptFunctions: scripts in the scene are not run by sitegen")

    @staticmethod
    def _pack(table: Any, code: str, start: int = 0, cnt: int = 0) -> bytes:
        items = list(table)[start : (start + cnt) if cnt else None]
        return array.array(code, items).tobytes()

    @staticmethod
    def _unpack(data: bytes, code: str, start: int = 0, cnt: int = 0, off: int = 0) -> list:
        arr = array.array(code)
        begin = start * arr.itemsize + off
        end = begin + cnt * arr.itemsize if cnt else None
        arr.frombytes(bytes(data)[begin:end])
        return arr.tolist()


_CODES = {
    "UInt8": "B",
    "UInt16": "H",
    "UInt32": "I",
    "Int32": "i",
    "Float": "f",
    "Double": "d",
}
_SIM_HELPERS = ["copyTable", "getScriptFunctions"]
for _kind, _code in _CODES.items():

    def _packer(self, table, start=0, cnt=0, _code=_code):
        return RemoteAPIClient._pack(table, _code, start, cnt)

    def _unpacker(self, data, start=0, cnt=0, off=0, _code=_code):
        return RemoteAPIClient._unpack(data, _code, start, cnt, off)

    setattr(RemoteAPIClient, f"pack{_kind}Table", _packer)
    setattr(RemoteAPIClient, f"unpack{_kind}Table", _unpacker)
    _SIM_HELPERS += [f"pack{_kind}Table", f"unpack{_kind}Table"]
del _kind, _code

__all__ = ["RemoteAPIClient"]
