"""Render simulation clips (WebM + poster + CSV/JSON + SVG path), cached by content hash.

``render_clips(specs, cache_dir)`` resolves each :class:`ClipSpec` to a recording plan, looks
its key up in the cache (sims/cache.py) and renders only what is missing, in parallel worker
processes (one World each). A clip whose source raises or
passes the time limit comes back ``ok=False`` with an error naming it, the others still
render, and the last good render of that clip name is returned with ``stale=True``.

Workers are plain ``python -m sims.clip_worker`` subprocesses rather than multiprocessing's
spawn/forkserver: those re-import the caller's ``__main__``, so any script calling
render_clips without an ``if __name__ == "__main__"`` guard would recurse. A subprocess costs
~0.3 s of imports per clip and can be killed cleanly when it passes its time limit.

Progress: ``progress(ClipEvent)`` gets "cached" for a cache hit, or "started" and then "done"
or "failed" for a render (a clip that fails before starting gets just "failed").

Adding a recording source kind (e.g. ``kind="script"`` clips that run a course script)
--------------------------------------------------------------------------------------------
1. Write ``plan(spec: ClipSpec) -> sims.sources.RecordingPlan`` in any importable module. It
   must not build a World; it says which scene/seed/duration to use, which files identify the
   source (``hash_files``, e.g. the script), and gives ``drive(world, record)``, which drives
   the World (``world.advance`` etc.) while the Recorder samples and films. ``spec.scenario``
   is the source's own target (a script path, say) and ``spec.params`` its options.
2. Register it: ``sims.sources.register_source_kind("script", "pkg.module:plan")`` before
   calling render_clips (or add the entry to ``sims.sources.SOURCE_KINDS``). Workers receive
   the import path and import it themselves.
   Workers get the parent's ``sys.path``, so any module the parent can import works.
3. Use it: ``ClipSpec(name="demo", scenario="path/to/script.py", kind="script")``.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from sims import cache
from sims.clip_worker import JOB, LOG, RESULT
from sims.render import requested_renderer
from sims.sources import load_plan_function, source_target

DEFAULT_TIMEOUT = 900.0
KILL_GRACE = 15.0  # at most this long past the time limit before a worker is killed


@dataclass(frozen=True)
class ClipSpec:
    """One clip to render. ``seconds``/``seed`` None = the source's own duration/seed."""

    name: str
    scenario: str
    width: int = 480
    height: int = 360
    fps: int = 20
    seconds: float | None = None
    seed: int | None = None
    params: dict[str, Any] = field(default_factory=dict)
    kind: str = "scenario"


@dataclass
class ClipResult:
    """Outcome of one clip; ``files`` maps video/poster/csv/json/plot to paths in the cache."""

    name: str
    ok: bool
    error: str | None = None
    rendered: bool = False
    stale: bool = False
    files: dict[str, Path] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)
    seconds: float = 0.0  # wall time spent rendering it now (0 for cache hits)


@dataclass(frozen=True)
class ClipEvent:
    name: str
    status: str  # "started", "done", "failed" or "cached"
    seconds: float = 0.0
    error: str | None = None


Progress = Callable[[ClipEvent], None]


@dataclass
class _Job:
    index: int
    spec: ClipSpec
    key: str
    target: str
    tmp: Path
    frames: int = 0
    process: Any = None
    started: float = 0.0
    ended: float = 0.0


def spec_fields(spec: ClipSpec, seed: int, params: dict[str, Any]) -> dict[str, Any]:
    """The spec values that change the output (the clip name does not)."""
    return {
        "kind": spec.kind,
        "scenario": spec.scenario,
        "params": params,
        "seed": seed,
        "width": spec.width,
        "height": spec.height,
        "fps": spec.fps,
        "seconds": spec.seconds,
        "renderer": requested_renderer(),
    }


def render_clips(
    specs: Sequence[ClipSpec],
    cache_dir: str | Path,
    jobs: int | None = None,
    progress: Progress | None = None,
    timeout: float = DEFAULT_TIMEOUT,
) -> list[ClipResult]:
    """Render (or fetch from cache) every spec; results come back in the order of ``specs``.

    ``jobs``: parallel workers (default: CPU count). ``timeout``: wall-clock seconds per clip.
    """
    cache_dir = Path(cache_dir)
    cache_dir.mkdir(parents=True, exist_ok=True)
    notify = progress or (lambda event: None)
    results: list[ClipResult | None] = [None] * len(specs)
    queue: list[_Job] = []
    followers: dict[str, list[tuple[int, ClipSpec]]] = {}  # same key as a queued job
    seen: set[str] = set()
    for i, spec in enumerate(specs):
        if spec.name in seen:
            results[i] = _failed(
                cache_dir, spec, f"clip {spec.name!r} is listed twice", notify, keep_stale=False
            )
            continue
        seen.add(spec.name)
        try:
            target = source_target(spec.kind)
            plan = load_plan_function(target)(spec)
            _check_spec(spec)
            key = cache.clip_key(spec_fields(spec, plan.seed, plan.params), plan.hash_files)
        except Exception as exc:
            text = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
            results[i] = _failed(cache_dir, spec, f"{spec.kind} {spec.scenario!r}: {text}", notify)
            continue
        meta = cache.load_entry(cache_dir, key)
        if meta is not None:
            cache.set_latest(cache_dir, spec.name, key)
            results[i] = ClipResult(
                spec.name,
                True,
                files=cache.entry_files(cache_dir, key),
                meta={**meta, "name": spec.name, "key": key},
            )
            notify(ClipEvent(spec.name, "cached"))
            continue
        if key in followers:  # identical content under another name: render once
            followers[key].append((i, spec))
            continue
        followers[key] = []
        tmp = Path(tempfile.mkdtemp(prefix=f".tmp-{key}-", dir=cache_dir))
        tmp.chmod(0o755)
        length = spec.seconds if spec.seconds is not None else plan.duration
        queue.append(_Job(i, spec, key, target, tmp, frames=round(length * spec.fps)))

    if queue:
        workers = max(1, min(jobs or os.cpu_count() or 1, len(queue)))
        for job, outcome in _run_jobs(queue, workers, timeout, notify):
            results[job.index] = done = _finish(cache_dir, job, outcome, notify)
            for i, spec in followers[job.key]:
                results[i] = _share(cache_dir, spec, done, notify)
    return [r for r in results if r is not None]


def _share(cache_dir: Path, spec: ClipSpec, done: ClipResult, notify: Progress) -> ClipResult:
    """The result for a spec whose content was rendered under another name in this call."""
    if not done.ok:
        return _failed(cache_dir, spec, done.error or "failed", notify)
    key = done.meta["key"]
    cache.set_latest(cache_dir, spec.name, key)
    notify(ClipEvent(spec.name, "cached"))
    return ClipResult(
        spec.name, True, files=dict(done.files), meta={**done.meta, "name": spec.name}
    )


def _check_spec(spec: ClipSpec) -> None:
    if spec.width < 16 or spec.height < 16 or spec.width % 2 or spec.height % 2:
        raise ValueError(f"size {spec.width}x{spec.height}: need even sides of at least 16")
    if spec.fps <= 0 or (spec.seconds is not None and spec.seconds <= 0):
        raise ValueError("fps and seconds must be positive")


def _worker_env() -> dict[str, str]:
    """The parent's import path, so registered source modules import in the worker too."""
    env = dict(os.environ)
    paths = [str(cache.ROOT_DIR)] + [p for p in sys.path if p and os.path.isdir(p)]
    env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    return env


def _run_jobs(
    queue: list[_Job], workers: int, timeout: float, notify: Progress
) -> Iterator[tuple[_Job, dict[str, Any]]]:
    """Run jobs ``workers`` at a time; yields each as it ends with the worker's result dict."""
    env = _worker_env()
    pending = sorted(queue, key=lambda j: -j.frames * j.spec.width * j.spec.height)  # longest first
    running: list[_Job] = []
    try:
        yield from _schedule(pending, running, workers, timeout, env, notify)
    finally:  # interrupted (Ctrl-C, an exception in a progress callback): leave no workers
        for job in running:
            if job.process.poll() is None:
                job.process.kill()
                job.process.wait()
            shutil.rmtree(job.tmp, ignore_errors=True)
        for job in pending:
            shutil.rmtree(job.tmp, ignore_errors=True)


def _schedule(
    pending: list[_Job],
    running: list[_Job],
    workers: int,
    timeout: float,
    env: dict[str, str],
    notify: Progress,
) -> Iterator[tuple[_Job, dict[str, Any]]]:
    while pending or running:
        while pending and len(running) < workers:
            job = pending.pop(0)
            payload = {
                "spec": asdict(job.spec),
                "target": job.target,
                "out_dir": str(job.tmp),
                "time_limit": timeout,
            }
            (job.tmp / JOB).write_text(json.dumps(payload), encoding="utf-8")
            with open(job.tmp / LOG, "wb") as log:
                job.process = subprocess.Popen(
                    [sys.executable, "-m", "sims.clip_worker", str(job.tmp / JOB)],
                    stdin=subprocess.DEVNULL,
                    stdout=subprocess.DEVNULL,
                    stderr=log,
                    env=env,
                )
            job.started = time.monotonic()
            running.append(job)
            notify(ClipEvent(job.spec.name, "started"))
        time.sleep(0.05)
        for job in list(running):
            overdue = time.monotonic() - job.started > timeout + min(KILL_GRACE, 1 + timeout / 2)
            if job.process.poll() is None and not overdue:
                continue
            if job.process.poll() is None:
                job.process.kill()
            job.process.wait()
            job.ended = time.monotonic()
            running.remove(job)
            yield job, _read_result(job, timeout, overdue)


def _read_result(job: _Job, timeout: float, killed: bool) -> dict[str, Any]:
    label = f"{job.spec.kind} {job.spec.scenario!r}"
    try:
        return json.loads((job.tmp / RESULT).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        if killed:
            return {
                "ok": False,
                "error": f"{label} passed its time limit of {timeout:g} s (worker killed)",
            }
        lines = (job.tmp / LOG).read_text(encoding="utf-8", errors="replace").strip().splitlines()
        last = f": {lines[-1]}" if lines else ""
        return {
            "ok": False,
            "error": f"{label} crashed (worker exit code {job.process.returncode}){last}",
        }


def _finish(cache_dir: Path, job: _Job, outcome: dict[str, Any], notify: Progress) -> ClipResult:
    elapsed = round(job.ended - job.started, 3)
    if not outcome.get("ok"):
        shutil.rmtree(job.tmp, ignore_errors=True)
        result = _failed(
            cache_dir, job.spec, outcome.get("error") or "unknown error", notify, seconds=elapsed
        )
        return result
    for name in (RESULT, JOB, LOG):
        (job.tmp / name).unlink(missing_ok=True)
    cache.commit_entry(cache_dir, job.key, job.tmp)
    cache.set_latest(cache_dir, job.spec.name, job.key)
    notify(ClipEvent(job.spec.name, "done", elapsed))
    return ClipResult(
        job.spec.name,
        True,
        rendered=True,
        seconds=elapsed,
        files=cache.entry_files(cache_dir, job.key),
        meta={**outcome["meta"], "name": job.spec.name, "key": job.key},
    )


def _failed(
    cache_dir: Path,
    spec: ClipSpec,
    error: str,
    notify: Progress,
    seconds: float = 0.0,
    keep_stale: bool = True,
) -> ClipResult:
    """A failed clip, carrying the previous good render of the same name when there is one."""
    notify(ClipEvent(spec.name, "failed", seconds, error))
    old = cache.latest_key(cache_dir, spec.name) if keep_stale else None
    if old is None:
        return ClipResult(spec.name, False, error=error, seconds=seconds)
    meta = cache.load_entry(cache_dir, old) or {}
    return ClipResult(
        spec.name,
        False,
        error=error,
        stale=True,
        seconds=seconds,
        files=cache.entry_files(cache_dir, old),
        meta={**meta, "name": spec.name, "key": old},
    )


if __name__ == "__main__":  # pragma: no cover - convenience: python -m sims.clips NAME...
    from sims.cli import main

    sys.exit(main(["render", *sys.argv[1:]]))
