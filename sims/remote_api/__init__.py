"""CoppeliaSim's legacy remote API (``import sim`` / ``import vrep``) on sitegen's pybullet scenes.

Course scripts written for CoppeliaSim run unchanged: ``run_script`` (or the CLI,
``sitegen remote-api run SCRIPT --scene 2w1a``) executes them with the ``shim`` directory first
on ``sys.path``, so ``import sim`` finds :mod:`sims.remote_api.api`. No socket is ever opened:
``simxStart`` only records the address. See docs/README-remote-api.md.

Importing this package registers the ``script`` clip kind with ``sims.clips``
(``ClipSpec(kind="script", scenario="path/to/script.py", params={"scene": ..., "after": ...})``).
"""

from __future__ import annotations

from .client import Session, configure, current_session, set_session
from .record import register as _register_clip_kind
from .runner import RunResult, run_script

_register_clip_kind()

__all__ = ["RunResult", "Session", "configure", "current_session", "run_script", "set_session"]
