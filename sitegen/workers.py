"""Both cores for a big build: forked worker processes that inherit the build's state.

A cold build spends its time converting Markdown and rendering pages, one page at a time and
independently of the others, so the work is split into chunks of pages handed to worker
processes. Workers are forked *after* the build has read the site, so they start in a few
milliseconds and already hold everything (site tree, theme, link targets); only chunk numbers
go to them and only small results come back. Results are returned in task order whatever the
scheduling, so the output does not depend on which worker finished first.

Small jobs (an incremental build, a small site) run in the build's own process: starting
workers costs more than it saves below :data:`MIN_PARALLEL` tasks. Where ``fork`` is not
available (Windows, macOS' default), everything runs in one process.
"""

from __future__ import annotations

import gc
import os
import sys
from collections.abc import Callable, Sequence
from typing import Any

#: Fewer tasks than this run in-process: forking and collecting results cost ~20 ms, and a
#: page costs ~3 ms, so below ~64 pages the second core does not pay for itself.
MIN_PARALLEL = 64
#: Tasks per chunk sent to a worker: big enough to keep messages few, small enough to balance.
CHUNK = 16

#: Chunks a worker handles before a fresh one is forked in its place: a worker's memory grows
#: as it touches (and so copies) pages it shares with the build; a fork costs ~5 ms.
RECYCLE = 16

_JOB: Callable[[Sequence[Any]], list[Any]] | None = None
_TASKS: Sequence[Any] = ()


def jobs_wanted() -> int:
    """Worker count: ``SITEGEN_JOBS`` if set (1 turns workers off), else the usable cores."""
    env = os.environ.get("SITEGEN_JOBS", "").strip()
    if env.isdigit() and int(env) > 0:
        return int(env)
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _fork_available() -> bool:
    # imported here: a build small enough for one process (a page edit) never needs it (~9 ms)
    import multiprocessing

    return sys.platform.startswith("linux") and "fork" in multiprocessing.get_all_start_methods()


def _run_chunk(bounds: tuple[int, int]) -> list[Any]:
    assert _JOB is not None
    return _JOB(_TASKS[bounds[0] : bounds[1]])


def run_chunks(
    tasks: Sequence[Any],
    job: Callable[[Sequence[Any]], list[Any]],
    jobs: int | None = None,
    recycle: int | None = RECYCLE,
) -> list[Any]:
    """``job`` over consecutive chunks of ``tasks``; the concatenated results in task order.

    ``job`` may be a closure: workers are forked with it in place, nothing is pickled but the
    chunk bounds and the results. ``recycle``: chunks per worker before a fresh fork (None:
    never, for jobs whose workers are costly to set up).
    """
    global _JOB, _TASKS
    jobs = jobs or jobs_wanted()
    if jobs < 2 or len(tasks) < MIN_PARALLEL or not _fork_available():
        return job(tasks)
    bounds = [(i, min(i + CHUNK, len(tasks))) for i in range(0, len(tasks), CHUNK)]
    _JOB, _TASKS = job, tasks
    gc.collect()
    gc.freeze()  # the workers' collector then never writes to (and so copies) inherited pages
    try:
        import multiprocessing

        ctx = multiprocessing.get_context("fork")
        # the build pauses the collector (sitegen.build.collector_paused); a worker, which
        # makes its own garbage page after page, turns it back on
        with ctx.Pool(min(jobs, len(bounds)), gc.enable, maxtasksperchild=recycle) as pool:
            out: list[Any] = []
            for part in pool.imap(_run_chunk, bounds):
                out.extend(part)
            return out
    finally:
        gc.unfreeze()
        _JOB, _TASKS = None, ()
