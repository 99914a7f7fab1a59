"""The local executor: worker processes on this machine, one run at a time each.

The workers are sims/clip_pool.py's (long-lived ``python -m sims.sweeps.worker`` processes fed
over pipes, killed and replaced past a deadline, a crash failing only the job it ran), so a
sweep needs nothing installed and never re-imports the caller's ``__main__``. A run whose
worker died is run again on a fresh worker, up to ``retries`` times, then recorded as lost.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections import deque
from collections.abc import Callable, Iterator
from itertools import count
from pathlib import Path
from typing import Any

from sims.clip_pool import Job, Pool

from .one_run import lost_record

MODULE = "sims.sweeps.worker"
DEADLINE_SLACK = 60.0  # s past a run's own limits before its worker is killed (a safety net)
KILL_GRACE = 15.0  # the runner's own grace past a run's wall-clock limit


class LocalExecutor:
    """``workers`` processes (default: every core)."""

    name = "local"

    def __init__(self, workers: int | None = None, retries: int = 2):
        self.workers = max(1, workers or os.cpu_count() or 1)
        self.retries = retries
        self._pool: Pool | None = None  # kept between run() calls (an optimiser's generations)
        self._log_dir: str | None = None

    def __enter__(self) -> LocalExecutor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def describe(self) -> str:
        return f"local, {self.workers} worker{'s' if self.workers != 1 else ''}"

    def run(
        self, jobs: list[dict[str, Any]], started: Callable[[int], None] | None = None
    ) -> Iterator[dict[str, Any]]:
        """Yields each run's record as it ends (in any order)."""
        queue = deque(jobs)
        tries: dict[int, int] = {}
        ids = count(1)

        def next_job(_last: Any) -> Job | None:
            if not queue:
                return None
            job = queue.popleft()
            if started is not None:
                started(job["index"])
            limit = job["timeout"] + max(0.0, job["after"]) + KILL_GRACE + DEADLINE_SLACK
            return Job(next(ids), job, limit, owner=job)

        if self._pool is None:
            self._log_dir = tempfile.mkdtemp(prefix="sitegen-sweep-workers-")
            self._pool = Pool(self.workers, log_dir=Path(self._log_dir), module=MODULE)
        pool = self._pool
        try:
            for job, outcome in pool.run(next_job, lambda: bool(queue), lambda _j: None):
                spec = job.owner
                index = spec["index"]
                tries[index] = tries.get(index, 0) + 1
                if outcome.get("ok"):
                    record = outcome["result"]
                    record["attempts"] = tries[index]
                    yield record
                elif outcome.get("killed"):
                    yield lost_record(spec, f"{outcome.get('error')}", "timeout", tries[index])
                elif tries[index] <= self.retries:
                    queue.appendleft(spec)  # the worker died under it: again, on a new one
                else:
                    yield lost_record(spec, f"worker {outcome.get('error')}", "lost", tries[index])
        except BaseException:  # interrupted: no worker keeps running a run nobody waits for
            self.close()
            raise

    def close(self) -> None:
        if self._pool is not None:
            self._pool.close()
            self._pool = None
        if self._log_dir is not None:
            shutil.rmtree(self._log_dir, ignore_errors=True)
            self._log_dir = None
