"""Silence C-level output from pybullet, its EGL plugin and FFmpeg.

pybullet prints "pybullet build time: ..." on import (fd 2), the EGL plugin prints driver
details (fd 1) and FFmpeg warns (fd 2), all through C stdio. That noise would break the
CLI's one-line-per-clip output. Redirecting the descriptor is not enough on its own: C stdio
buffers, so its buffers are flushed (``fflush(NULL)``) before the descriptor is restored.

Import pybullet as ``from sims.quiet import pybullet as p`` to get it imported silently.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
import sys
from collections.abc import Iterator

try:
    _libc: ctypes.CDLL | None = ctypes.CDLL(None)
except OSError:  # not a POSIX libc: skip the C flush
    _libc = None


def _flush_c() -> None:
    if _libc is not None:
        try:
            _libc.fflush(None)
        except Exception:
            pass


@contextlib.contextmanager
def quiet_fd(fd: int) -> Iterator[None]:
    """Send what is written to ``fd`` (1 or 2) inside the block to /dev/null."""
    try:
        (sys.stdout if fd == 1 else sys.stderr).flush()
        saved = os.dup(fd)
    except (OSError, ValueError, AttributeError):
        yield
        return
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, fd)
        yield
    finally:
        _flush_c()
        os.dup2(saved, fd)
        os.close(saved)
        os.close(devnull)


with quiet_fd(1), quiet_fd(2):
    import pybullet  # noqa: E402

__all__ = ["pybullet", "quiet_fd"]
