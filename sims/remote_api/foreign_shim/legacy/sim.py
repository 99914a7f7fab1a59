"""``import sim``: CoppeliaSim's legacy remote API for a script run with ``sitegen remote-api run
SCRIPT --python PATH``: every ``simx*`` call is answered by the sitegen server (standard
library only; see sims/remote_api/rpc.py)."""

import _sitegen_bridge as _bridge


def _proxy(name):
    def call(*args):
        return _bridge.request({"op": "legacy", "fn": name, "args": list(args)})

    call.__name__ = call.__qualname__ = name
    return call


_info = _bridge.hello()
globals().update(_info["constants"])
for _name in _info["functions"]:
    globals()[_name] = _proxy(_name)
__all__ = sorted(list(_info["constants"]) + list(_info["functions"]))
del _name


def __getattr__(name):
    if name.startswith("simx") and not name.startswith("simx_"):
        return _proxy(name)  # the server answers with the local error flag and says why
    raise AttributeError(f"module 'sim' has no attribute {name!r}")
