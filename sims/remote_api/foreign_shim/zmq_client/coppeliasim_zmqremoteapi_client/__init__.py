"""``from coppeliasim_zmqremoteapi_client import RemoteAPIClient`` for a script run with
``--python PATH`` in an environment without the real client (pyzmq, cbor2): the same calls,
answered by the sitegen server through its bridge (standard library only; rpc.py). Where the
real client is installed the script uses it instead, over ZeroMQ (bootstrap.py decides)."""

import array
import copy
import sys
import uuid

import _sitegen_bridge as _bridge


class RemoteAPIClient:
    def __init__(self, host="localhost", port=23000, cntport=None, *, verbose=None):
        self.host, self.port, self.cntport = host, port, cntport
        self.uuid = str(uuid.uuid4())
        self.requiredItems = {}
        self.callbackFuncs = {}
        main = sys.modules.get("__main__")
        if main is not None:
            main.__dict__["require"] = self.require

    def call(self, func, args):
        if any(callable(a) for a in (args or [])):
            raise Exception(f"Python callbacks are not supported by the sitegen emulation ({func})")
        request = {"func": func, "args": list(args or []), "uuid": self.uuid}
        reply = _bridge.request({"op": "zmq", "req": request})
        if "err" in reply:
            raise Exception(reply["err"])
        ret = reply.get("ret", [])
        if len(ret) == 1:
            return ret[0]
        if len(ret) > 1:
            return tuple(ret)
        return None

    def getObject(self, name, _info=None):
        info = _info if _info is not None else self.call("zmqRemoteApi.info", [name])
        obj = type(name, (), {})
        for key, value in info.items():
            if len(value) == 1 and "func" in value:
                setattr(obj, key, lambda *a, func=f"{name}.{key}": self.call(func, a))
            elif len(value) == 1 and "const" in value:
                setattr(obj, key, value["const"])
            else:
                setattr(obj, key, self.getObject(f"{name}.{key}", _info=value))
        if name == "sim":
            for helper in _HELPERS:
                setattr(obj, helper, getattr(self, helper))
        return obj

    def require(self, name):
        vname = name.split("-")[0]
        if vname not in self.requiredItems:
            self.call("zmqRemoteApi.require", [name])
            self.requiredItems[vname] = self.getObject(vname)
        return self.requiredItems[vname]

    def setStepping(self, enable=True):
        return self.call("sim.setStepping", [enable])

    def step(self, *, wait=True):
        self.call("sim.step", [wait])

    def copyTable(self, table):
        return copy.deepcopy(table)

    def __del__(self):
        try:
            _bridge.request({"op": "zmq", "req": {"func": "_*end*_", "uuid": self.uuid}})
        except Exception:
            pass


def _pack(code):
    def pack(self, table, start=0, cnt=0):
        items = list(table)[start : (start + cnt) if cnt else None]
        return array.array(code, items).tobytes()

    return pack


def _unpack(code):
    def unpack(self, data, start=0, cnt=0, off=0):
        arr = array.array(code)
        begin = start * arr.itemsize + off
        end = begin + cnt * arr.itemsize if cnt else None
        arr.frombytes(bytes(data)[begin:end])
        return arr.tolist()

    return unpack


_HELPERS = ["copyTable"]
for _kind, _code in (
    ("UInt8", "B"),
    ("UInt16", "H"),
    ("UInt32", "I"),
    ("Int32", "i"),
    ("Float", "f"),
    ("Double", "d"),
):
    setattr(RemoteAPIClient, f"pack{_kind}Table", _pack(_code))
    setattr(RemoteAPIClient, f"unpack{_kind}Table", _unpack(_code))
    _HELPERS += [f"pack{_kind}Table", f"unpack{_kind}Table"]

__all__ = ["RemoteAPIClient"]
