"""The fences around a course script running in this process: what it imports and sees
(``script_environment``), how long it may run (``Watchdog``) and that it cannot reach a network
(``no_network``).

``sims.remote_api.runner.run_script`` puts these around the script's thread; each undoes
itself on exit, so a run leaves ``sys.path``, ``sys.argv``, ``sys.modules``, ``random`` and
``socket`` as it found them (tests/test_remote_api_scripts.py checks this).
"""

from __future__ import annotations

import contextlib
import ctypes
import math
import random
import socket
import sys
import threading
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

from .clock import ScriptTimeout
from .zmq import MODULES as ZMQ_MODULES

SHIM_DIR = Path(__file__).resolve().parent / "shim"
SHIM_MODULES = ("sim", "vrep", "simConst", "vrepConst", "keyboard", *ZMQ_MODULES)


class Watchdog:
    """Stops the script thread once ``limit`` wall seconds pass (re-raising until it ends)."""

    def __init__(self, limit: float | None, thread_id: int):
        self.limit = limit
        self.thread_id = thread_id
        self.fired = False
        self._done = threading.Event()
        self._thread: threading.Thread | None = None

    def _raise(self, exc: Any) -> None:
        ctypes.pythonapi.PyThreadState_SetAsyncExc(
            ctypes.c_ulong(self.thread_id), ctypes.py_object(exc) if exc else None
        )

    def _watch(self) -> None:
        if self._done.wait(min(self.limit or 0.0, threading.TIMEOUT_MAX)):
            return
        while not self._done.is_set():
            self.fired = True
            self._raise(ScriptTimeout)
            self._done.wait(0.5)

    def __enter__(self) -> Watchdog:
        if self.limit is not None and math.isfinite(self.limit):
            self._thread = threading.Thread(
                target=self._watch, name="remote-api-watchdog", daemon=True
            )
            self._thread.start()
        return self

    def __exit__(self, *exc: object) -> None:
        self._done.set()
        if self._thread is not None:
            self._thread.join()
            if self.fired:
                self._raise(None)  # drop an exception not yet delivered


@contextlib.contextmanager
def script_environment(path: Path, argv: Sequence[str], seed: int | None) -> Iterator[None]:
    saved_path, saved_argv = list(sys.path), list(sys.argv)
    saved_modules = {name: sys.modules.pop(name) for name in SHIM_MODULES if name in sys.modules}
    before = set(sys.modules)
    saved_random = random.getstate()
    real_seed = random.seed
    sys.path[:0] = [str(SHIM_DIR), str(path.parent)]
    sys.argv = [str(path), *argv]
    if seed is not None:
        real_seed(seed)

        def seeded(a: Any = None, version: int = 2) -> None:
            real_seed(seed if a is None else a, version)

        random.seed = seeded
    try:
        yield
    finally:
        random.seed = real_seed
        random.setstate(saved_random)
        sys.path[:], sys.argv[:] = saved_path, saved_argv
        for name in set(sys.modules) - before:
            module_file = getattr(sys.modules[name], "__file__", None) or ""
            ours = name.split(".")[0] in ("sims", "sitegen", "roster")
            if name in SHIM_MODULES or (not ours and _inside(module_file, (path.parent,))):
                del sys.modules[name]
        sys.modules.update(saved_modules)


def _inside(file: str, folders: Sequence[Path]) -> bool:
    if not file:
        return False
    p = Path(file).resolve()
    return any(folder == p.parent or folder in p.parents for folder in folders)


@contextlib.contextmanager
def no_network(thread_id: int, every_thread: bool = False) -> Iterator[None]:
    """Sockets used by the script's thread (every thread with ``every_thread``: the script's
    own child process) cannot connect or send anywhere."""
    cls = socket.socket
    names = ("connect", "connect_ex", "sendto") if isinstance(cls, type) else ()
    saved = {name: getattr(cls, name) for name in names if hasattr(cls, name)}

    def guard(name: str):
        original = saved[name]

        def method(self, *args: Any, **kwargs: Any):
            if every_thread or threading.get_ident() == thread_id:
                raise OSError(
                    f"socket.{name}: network access is disabled while a script runs "
                    "under the sitegen remote API emulation"
                )
            return original(self, *args, **kwargs)

        return method

    for name in saved:
        setattr(cls, name, guard(name))
    try:
        yield
    finally:
        for name, fn in saved.items():
            setattr(cls, name, fn)
