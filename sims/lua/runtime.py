"""One scene script in its own Lua 5.4 state (lupa), as CoppeliaSim gives each script its own.

``LuaState`` owns the interpreter: the sandbox prelude (prelude.py), the ``sim`` table and the
old-style globals (``simGetObjectHandle``, ``sim_handle_self``...), conversions between Python
and Lua values, and the three ways a script is entered: ``call`` (a function runs to its end
within the instruction budget), ``resume`` (a threaded script's coroutine runs until it yields
at ``sim.switchThread``/``sim.wait``/an automatic switch) and ``compile``.

Python never sees a Lua string as ``str`` by accident: the state runs with ``encoding=None``, so
Lua strings arrive as bytes (a packed buffer stays a buffer) and ``to_lua`` encodes ``str``.
"""

from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
import time
import weakref
from collections.abc import Callable
from pathlib import Path
from typing import Any

import lupa.lua54 as lua54

from .prelude import PRELUDE

#: Lua instructions one virtual step is worth: a threaded script switches after this many
#: (CoppeliaSim's automatic thread switch), and a script that runs MAX_STEPS times this without
#: returning or yielding is stopped as an endless loop, naming its line.
STEP_BUDGET = 200_000
MAX_STEPS = 50
MAX_MEMORY = 256 << 20  # bytes for all the script states of one run together (issue 33)
MAX_DISK = 64 << 20  # bytes the scripts of one run may write to its temporary folder
TMP_PREFIX = "sitegen-lua-"


class _RunMemory:
    """The states of one run (they share its temporary folder) and the memory they hold: each
    state may grow only into what the others leave of ``MAX_MEMORY`` (16 scripts of a scene
    took 16 times 256 MiB when the limit was per state)."""

    def __init__(self) -> None:
        self.states: list[Any] = []
        self.written = 0  # bytes the run's scripts wrote to its temporary folder

    def take_disk(self, n: int) -> bool:
        """Count ``n`` more bytes written; False (not counted) past ``MAX_DISK``."""
        if self.written + n > MAX_DISK:
            return False
        self.written += n
        return True

    def limit_for(self, state: Any) -> int:
        others = 0
        for ref in self.states:
            other = ref()
            if other is not None and other is not state:
                others += other.lua.get_memory_used() or 0
        return max(1 << 20, MAX_MEMORY - others)

    def alive(self) -> bool:
        return any(ref() is not None for ref in self.states)


_RUNS: dict[str, _RunMemory] = {}


def _run_memory(tmp_dir: str) -> _RunMemory:
    for key in [k for k, run in _RUNS.items() if not run.alive()]:
        del _RUNS[key]  # runs whose states are all gone
    return _RUNS.setdefault(tmp_dir, _RunMemory())


class LuaScriptError(Exception):
    """A script raised a Lua error (the message starts with ``script:line:``)."""


def _deny(obj: Any, name: Any, setting: bool) -> Any:
    raise AttributeError("Python attributes are not reachable from scene scripts")


class LuaState:
    """A sandboxed Lua 5.4 interpreter for one script."""

    def __init__(
        self, tmp_dir: str, missing: Callable[[str, int], None], modules: str | None = None
    ):
        self.lua = lua54.LuaRuntime(
            encoding=None,
            register_eval=False,
            register_builtins=False,
            unpack_returned_tuples=True,
            attribute_filter=_deny,
            max_memory=MAX_MEMORY,
        )
        py = self.table_of(
            {"step_budget": STEP_BUDGET, "max_steps": MAX_STEPS},
        )
        py[b"missing"] = lambda name, line: missing(_text(name), int(line))
        py[b"module_text"] = lambda name: module_text(modules, _text(name))
        self.err = self.lua.table()
        tmp = str(tmp_dir).rstrip("/").encode()
        self.run_memory = _run_memory(str(tmp_dir))
        self.run_memory.states.append(weakref.ref(self))
        py[b"take_disk"] = lambda n: self.run_memory.take_disk(int(n))
        # loaded as the chunk "=prelude", so that debug.getinfo can tell its frames
        prelude = self.lua.globals()[b"load"](PRELUDE.encode(), b"=prelude", b"t")
        self.rt = prelude(py, self.err, tmp, True)
        self.g = self.lua.globals()

    def _share_memory(self) -> None:
        """Before the script runs: its limit is what the run's other states leave."""
        self.lua.set_max_memory(self.run_memory.limit_for(self))

    # -- values --------------------------------------------------------------------------------
    def table_of(self, mapping: dict) -> Any:
        t = self.lua.table()
        for k, v in mapping.items():
            t[k.encode() if isinstance(k, str) else k] = self.to_lua(v)
        return t

    def to_lua(self, value: Any) -> Any:
        if isinstance(value, (int, float)):  # the common case first: sim.* calls return numbers
            return value
        if isinstance(value, str):
            return value.encode("utf-8")
        if isinstance(value, bytearray):
            return bytes(value)
        if isinstance(value, (list, tuple)):  # one lupa call fills the array part
            if all(type(v) is float for v in value):  # a vector: nothing to convert
                return self.lua.table(*value)
            return self.lua.table(*[self.to_lua(v) for v in value])
        if isinstance(value, dict):
            return self.table_of(value)
        return value

    def fail(self, message: str) -> tuple:
        """What a sim.* Python function returns to make its Lua wrapper raise ``message``."""
        return (self.err, message)

    def set_function(self, table: Any, name: str, fn: Callable, threaded: bool, label: str) -> None:
        table[name.encode()] = self.rt.wrap(fn, label.encode(), threaded)

    def module(self, name: str) -> Any:
        """A table whose unknown members are reported stubs (``sim``, ``simUI``...)."""
        t = self.rt.module(name.encode(), self.lua.table())
        self.g[name.encode()] = t
        return t

    # -- running -------------------------------------------------------------------------------
    def compile(self, text: str, name: str) -> Any:
        out = self.rt.compile(text.encode("utf-8"), name.encode("utf-8"))
        fn, err = out if isinstance(out, tuple) else (out, None)
        if fn is None:
            raise LuaScriptError(_text(err))
        return fn

    def call(self, fn: Any, *args: Any) -> tuple:
        """Run ``fn`` to its end; its results, or LuaScriptError with the script's line."""
        self._share_memory()
        out = self.rt.call(fn, *[self.to_lua(a) for a in args])
        if not isinstance(out, tuple):
            out = (out,)
        if not out[0]:
            raise LuaScriptError(_text(out[1]) if len(out) > 1 else "error")
        return out[1:]

    def section(self, fn: Any, call_type: int) -> None:
        """Run an old-style chunk with ``sim_call_type`` = ``call_type``."""
        self._share_memory()
        out = self.rt.section(fn, call_type)
        if isinstance(out, tuple) and not out[0]:
            raise LuaScriptError(_text(out[1]) if len(out) > 1 else "error")
        if out is False:
            raise LuaScriptError("error")

    def thread(self, fn: Any) -> Any:
        return self.rt.thread(fn)

    def resume(self, co: Any) -> str:
        """Resume a threaded script; "suspended" (it yielded) or "dead" (it ended)."""
        self._share_memory()
        out = self.rt.resume(co)
        ok, status = out if isinstance(out, tuple) else (out, None)
        if not ok:
            raise LuaScriptError(_text(status))
        return _text(status)

    def get(self, name: str) -> Any:
        return self.g[name.encode()]

    def set(self, name: str, value: Any) -> None:
        self.g[name.encode()] = self.to_lua(value)


def _text(value: Any) -> str:
    if isinstance(value, bytes):
        return value.decode("utf-8", "replace")
    return str(value)


def to_py(value: Any) -> Any:
    """A Lua value as Python: strings stay bytes; a table becomes a list (1..n) or a dict."""
    if lua54.lua_type(value) == "table":
        keys = list(value.keys())
        n = len(keys)
        if all(isinstance(k, int) for k in keys) and set(keys) == set(range(1, n + 1)):
            return [to_py(value[i]) for i in range(1, n + 1)]
        return {(_text(k) if isinstance(k, bytes) else k): to_py(v) for k, v in value.items()}
    return value


def numbers(value: Any) -> list[float]:
    """A Lua table of numbers as a list of floats (None, or a non-table: empty)."""
    if lua54.lua_type(value) != "table":
        return []
    return [float(v) for v in to_py(value) if isinstance(v, (int, float))]


def text(value: Any) -> str:
    return _text(value)


def module_text(folder: str | None, name: str) -> tuple[Any, Any]:
    """(source, chunk name) of the Lua module ``name`` (``a.b`` -> ``a/b.lua``) in the scene's
    folder, or (None, why): the sandbox reads nothing else, and no name may climb out."""
    if folder is None:
        return None, b"the scene has no folder"
    parts = name.split(".")
    if not name or any(not p or p in (".", "..") or "/" in p or "\\" in p for p in parts):
        return None, b"not a module name"
    base = Path(folder)
    path = base.joinpath(*parts[:-1], parts[-1] + ".lua")
    try:
        resolved = path.resolve()
        resolved.relative_to(base.resolve())
        return resolved.read_bytes(), ("@" + path.name).encode()
    except (OSError, ValueError):
        return None, f"no file {path.name} beside the scene".encode()


def run_tmp_dir() -> tempfile.TemporaryDirectory:
    """A run's temporary folder (``sitegen-lua-PID-...``), after removing those of runs whose
    process is gone (a killed run cannot remove its own). Folders of older versions (no process
    number in the name) are removed once a day old."""
    root = Path(tempfile.gettempdir())
    with contextlib.suppress(OSError):
        for folder in root.glob(f"{TMP_PREFIX}*"):
            pid = folder.name[len(TMP_PREFIX) :].split("-", 1)[0]
            stale = False
            if pid.isdigit():
                stale = Path("/proc/self").exists() and not Path(f"/proc/{pid}").exists()
            else:
                with contextlib.suppress(OSError):
                    stale = time.time() - folder.stat().st_mtime > 86400
            if stale and folder.is_dir() and not folder.is_symlink():
                shutil.rmtree(folder, ignore_errors=True)
    return tempfile.TemporaryDirectory(prefix=f"{TMP_PREFIX}{os.getpid()}-")
