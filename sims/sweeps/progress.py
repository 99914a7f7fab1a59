"""A sweep's progress on a terminal: runs done, failed, running, rate and time left.

On a terminal one line is redrawn in place (at most every 0.2 s); elsewhere (a CI log) a line
is printed every ``every`` seconds and at the end. A failed run is printed once, with its error,
as it ends: the sweep goes on.
"""

from __future__ import annotations

import sys
import time
from typing import Any, TextIO


def _duration(seconds: float) -> str:
    seconds = int(round(seconds))
    if seconds >= 3600:
        return f"{seconds // 3600} h {seconds % 3600 // 60:02d} min"
    if seconds >= 60:
        return f"{seconds // 60} min {seconds % 60:02d} s"
    return f"{seconds} s"


class SweepProgress:
    def __init__(
        self,
        total: int,
        stream: TextIO | None = None,
        live: bool | None = None,
        every: float = 10.0,
        quiet: bool = False,
    ):
        """``quiet``: failed runs only, no progress line."""
        self.total = total
        self.stream = stream or sys.stderr
        self.quiet = quiet
        self.live = self.stream.isatty() if live is None else live
        self.every = every
        self.done = self.failed = 0
        self.running: set[int] = set()
        self.start = time.monotonic()
        self._shown = 0.0
        self._width = 0
        self._closed = False

    def started(self, index: int) -> None:
        self.running.add(index)
        self._show()

    def finished(self, record: dict[str, Any]) -> None:
        self.running.discard(record["index"])
        self.done += 1
        if record["status"] not in ("ok", "cut"):
            self.failed += 1
            self._print(f"run {record['index']} {record['status']}: {record['error']}")
        self._show()

    def line(self) -> str:
        elapsed = max(1e-9, time.monotonic() - self.start)
        rate = self.done / elapsed
        left = (self.total - self.done) / rate if rate > 0 else None
        text = (
            f"runs: {self.done}/{self.total} done, {self.failed} failed, "
            f"{len(self.running)} running, {rate:.2f} runs/s"
        )
        if self.done < self.total:
            text += f", about {_duration(left)} left" if left is not None else ""
        else:
            text += f", {_duration(elapsed)}"
        return text

    def _print(self, text: str) -> None:
        if self.live and self._width:
            self.stream.write("\r" + " " * self._width + "\r")
            self._width = 0
        self.stream.write(text + "\n")
        self.stream.flush()

    def _show(self, force: bool = False) -> None:
        if self.quiet:
            return
        now = time.monotonic()
        if self.live:
            if force or now - self._shown >= 0.2:
                text = self.line()
                self.stream.write("\r" + text.ljust(self._width))
                self.stream.flush()
                self._width, self._shown = len(text), now
        elif force or now - self._shown >= self.every:
            if force or self.done:
                self._print(self.line())
            self._shown = now

    def close(self) -> None:
        if self.quiet or self._closed:
            return
        self._closed = True
        self._show(force=True)
        if self.live:
            self.stream.write("\n")
            self._width = 0
            self.stream.flush()
