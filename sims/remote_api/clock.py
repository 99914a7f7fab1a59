"""The clock a script lives by: virtual by default, or paced by the wall clock.

While a script runs (``patch_time``), ``time.sleep``/``time.time``/``time.monotonic``/
``time.perf_counter`` (and their ``_ns`` forms) called from the script's thread follow the run's
clock; other threads, and sitegen's own ``sims`` code (recorder deadlines), keep the real ones. A
virtual sleep lets simulated time pass at once: the simulator steps the world through it, so an
80 s script finishes in a few wall seconds.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
import time as _time
from collections.abc import Callable, Iterator

# The real functions, taken before anything is patched.
real_time = _time.time
real_monotonic = _time.monotonic
real_perf_counter = _time.perf_counter
real_sleep = _time.sleep

#: Code in this directory (the ``sims`` package: recorder, renderer...) keeps the real clock.
LIBRARY_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__))) + os.sep

#: Virtual seconds a clock read costs, so that a busy-wait loop on time.time() makes progress.
READ_COST = 1e-4


class ScriptTimeout(BaseException):
    """Raised inside a script that ran past its time limit (BaseException: ``except Exception``
    in the script does not swallow it)."""

    def __init__(self, message: str = "time limit reached"):
        super().__init__(message)
        self.message = message


class Clock:
    """Seconds since the run started. ``listener`` is called whenever time has passed."""

    realtime = False

    def __init__(self, limit: float | None = None):
        self.limit = limit
        self.listener: Callable[[], None] | None = None
        self.epoch = real_time()
        self.timed_out = False

    def now(self) -> float:
        raise NotImplementedError

    def advance(self, seconds: float) -> None:
        raise NotImplementedError

    def read(self) -> float:
        """A clock read by the script (``time.time()`` and friends)."""
        return self.now()

    def _notify(self) -> None:
        if self.listener is not None:
            self.listener()

    def check(self) -> None:
        if self.limit is not None and self.now() > self.limit:
            self.timed_out = True
            raise ScriptTimeout(f"time limit of {self.limit:g} s reached")


class VirtualClock(Clock):
    """Time that passes only when the script sleeps or calls the API."""

    def __init__(self, limit: float | None = None):
        super().__init__(limit)
        self._t = 0.0

    def now(self) -> float:
        return self._t

    def read(self) -> float:
        self._t += READ_COST
        self.check()
        return self._t

    def advance(self, seconds: float) -> None:
        if seconds > 0:
            self._t += seconds
            self._notify()
        self.check()


class WallClock(Clock):
    """Real time: sleeping really sleeps, in slices, so the world keeps pace. ``scale`` > 1
    runs the clock faster than the wall clock (2: two clock seconds per wall second)."""

    realtime = True
    slice = 0.02

    def __init__(self, limit: float | None = None, scale: float = 1.0):
        super().__init__(limit)
        if not 0 < scale < float("inf"):
            raise ValueError(f"clock scale must be a positive number, not {scale!r}")
        self.scale = float(scale)
        self._start = real_monotonic()

    def now(self) -> float:
        return (real_monotonic() - self._start) * self.scale

    def advance(self, seconds: float) -> None:
        end = self.now() + max(0.0, seconds)
        while True:
            self.check()
            left = end - self.now()
            if left <= 0:
                break
            real_sleep(min(left / self.scale, self.slice))
            self._notify()
        self._notify()


@contextlib.contextmanager
def patch_time(clock: Clock, thread_id: int | None = None) -> Iterator[None]:
    """Make the ``time`` module follow ``clock`` in the given thread (default: this one)."""
    owner = threading.get_ident() if thread_id is None else thread_id
    mono_epoch, perf_epoch = real_monotonic(), real_perf_counter()
    saved = {
        name: getattr(_time, name)
        for name in (
            "time",
            "time_ns",
            "monotonic",
            "monotonic_ns",
            "perf_counter",
            "perf_counter_ns",
            "sleep",
        )
    }

    def mine() -> bool:
        """Called by the script (its thread, and not from sitegen's own sims package)?"""
        if threading.get_ident() != owner:
            return False
        caller = sys._getframe(2).f_code.co_filename
        return not caller.startswith(LIBRARY_DIR)

    def v_time() -> float:
        return clock.epoch + clock.read() if mine() else saved["time"]()

    def v_time_ns() -> int:
        return int(v_time() * 1e9) if mine() else saved["time_ns"]()

    def v_monotonic() -> float:
        return mono_epoch + clock.read() if mine() else saved["monotonic"]()

    def v_monotonic_ns() -> int:
        return int(v_monotonic() * 1e9) if mine() else saved["monotonic_ns"]()

    def v_perf_counter() -> float:
        return perf_epoch + clock.read() if mine() else saved["perf_counter"]()

    def v_perf_counter_ns() -> int:
        return int(v_perf_counter() * 1e9) if mine() else saved["perf_counter_ns"]()

    def v_sleep(seconds: float) -> None:
        if not mine():
            return saved["sleep"](seconds)
        seconds = float(seconds)
        if seconds < 0:
            raise ValueError("sleep length must be non-negative")
        clock.advance(seconds)

    patched = {
        "time": v_time,
        "time_ns": v_time_ns,
        "monotonic": v_monotonic,
        "monotonic_ns": v_monotonic_ns,
        "perf_counter": v_perf_counter,
        "perf_counter_ns": v_perf_counter_ns,
        "sleep": v_sleep,
    }
    for name, fn in patched.items():
        setattr(_time, name, fn)
    try:
        yield
    finally:
        for name, fn in saved.items():
            setattr(_time, name, fn)
