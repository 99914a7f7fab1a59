"""The Ray executor: each run a Ray task, retried by Ray when its worker or node is lost, its
record streamed back as it ends (``ray.wait``).

Ray is an optional dependency (``pip install ray``, the ``[ray]`` extra); without it,
:func:`import_ray` raises :class:`RayMissing`, whose one line says how to get it. A task runs
:func:`sims.sweeps.one_run.execute` in a Ray worker process, which forks the run's isolated
child exactly as a local worker does, so records are the same whichever executor ran them.
At most twice the cluster's CPUs are in flight, so a sweep of thousands of runs holds little in
Ray's object store and ``running`` in the progress line means something. The script and scene
paths must exist on every node (a shared folder, or the same checkout at the same place:
docs/sweeps.md says how).
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable, Iterator
from typing import Any

from .one_run import lost_record

INSTALL_HINT = "pip install ray (sitegen's [ray] extra)"


class RayMissing(RuntimeError):
    """Ray was asked for but is not installed."""


def import_ray() -> Any:
    try:
        import ray
    except ImportError:
        raise RayMissing(f"Ray is not installed: {INSTALL_HINT}") from None
    return ray


def ray_execute(job: dict[str, Any]) -> dict[str, Any]:
    """The Ray task: one run, in a Ray worker process; ``host`` also names the Ray node."""
    import ray

    from .one_run import execute

    record = execute(job)
    record["host"] += f" node {ray.get_runtime_context().get_node_id()[:12]}"
    return record


class RayExecutor:
    """Runs on the Ray cluster at ``address`` ("auto": the running one; None: the one this
    process already joined, else a new local one). ``retries``: Ray's ``max_retries`` for a
    task whose worker died."""

    name = "ray"

    def __init__(self, address: str | None = None, retries: int = 3):
        self.address = address
        self.retries = retries
        self._ray: Any = None

    def _connect(self) -> Any:
        ray = import_ray()
        if not ray.is_initialized():
            options: dict[str, Any] = {"log_to_driver": False, "include_dashboard": False}
            if self.address:
                options["address"] = self.address
                if self.address.split(":")[0] in ("127.0.0.1", "localhost"):
                    options["_node_ip_address"] = "127.0.0.1"  # nodes started on loopback
            try:
                ray.init(**options)
            except ConnectionError as exc:
                raise RuntimeError(f"cannot reach a Ray cluster at {self.address}: {exc}") from None
        self._ray = ray
        return ray

    def __enter__(self) -> RayExecutor:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def describe(self) -> str:
        ray = self._ray or self._connect()
        nodes = [n for n in ray.nodes() if n.get("Alive")]
        cpus = int(ray.cluster_resources().get("CPU", 0))
        return f"ray, {len(nodes)} node{'s' if len(nodes) != 1 else ''}, {cpus} CPUs"

    def run(
        self, jobs: list[dict[str, Any]], started: Callable[[int], None] | None = None
    ) -> Iterator[dict[str, Any]]:
        ray = self._ray or self._connect()
        task = ray.remote(max_retries=self.retries, retry_exceptions=False, num_cpus=1)(ray_execute)
        window = max(2, 2 * int(ray.cluster_resources().get("CPU", 1)))
        queue = deque(jobs)
        flying: dict[Any, dict[str, Any]] = {}
        try:
            while queue or flying:
                while queue and len(flying) < window:
                    job = queue.popleft()
                    flying[task.remote(job)] = job
                    if started is not None:
                        started(job["index"])
                done, _ = ray.wait(list(flying), num_returns=1)
                for ref in done:
                    job = flying.pop(ref)
                    try:
                        yield ray.get(ref)
                    except ray.exceptions.RayError as exc:  # lost past its retries
                        text = str(exc).strip().splitlines()[0] if str(exc).strip() else ""
                        error = f"{type(exc).__name__}: {text}".rstrip(": ")
                        yield lost_record(job, error, "lost", self.retries + 1)
        finally:
            for ref in flying:  # interrupted: leave nothing running on the cluster
                ray.cancel(ref, force=True)

    def close(self) -> None:
        pass
