"""Feedback while clips render: a live display on a terminal, plain lines in CI and pipes.

``sims`` only emits events (:class:`sims.clips.ClipEvent`); this module decides how a person
sees them. On a terminal: one bar for the frames of all clips (frames drawn of frames to draw,
elapsed and remaining time) and one row per clip with its state (queued, simulating, rendering,
encoding, done, cached, failed), redrawn ten times a second from the first moment, so a long
first build is never silent. Elsewhere: one line when a clip starts and one when it ends, with
its frames per second, so a CI log tells where the time went.

The live display uses `rich <https://github.com/Textualize/rich>`_ (``rich.progress``): it
handles terminal width, redraw without flicker, Unicode bars and cleanup on exit, which would
otherwise be hand-written escape codes; it is only imported on a terminal.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

STATES = {"simulating": "simulating", "rendering": "rendering", "encoding": "encoding"}


@dataclass
class _Row:
    task: Any = None
    total: int = 0
    frames: int = 0
    started: float = 0.0


class ClipProgress:
    """Callable with each ClipEvent; ``close()`` when rendering ends (also on errors)."""

    def __init__(self, live: bool, log: Callable[[str], None]):
        self.live = live
        self.log = log
        self.rows: dict[str, _Row] = {}
        self._progress: Any = None
        self._overall: Any = None  # the live display starts with the first clip to render

    # -- terminal ---------------------------------------------------------------------------
    def _start_live(self) -> None:
        from rich.console import Console
        from rich.progress import (
            BarColumn,
            MofNCompleteColumn,
            Progress,
            TextColumn,
            TimeElapsedColumn,
            TimeRemainingColumn,
        )

        self._progress = Progress(
            TextColumn("{task.description:<22}"),
            BarColumn(bar_width=28),
            MofNCompleteColumn(),
            TextColumn("frames"),
            TextColumn("{task.fields[state]:<11}"),
            TimeElapsedColumn(),
            TextColumn("left"),
            TimeRemainingColumn(),
            console=Console(stderr=True),
            refresh_per_second=10,
        )
        self._overall = self._progress.add_task("clips", total=0, state="starting")
        self._progress.start()

    def _update(self, name: str, **fields: Any) -> None:
        """Update the clip's row (a row exists for clips being rendered, from "queued" on)."""
        row = self.rows[name]
        if self._progress is None:
            return
        if row.task is None and fields.get("state") == "queued":
            row.task = self._progress.add_task(name[:22], total=max(row.total, 1), state="queued")
        if row.task is not None:
            self._progress.update(row.task, **fields)
        done = sum(r.frames for r in self.rows.values())
        total = sum(r.total for r in self.rows.values())
        working = sum(1 for r in self.rows.values() if r.started and r.frames < r.total)
        self._progress.update(
            self._overall, completed=done, total=max(total, 1), state=f"{working} running"
        )

    # -- events -----------------------------------------------------------------------------
    def __call__(self, event: Any) -> None:
        row = self.rows.setdefault(event.name, _Row())
        status = event.status
        if event.total:
            row.total = event.total
        if status == "queued":
            if self.live and self._progress is None:
                self._start_live()
            self._update(event.name, total=max(row.total, 1), state="queued")
        elif status == "started":
            row.started = time.monotonic()
            self._update(event.name, state="simulating")
            if not self.live:  # a replay alone draws no frames
                what = f"{row.total} frames" if row.total else "replay"
                self.log(f"clip {event.name}: started ({what})")
        elif status == "progress":
            row.frames = event.frames
            self._update(event.name, completed=event.frames, state=STATES.get(event.phase, ""))
        elif status == "done":
            row.frames = row.total = event.frames or row.total
            rate = row.frames / event.seconds if event.seconds > 0 else 0.0
            self._update(event.name, completed=row.frames, total=row.total, state="done")
            if not row.frames:
                self._say(f"clip {event.name}: done, replay in {event.seconds:.1f} s")
                return
            line = f"clip {event.name}: done, {row.frames} frames in {event.seconds:.1f} s"
            self._say(f"{line} ({rate:.1f} frames/s)")
        elif status == "cached":
            row.total = row.frames = 0  # nothing to draw: not part of the frames to do
            self._say(f"clip {event.name}: cached")
        elif status == "failed":
            row.total = row.frames = 0  # its frames will not come
            self._update(event.name, state="failed")
            how = "FAILED (remembered)" if event.remembered else "FAILED"
            self._say(f"clip {event.name}: {how}: {event.error}")

    def _say(self, line: str) -> None:
        if self._progress is not None:
            self._progress.console.print(line, markup=False, highlight=False)
        else:
            self.log(line)

    def close(self) -> None:
        if self._progress is not None:
            self._progress.stop()
            self._progress = None
