"""The schedule of one ``render_clips`` call: every clip's jobs handed to the worker pool.

A clip is three kinds of job (sims/clip_worker.py): *simulate* first, which unlocks one *render*
job per frame range, and *encode* once every range is drawn. Simulations are handed out first
(longest clip first), then encodes, then the ranges of the clip a worker drew last (its World is
still built), so one long clip's ranges keep every core busy. Each step is reported as a
:class:`ClipEvent` to the caller's progress callback (sitegen/progress.py draws them).
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from sims.clip_pool import Job, make_pool
from sims.clip_spec import ClipSpec
from sims.clip_worker import RANGE_FRAMES, ClipJob, range_starts


@dataclass(frozen=True)
class ClipEvent:
    name: str
    status: str  # "queued", "started", "progress", "done", "failed" or "cached"
    seconds: float = 0.0
    error: str | None = None
    frames: int = 0  # frames drawn so far (progress/done)
    total: int = 0  # frames of the clip
    phase: str = ""  # "simulating", "rendering", "encoding"
    remembered: bool = False


Progress = Callable[[ClipEvent], None]


@dataclass(eq=False)
class ClipRun:
    """One clip being rendered: its cache key and folder, its jobs, frames drawn per range,
    its outcome (``outcome``: the meta of a finished clip; ``error``: why it failed)."""

    index: int
    spec: ClipSpec
    key: str
    target: str
    tmp: Path
    total: int
    limit: float
    started: float = 0.0
    meta: dict[str, Any] = field(default_factory=dict)
    starts: list[int] = field(default_factory=list)
    drawn: dict[int, int] = field(default_factory=dict)
    waiting: list[Job] = field(default_factory=list)  # ranges not yet handed out
    running: int = 0
    renderers: set[str] = field(default_factory=set)
    fallbacks: set[str] = field(default_factory=set)  # why EGL fell back, per frame range
    phase: str = "simulating"
    error: str | None = None
    outcome: dict[str, Any] | None = None


def run_clips(todo: list[ClipRun], jobs: int | None, notify: Progress) -> Iterator[ClipRun]:
    """Run every clip's jobs on a pool; yields each clip once its outcome is known."""
    ids = iter(range(1, 1 << 62))
    simulations = [
        Job(next(ids), _payload(c, "simulate"), c.limit, owner=c)
        for c in sorted(todo, key=lambda c: -c.total * c.spec.width * c.spec.height)
    ]
    ready: list[Job] = []  # encodes, then ranges
    open_clips = set(todo)

    def next_job(last: ClipRun | None) -> Job | None:
        if ready and ready[0].payload.phase == "encode":
            return ready.pop(0)
        if simulations:
            job = simulations.pop(0)
            job.owner.started = time.monotonic()
            notify(ClipEvent(job.owner.spec.name, "started", total=job.owner.total))
            return job
        for job in ready:  # the ranges of the clip this worker drew last: its World is ready
            if job.owner is last:
                ready.remove(job)
                return job
        return ready.pop(0) if ready else None

    def on_progress(job: Job) -> None:
        clip: ClipRun = job.owner
        if job.payload.phase == "render":
            clip.drawn[job.payload.start] = job.progress
            _tell(clip, notify)

    # every clip is at least one job (its simulation; a replay-only clip has no frames to
    # draw), so a site of replays gets as many workers as clips, up to the cores
    workers = max(1, min(jobs or os.cpu_count() or 1, sum(max(1, c.total) for c in todo)))
    log_dir = Path(tempfile.mkdtemp(prefix=".workers-", dir=todo[0].tmp.parent))
    pool = make_pool(workers, log_dir)  # local workers or Ray (sims.clip_pool.EXECUTOR)
    try:
        for job, outcome in pool.run(next_job, lambda: bool(simulations or ready), on_progress):
            clip: ClipRun = job.owner
            if clip not in open_clips:
                continue
            if not outcome.get("ok"):
                error = str(outcome.get("error") or "failed")
                label = _label(clip.spec)
                clip.error = error if error.startswith(label) else f"{label} {error}"
                ready[:] = [j for j in ready if j.owner is not clip]
            else:
                _advance(clip, job, outcome["result"], ready, ids, notify)
            if clip.error is not None or clip.outcome is not None:
                open_clips.discard(clip)
                yield clip
    finally:  # interrupted (Ctrl-C, an exception in a progress callback): leave no workers
        pool.close()
        shutil.rmtree(log_dir, ignore_errors=True)
        for clip in open_clips:
            shutil.rmtree(clip.tmp, ignore_errors=True)


def _advance(
    clip: ClipRun, job: Job, result: dict[str, Any], ready: list[Job], ids, notify
) -> None:
    """A job of ``clip`` succeeded: queue what it unlocks."""
    phase = job.payload.phase
    if phase == "simulate" and "files" in result:  # a replay without video: complete
        clip.outcome = result
    elif phase == "simulate":
        clip.meta = result
        clip.total = result["frames"]
        clip.starts = range_starts(clip.total, RANGE_FRAMES)
        clip.phase = "rendering"
        for start in clip.starts:
            stop = min(start + RANGE_FRAMES, clip.total)
            payload = replace(
                _payload(clip, "render"), start=start, stop=stop, follow=result["follow"]
            )
            ready.append(Job(next(ids), payload, clip.limit, owner=clip))
        clip.running = len(clip.starts)
        _tell(clip, notify)
    elif phase == "render":
        clip.drawn[job.payload.start] = result["frames"]
        clip.renderers.add(result["renderer"])
        if result.get("fallback"):
            clip.fallbacks.add(result["fallback"])
        clip.running -= 1
        _tell(clip, notify)
        if clip.running == 0:
            clip.phase = "encoding"
            payload = replace(
                _payload(clip, "encode"),
                meta=clip.meta,
                starts=clip.starts,
                renderer="+".join(sorted(clip.renderers)),
            )
            ready.insert(0, Job(next(ids), payload, clip.limit, owner=clip))
            _tell(clip, notify)
    else:
        clip.outcome = result


def _tell(clip: ClipRun, notify: Progress) -> None:
    notify(
        ClipEvent(
            clip.spec.name,
            "progress",
            seconds=time.monotonic() - clip.started,
            frames=sum(clip.drawn.values()),
            total=clip.total,
            phase=clip.phase,
        )
    )


def _payload(clip: ClipRun, phase: str) -> ClipJob:
    return ClipJob(phase, clip.spec, clip.target, str(clip.tmp))


def _label(spec: ClipSpec) -> str:
    return f"{spec.kind} {spec.label or spec.scenario!r}"
