"""CoppeliaSim's client modules kept inside a script's own package load the emulation too.

The shim directory first on ``sys.path`` catches ``import sim``; it cannot catch ``from . import
sim`` or ``from robot import vrep``, where Python finds the package's own copy of CoppeliaSim's
``sim.py`` (which then fails: "The remoteApi library could not be loaded"). While a script runs,
``substitute_clients`` puts a finder in front of the import system: a module ``PKG.sim``,
``PKG.vrep``, ``PKG.simConst``, ``PKG.vrepConst``, ``PKG.zmqRemoteApi`` or
``PKG.coppeliasim_zmqremoteapi_client`` whose file is CoppeliaSim's (recognised by what it
defines, see ``_MARKERS``) is loaded as the emulation of the same name. Any other module with one
of those names (a student's own ``robot/sim.py`` helpers) loads as usual.
"""

from __future__ import annotations

import contextlib
import importlib
import importlib.abc
import importlib.machinery
import importlib.util
import sys
from collections.abc import Iterator
from types import ModuleType

#: last name component -> the emulation module whose names it gets
EMULATIONS = {
    "sim": "sims.remote_api.api",
    "vrep": "sims.remote_api.api",
    "simConst": "sims.remote_api.constants",
    "vrepConst": "sims.remote_api.constants",
    "zmqRemoteApi": "sims.remote_api.zmq.client",
    "coppeliasim_zmqremoteapi_client": "sims.remote_api.zmq.client",
}

#: text every CoppeliaSim client module of that kind holds (checked on its first 200 kB)
_MARKERS = {
    "sim": ("simxStart", "remoteApi"),
    "vrep": ("simxStart", "remoteApi"),
    "simConst": ("simx_opmode_oneshot", "sim_"),
    "vrepConst": ("simx_opmode_oneshot", "sim_"),
    "zmqRemoteApi": ("RemoteAPIClient", "zmq"),
    "coppeliasim_zmqremoteapi_client": ("RemoteAPIClient", "zmq"),
}


def is_coppelia_client(name: str, origin: str | None) -> bool:
    """Whether the file ``origin`` is CoppeliaSim's client module ``name`` (by its content)."""
    markers = _MARKERS.get(name)
    if not markers or not origin:
        return False
    try:
        with open(origin, "rb") as fh:
            text = fh.read(200_000).decode("utf-8", "replace")
    except OSError:
        return False
    return all(m in text for m in markers)


class _EmulationLoader(importlib.abc.Loader):
    def __init__(self, emulation: str):
        self.emulation = emulation

    def create_module(self, spec: importlib.machinery.ModuleSpec) -> ModuleType | None:
        return None  # the default module object

    def exec_module(self, module: ModuleType) -> None:
        source = importlib.import_module(self.emulation)
        names = getattr(source, "__all__", None) or [n for n in vars(source) if n[:1] != "_"]
        for name in names:
            module.__dict__[name] = getattr(source, name)
        if hasattr(source, "__getattr__"):
            module.__dict__["__getattr__"] = source.__getattr__
        if self.emulation.endswith("zmq.client"):
            module.__dict__["RemoteAPIClient"] = source.RemoteAPIClient
        module.__dict__["__sitegen_emulation__"] = self.emulation


class _ClientFinder(importlib.abc.MetaPathFinder):
    """Finds ``PKG.<client>`` modules that are CoppeliaSim's and hands back the emulation."""

    def find_spec(self, fullname: str, path=None, target=None):
        parent, _, last = fullname.rpartition(".")
        if not parent or last not in EMULATIONS:
            return None
        spec = importlib.machinery.PathFinder.find_spec(fullname, path)
        if spec is None:
            return None
        origin = spec.origin
        if not is_coppelia_client(last, origin):
            return None
        return importlib.util.spec_from_loader(
            fullname, _EmulationLoader(EMULATIONS[last]), origin=origin
        )


@contextlib.contextmanager
def substitute_clients() -> Iterator[None]:
    """CoppeliaSim's client modules inside the script's packages load as the emulation."""
    finder = _ClientFinder()
    sys.meta_path.insert(0, finder)
    before = set(sys.modules)
    try:
        yield
    finally:
        with contextlib.suppress(ValueError):
            sys.meta_path.remove(finder)
        for name in set(sys.modules) - before:  # the shim packages' submodules (.asyncio)
            if name.split(".")[0] in SHIM_PACKAGES and "." in name:
                del sys.modules[name]


#: Shim modules that are packages (their submodules are dropped after a run, like them).
SHIM_PACKAGES = ("coppeliasim_zmqremoteapi_client", "zmqRemoteApi")
