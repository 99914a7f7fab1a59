"""Clip jobs on Ray: the build's own clip rendering sent to the same executor as sweeps.

:class:`RayPool` has the run/close interface of :class:`sims.clip_pool.Pool` (the scheduler in
sims/clip_schedule.py hands out simulate, render and encode jobs and reads their outcomes), and
runs each job as a Ray task calling the clip worker's own :func:`sims.clip_worker.run_phase`,
so a clip is the same bytes whichever ran it. ``sims.clip_pool.make_pool`` picks it when the
build's ``sims.executor`` is ray (or ``$SITEGEN_CLIP_EXECUTOR=ray[:ADDRESS]``).

A clip's jobs pass frames through files in its folder of the clip cache, so on a real cluster
every node must see the project's folder at the same path (a shared file system); on one
machine (a local Ray, or nodes started there) nothing is needed. A task runs in the build's
folder so relative paths mean what they mean to the build.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Callable, Iterator
from typing import Any

from .ray_runs import import_ray

_worlds: Any = None  # the Ray worker's render World, kept between ranges (clip_worker.WorldCache)


def clip_task(message: dict[str, Any], cwd: str) -> dict[str, Any]:
    """One clip job in a Ray worker: ``{"ok", "result"}`` or ``{"ok": False, "error"}``."""
    global _worlds
    from sims.clip_worker import ClipJob, WorldCache, outcome, run_phase

    job = ClipJob.from_message(message)
    if _worlds is None:
        _worlds = WorldCache()
    here = os.getcwd()
    try:
        with contextlib.suppress(OSError):
            os.chdir(cwd)
        return outcome(job, lambda: run_phase(job, lambda _n: None, _worlds))
    finally:
        os.chdir(here)


class RayPool:
    """Clip jobs as Ray tasks (at most twice the cluster's CPUs in flight)."""

    def __init__(self, size: int, log_dir: Any = None, address: str | None = "auto"):
        self.size, self.address = size, address
        self._ray: Any = None
        self._flying: dict[Any, Any] = {}

    def _connect(self) -> Any:
        ray = import_ray()
        if not ray.is_initialized():
            options: dict[str, Any] = {"log_to_driver": False, "include_dashboard": False}
            if self.address:
                options["address"] = self.address
            ray.init(**options)
        return ray

    def run(
        self,
        next_job: Callable[[Any], Any],
        pending: Callable[[], bool],
        on_progress: Callable[[Any], None],
    ) -> Iterator[tuple[Any, dict[str, Any]]]:
        ray = self._ray = self._ray or self._connect()
        task = ray.remote(max_retries=2, num_cpus=1)(clip_task)
        window = max(2, 2 * int(ray.cluster_resources().get("CPU", 1)))
        cwd = os.getcwd()
        while True:
            while len(self._flying) < window:
                job = next_job(None)
                if job is None:
                    break
                self._flying[task.remote(job.message(), cwd)] = job
            if not self._flying:
                return
            done, _ = ray.wait(list(self._flying), num_returns=1)
            for ref in done:
                job = self._flying.pop(ref)
                try:
                    result = ray.get(ref)
                except ray.exceptions.RayError as exc:
                    text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
                    result = {"ok": False, "error": f"crashed on Ray: {type(exc).__name__} {text}"}
                yield job, result

    def close(self) -> None:
        if self._ray is not None:
            for ref in self._flying:
                self._ray.cancel(ref, force=True)
        self._flying.clear()
