"""CoppeliaSim's ZeroMQ remote API (4.3 and later) on sitegen's emulated World.

Scripts that import ``coppeliasim_zmqremoteapi_client`` (the PyPI client) or ``zmqRemoteApi``
(CoppeliaSim 4.3-4.5) run unchanged under ``sitegen remote-api run``: the shim directory provides
both names, and their ``RemoteAPIClient`` (``client.py``) hands each request, in the protocol's
shape, to an in-process server (``server.py``) that answers on the run's World, clock and
simulation state. No socket is opened. See docs/remote-api.md.
"""

from __future__ import annotations

import re
from pathlib import Path

#: Module names a ZeroMQ script imports; the runner puts shims for both on sys.path.
MODULES = ("coppeliasim_zmqremoteapi_client", "zmqRemoteApi")

_IMPORT = re.compile(
    r"^\s*(?:from\s+(?:coppeliasim_zmqremoteapi_client|zmqRemoteApi)\b"
    r"|import\s+(?:coppeliasim_zmqremoteapi_client|zmqRemoteApi)\b)",
    re.MULTILINE,
)


_LOCAL_IMPORT = re.compile(r"^\s*(?:from|import)\s+([A-Za-z_]\w*)", re.MULTILINE)


def uses_zmq(script: str | Path, depth: int = 2) -> bool:
    """Whether the script, or a module beside it that it imports (``depth`` levels), imports
    the ZeroMQ client."""
    path = Path(script)
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return False
    if _IMPORT.search(text) is not None:
        return True
    if depth <= 0:
        return False
    for name in dict.fromkeys(_LOCAL_IMPORT.findall(text)):
        sibling = path.parent / f"{name}.py"
        if sibling != path and sibling.is_file() and uses_zmq(sibling, depth - 1):
            return True
    return False


__all__ = ["MODULES", "uses_zmq"]
