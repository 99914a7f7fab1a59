"""Worker processes for clip jobs, and the scheduler that keeps every one of them busy.

Workers are long-lived ``python -m sims.clip_worker`` subprocesses (not multiprocessing: spawn
and forkserver re-import the caller's ``__main__``, so a script calling render_clips without an
``if __name__ == "__main__"`` guard would recurse). Each takes one job at a time over a pipe and
reports progress and its result as JSON lines. A job that passes its wall-clock limit (plus a
grace period) gets its worker killed and replaced; a worker that dies fails only its job.

The scheduler (:class:`Pool.run`) asks a ``next_job(worker)`` callback for work whenever a
worker is idle, so the caller decides the order (simulations first, then frame ranges, the
ranges of the clip a worker just drew first) and can add jobs as earlier ones finish.
"""

from __future__ import annotations

import json
import os
import selectors
import subprocess
import sys
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

KILL_GRACE = 15.0  # at most this long past a job's limit before its worker is killed
START_LIMIT = 300.0  # a worker that has not finished its imports by then is killed


@dataclass
class Job:
    """One unit of work for a worker; ``payload`` is what the worker receives: a dict, or a
    record whose ``message()`` gives it (sims.clip_worker.ClipJob)."""

    id: int
    payload: Any
    limit: float  # wall-clock seconds
    owner: Any = None  # the caller's record (the clip this job belongs to)
    started: float = 0.0
    progress: int = 0

    def message(self) -> dict[str, Any]:
        """What a worker receives (one JSON line): the payload, the id and the limit."""
        payload = self.payload.message() if hasattr(self.payload, "message") else self.payload
        return {**payload, "id": self.id, "time_limit": self.limit}


@dataclass
class Worker:
    process: subprocess.Popen
    log: Path
    buffer: bytes = b""
    job: Job | None = None
    last_owner: Any = None
    ready: bool = False  # imports done: a job's wall clock starts when its worker is ready
    spawned: float = field(default_factory=time.monotonic)


def worker_env() -> dict[str, str]:
    """The parent's import path, so registered source modules import in the worker too."""
    from sims.clip_cache import ROOT_DIR

    env = dict(os.environ)
    paths = [str(ROOT_DIR)] + [p for p in sys.path if p and os.path.isdir(p)]
    env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    return env


class Pool:
    """Up to ``size`` workers; logs go to ``log_dir``. ``module``: what each worker runs
    (``python -m MODULE``, speaking the protocol above; sweeps use sims.sweeps.worker)."""

    def __init__(self, size: int, log_dir: Path, module: str = "sims.clip_worker"):
        self.size = size
        self.module = module
        self.log_dir = log_dir
        self.env = worker_env()
        self.workers: list[Worker] = []
        self.selector = selectors.DefaultSelector()
        self._spawned = 0

    def _spawn(self) -> Worker:
        self._spawned += 1
        log = self.log_dir / f"worker-{self._spawned}.log"
        with open(log, "wb") as err:
            process = subprocess.Popen(
                [sys.executable, "-m", self.module],
                stdin=subprocess.PIPE,
                stdout=subprocess.PIPE,
                stderr=err,
                env=self.env,
            )
        worker = Worker(process, log)
        os.set_blocking(process.stdout.fileno(), False)
        self.selector.register(process.stdout, selectors.EVENT_READ, worker)
        self.workers.append(worker)
        return worker

    def _retire(self, worker: Worker, kill: bool) -> None:
        self.selector.unregister(worker.process.stdout)
        if kill and worker.process.poll() is None:
            worker.process.kill()
        try:
            worker.process.stdin.close()
        except OSError:
            pass
        worker.process.wait()
        worker.process.stdout.close()
        self.workers.remove(worker)

    def close(self) -> None:
        for worker in list(self.workers):
            self._retire(worker, kill=worker.job is not None)
        self.selector.close()

    def _start(self, worker: Worker, job: Job) -> None:
        worker.job, worker.last_owner = job, job.owner
        job.started = time.monotonic() if worker.ready else 0.0
        message = job.message()
        worker.process.stdin.write((json.dumps(message) + "\n").encode())
        worker.process.stdin.flush()

    def run(
        self,
        next_job: Callable[[Any], Job | None],
        pending: Callable[[], bool],
        on_progress: Callable[[Job], None],
    ) -> Iterator[tuple[Job, dict[str, Any]]]:
        """Yields ``(job, outcome)`` as jobs end; ``next_job(last_owner)`` hands out work and
        ``pending()`` says whether more may come (jobs added after others end)."""
        while True:
            for worker in [w for w in self.workers if w.job is None]:
                job = next_job(worker.last_owner)
                if job is not None:
                    self._start(worker, job)
            while len(self.workers) < self.size and pending():
                job = next_job(None)
                if job is None:
                    break
                self._start(self._spawn(), job)
            busy = [w for w in self.workers if w.job is not None]
            if not busy:  # nothing running, nothing to start: jobs only come from ended ones
                return
            yield from self._wait(busy, on_progress)

    def _wait(
        self, busy: list[Worker], on_progress: Callable[[Job], None]
    ) -> Iterator[tuple[Job, dict[str, Any]]]:
        now = time.monotonic()
        wait = min(_deadline(w) - now for w in busy)
        for key, _ in self.selector.select(timeout=max(0.01, min(0.5, wait))):
            worker: Worker = key.data
            try:
                data = os.read(worker.process.stdout.fileno(), 1 << 16)
            except BlockingIOError:
                continue
            if not data:  # the worker died
                job = worker.job
                self._retire(worker, kill=True)
                if job is not None:
                    yield job, {"ok": False, "error": _crash_message(job, worker)}
                continue
            worker.buffer += data
            while b"\n" in worker.buffer:
                line, worker.buffer = worker.buffer.split(b"\n", 1)
                message = json.loads(line)
                if message.get("ready"):
                    worker.ready = True
                    if worker.job is not None:
                        worker.job.started = time.monotonic()
                    continue
                job = worker.job
                if job is None or message.get("id") != job.id:
                    continue
                if "progress" in message:
                    job.progress = int(message["progress"])
                    on_progress(job)
                    continue
                worker.job = None
                yield job, message
        now = time.monotonic()
        for worker in list(self.workers):
            job = worker.job
            if job is not None and now > _deadline(worker):
                self._retire(worker, kill=True)
                error = f"passed its wall-clock limit of {job.limit:g} s (worker killed)"
                if not worker.ready:
                    error = f"crashed: its worker did not start within {START_LIMIT:g} s"
                yield job, {"ok": False, "error": error, "killed": True}


#: What runs clip jobs: None or "local", these worker processes; "ray" or "ray:ADDRESS", Ray
#: tasks (sims/sweeps/ray_pool.py). Set by the build from ``sims.executor`` (sitegen/
#: sweeps_pages.py); ``$SITEGEN_CLIP_EXECUTOR`` when it is None.
EXECUTOR: str | None = None


def make_pool(size: int, log_dir: Path) -> Pool:
    """The pool for one render_clips call, as :data:`EXECUTOR` says."""
    choice = EXECUTOR or os.environ.get("SITEGEN_CLIP_EXECUTOR") or "local"
    if choice == "ray" or choice.startswith("ray:"):
        from sims.sweeps.ray_pool import RayPool

        return RayPool(size, log_dir, choice.partition(":")[2] or "auto")  # type: ignore[return-value]
    return Pool(size, log_dir)


def _grace(limit: float) -> float:
    return min(KILL_GRACE, 1 + limit / 2)


def _deadline(worker: Worker) -> float:
    """When the worker's job is overdue: its limit counts from the moment the worker is ready
    (a busy machine may take seconds to import a fresh worker)."""
    job = worker.job
    assert job is not None
    if not worker.ready:
        return worker.spawned + START_LIMIT
    return job.started + job.limit + _grace(job.limit)


def _crash_message(job: Job, worker: Worker) -> str:
    try:
        text = worker.log.read_text(encoding="utf-8", errors="replace").strip()
    except OSError:
        text = ""
    lines = text.splitlines()
    last = f": {lines[-1]}" if lines else ""
    return f"crashed (worker exit code {worker.process.returncode}){last}"
