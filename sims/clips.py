"""Render simulation clips (WebM + poster + CSV/JSON + SVG path), cached by content hash.

``render_clips(specs, cache_dir)`` resolves each :class:`ClipSpec` to a recording plan, looks
its key up in the cache (sims/cache.py) and renders only what is missing. A render is three
kinds of job (sims/clip_worker.py): *simulate* (physics only, records the state of every frame),
*render* one frame range of that state tape, *encode* the ranges into the WebM. Jobs run in
worker processes (sims/clip_pool.py), simulations first, so one long clip's frame ranges keep
every core busy.

Failures never raise: a clip whose source raises, crashes its worker or passes its limit comes
back ``ok=False`` with an error naming it, and with the last good render of that clip name
(``stale=True``) when there is one. The failure is remembered in the cache under the clip's key
(its inputs), so an unchanged broken clip is reported again without running;
``retry_failed=True`` runs it anyway.

Limits: a clip stops after its length in simulated seconds (the Recorder ends the source, so it
never runs more physics steps than ``length / timestep``); a script source also has a simulated
clock limit (sims/remote_api/script_clips.py). Wall-clock time is only a safety net:
``spec.timeout`` or ``timeout`` (seconds per job), checked between frames and enforced by
killing the worker.

Progress: ``progress(ClipEvent)`` gets "cached" for a cache hit, or "queued" (with the
frame count, as soon as the clip is planned), "started", "progress"
(frames done, phase) and then "done" or "failed" for a render ("failed" alone for a clip that
fails before starting, ``remembered=True`` for a failure recalled from the cache).

Adding a recording source kind (e.g. ``kind="script"`` clips that run a course script)
--------------------------------------------------------------------------------------------
1. Write ``plan(spec: ClipSpec) -> sims.recording.RecordingPlan`` in any importable module. It
   must not build a World; it says which scene/seed/duration to use, which files identify the
   source (``hash_files``, e.g. the script), and gives ``drive(world, record)``, which drives
   the World (``world.advance`` etc.) while the Recorder samples. ``spec.scenario`` is the
   source's own target (a script path, say), ``spec.label`` its portable name (a path relative
   to the project: what keys and outputs show), and ``spec.params`` its options.
2. Declare it in the one table ``sims.sources.SOURCE_KINDS`` (kind -> "module:function";
   ``register_source_kind`` adds one at run time, for tests and extensions). Workers
   receive the import path and import it themselves; they get the parent's ``sys.path``.
3. Use it: ``ClipSpec(name="demo", scenario="path/to/script.py", kind="script")``.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

from sims import cache
from sims.clip_pool import Job, Pool
from sims.clip_spec import ClipSpec
from sims.clip_worker import RANGE_FRAMES, range_starts
from sims.recording import frame_count
from sims.render import requested_renderer
from sims.sources import load_plan_function, source_target

DEFAULT_TIMEOUT = 600.0


@dataclass
class ClipResult:
    """Outcome of one clip; ``files`` maps video/poster/csv/json/plot to paths in the cache."""

    name: str
    ok: bool
    error: str | None = None
    rendered: bool = False
    stale: bool = False
    remembered: bool = False  # a failure recalled from the cache, not run again
    pending: bool = False  # not rendered: the call rendered nothing (``render=False``)
    files: dict[str, Path] = field(default_factory=dict)
    meta: dict[str, Any] = field(default_factory=dict)
    seconds: float = 0.0  # wall time spent rendering it now (0 for cache hits)


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
class _Clip:
    """One clip being rendered: its jobs, frames drawn per range, its outcome."""

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
    phase: str = "simulating"
    error: str | None = None
    outcome: dict[str, Any] | None = None


def spec_fields(spec: ClipSpec, seed: int, params: dict[str, Any]) -> dict[str, Any]:
    """The spec values that change the output: never the clip name or an absolute path."""
    source = spec.label or (spec.scenario if spec.kind == "scenario" else Path(spec.scenario).name)
    return {
        "kind": spec.kind,
        "scenario": source,
        "params": cache.portable_params(params),
        "seed": seed,
        "width": spec.width,
        "height": spec.height,
        "fps": spec.fps,
        "seconds": spec.seconds,
        "speed": spec.speed,
        "renderer": requested_renderer(),
        # only when not the default, so the keys of existing follow-camera clips stay valid
        **({"camera": spec.camera} if spec.camera != "follow" else {}),
        **({"trail": True} if spec.trail else {}),
    }


def render_clips(
    specs: Sequence[ClipSpec],
    cache_dir: str | Path,
    jobs: int | None = None,
    progress: Progress | None = None,
    timeout: float = DEFAULT_TIMEOUT,
    retry_failed: bool = False,
    render: bool = True,
) -> list[ClipResult]:
    """Render (or fetch from cache) every spec; results come back in the order of ``specs``.

    ``jobs``: worker processes (default: CPU count). ``timeout``: wall-clock seconds per job
    for specs without their own. ``retry_failed``: run clips whose failure is remembered.
    ``render=False``: cache only; a clip not in the cache comes back ``pending``, with the
    last good render of its name when there is one (``sitegen serve``'s first build)."""
    cache_dir = Path(cache_dir)
    cache_dir.mkdir(parents=True, exist_ok=True)
    notify = progress or (lambda event: None)
    results: list[ClipResult | None] = [None] * len(specs)
    todo: list[_Clip] = []
    followers: dict[str, list[tuple[int, ClipSpec]]] = {}  # same key as a queued clip
    seen: set[str] = set()
    for i, spec in enumerate(specs):
        if spec.name in seen:
            results[i] = _failed(
                cache_dir, spec, f"clip {spec.name!r} is listed twice", notify, keep_stale=False
            )
            continue
        seen.add(spec.name)
        try:
            _check_spec(spec)
            target = source_target(spec.kind)
            plan = load_plan_function(target)(spec)
            key = cache.clip_key(spec_fields(spec, plan.seed, plan.params), cache.key_files(plan))
        except Exception as exc:
            text = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
            label = spec.label or spec.scenario
            results[i] = _failed(cache_dir, spec, f"{spec.kind} {label!r}: {text}", notify)
            continue
        meta = cache.load_entry(cache_dir, key)
        if meta is not None:
            cache.set_latest(cache_dir, spec.name, key)
            results[i] = _hit(cache_dir, spec, key, meta)
            notify(ClipEvent(spec.name, "cached", frames=meta.get("frames", 0)))
            continue
        remembered = None if retry_failed else cache.load_failure(cache_dir, key)
        if remembered is not None:
            error = f"{remembered} (remembered from an earlier build: --retry-failed runs it again)"
            results[i] = _failed(cache_dir, spec, error, notify, remembered=True)
            continue
        if not render:
            results[i] = _pending(cache_dir, spec)
            continue
        if key in followers:  # identical content under another name: render once
            followers[key].append((i, spec))
            continue
        followers[key] = []
        tmp = Path(tempfile.mkdtemp(prefix=f".tmp-{key}-", dir=cache_dir))
        tmp.chmod(0o755)
        length = spec.seconds if spec.seconds is not None else plan.duration
        limit = spec.timeout if spec.timeout is not None else timeout
        todo.append(
            _Clip(i, spec, key, target, tmp, frame_count(length, spec.fps, spec.speed), limit)
        )
        notify(ClipEvent(spec.name, "queued", total=todo[-1].total))
    if todo:
        for clip in _render(todo, jobs, notify):
            done = _finish(cache_dir, clip, notify)
            results[clip.index] = done
            for i, spec in followers[clip.key]:
                results[i] = _share(cache_dir, spec, done, notify)
    return [r for r in results if r is not None]


def _render(todo: list[_Clip], jobs: int | None, notify: Progress):
    """Run every clip's jobs on a pool; yields each clip once its outcome is known."""
    ids = iter(range(1, 1 << 62))
    simulations = [
        Job(next(ids), _payload(c, "simulate"), c.limit, owner=c)
        for c in sorted(todo, key=lambda c: -c.total * c.spec.width * c.spec.height)
    ]
    ready: list[Job] = []  # encodes, then ranges
    open_clips = set(todo)

    def next_job(last: _Clip | None) -> Job | None:
        if ready and ready[0].payload["phase"] == "encode":
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
        clip: _Clip = job.owner
        if job.payload["phase"] == "render":
            clip.drawn[job.payload["start"]] = job.progress
            _tell(clip, notify)

    workers = max(1, min(jobs or os.cpu_count() or 1, sum(c.total for c in todo)))
    log_dir = Path(tempfile.mkdtemp(prefix=".workers-", dir=todo[0].tmp.parent))
    pool = Pool(workers, log_dir)
    try:
        for job, outcome in pool.run(next_job, lambda: bool(simulations or ready), on_progress):
            clip: _Clip = job.owner
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


def _advance(clip: _Clip, job: Job, result: dict[str, Any], ready: list[Job], ids, notify) -> None:
    """A job of ``clip`` succeeded: queue what it unlocks."""
    phase = job.payload["phase"]
    if phase == "simulate":
        clip.meta = result
        clip.total = result["frames"]
        clip.starts = range_starts(clip.total, RANGE_FRAMES)
        clip.phase = "rendering"
        for start in clip.starts:
            payload = _payload(clip, "render")
            stop = min(start + RANGE_FRAMES, clip.total)
            payload.update(start=start, stop=stop, follow=result["follow"])
            ready.append(Job(next(ids), payload, clip.limit, owner=clip))
        clip.running = len(clip.starts)
        _tell(clip, notify)
    elif phase == "render":
        clip.drawn[job.payload["start"]] = result["frames"]
        clip.renderers.add(result["renderer"])
        clip.running -= 1
        _tell(clip, notify)
        if clip.running == 0:
            clip.phase = "encoding"
            payload = _payload(clip, "encode")
            payload.update(
                meta=clip.meta, starts=clip.starts, renderer="+".join(sorted(clip.renderers))
            )
            ready.insert(0, Job(next(ids), payload, clip.limit, owner=clip))
            _tell(clip, notify)
    else:
        clip.outcome = result


def _tell(clip: _Clip, notify: Progress) -> None:
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


def _payload(clip: _Clip, phase: str) -> dict[str, Any]:
    return {
        "phase": phase,
        "spec": asdict(clip.spec),
        "target": clip.target,
        "out_dir": str(clip.tmp),
    }


def _label(spec: ClipSpec) -> str:
    return f"{spec.kind} {spec.label or spec.scenario!r}"


def _check_spec(spec: ClipSpec) -> None:
    if spec.width < 16 or spec.height < 16 or spec.width % 2 or spec.height % 2:
        raise ValueError(f"size {spec.width}x{spec.height}: need even sides of at least 16")
    if spec.fps <= 0 or (spec.seconds is not None and spec.seconds <= 0):
        raise ValueError("fps and seconds must be positive")
    if not spec.speed >= 1:
        raise ValueError(f"speed must be at least 1, not {spec.speed!r}")
    if spec.timeout is not None and not spec.timeout > 0:
        raise ValueError(f"timeout must be positive, not {spec.timeout!r}")


def _hit(cache_dir: Path, spec: ClipSpec, key: str, meta: dict[str, Any]) -> ClipResult:
    return ClipResult(
        spec.name,
        True,
        files=cache.entry_files(cache_dir, key),
        meta={**meta, "name": spec.name, "key": key},
    )


def _pending(cache_dir: Path, spec: ClipSpec) -> ClipResult:
    """A clip left for a later build; shows the last good render of its name meanwhile."""
    result = ClipResult(spec.name, False, pending=True)
    old = cache.latest_key(cache_dir, spec.name)
    meta = cache.load_entry(cache_dir, old) if old is not None else None
    if old is not None and meta is not None:
        result.files = cache.entry_files(cache_dir, old)
        result.meta = {**meta, "name": spec.name, "key": old}
    return result


def _share(cache_dir: Path, spec: ClipSpec, done: ClipResult, notify: Progress) -> ClipResult:
    """The result for a spec whose content was rendered under another name in this call."""
    if not done.ok:
        return _failed(cache_dir, spec, done.error or "failed", notify)
    key = done.meta["key"]
    cache.set_latest(cache_dir, spec.name, key)
    notify(ClipEvent(spec.name, "cached", frames=done.meta.get("frames", 0)))
    return ClipResult(
        spec.name, True, files=dict(done.files), meta={**done.meta, "name": spec.name}
    )


def _finish(cache_dir: Path, clip: _Clip, notify: Progress) -> ClipResult:
    elapsed = round(time.monotonic() - clip.started, 3)
    if clip.outcome is None:
        shutil.rmtree(clip.tmp, ignore_errors=True)
        error = clip.error or "unknown error"
        cache.record_failure(cache_dir, clip.key, clip.spec.name, error)
        return _failed(cache_dir, clip.spec, error, notify, seconds=elapsed)
    cache.commit_entry(cache_dir, clip.key, clip.tmp)
    cache.clear_failure(cache_dir, clip.key)
    cache.set_latest(cache_dir, clip.spec.name, clip.key)
    meta = clip.outcome
    notify(ClipEvent(clip.spec.name, "done", elapsed, frames=meta["frames"], total=meta["frames"]))
    return ClipResult(
        clip.spec.name,
        True,
        rendered=True,
        seconds=elapsed,
        files=cache.entry_files(cache_dir, clip.key),
        meta={**meta, "name": clip.spec.name, "key": clip.key},
    )


def _failed(
    cache_dir: Path,
    spec: ClipSpec,
    error: str,
    notify: Progress,
    seconds: float = 0.0,
    keep_stale: bool = True,
    remembered: bool = False,
) -> ClipResult:
    """A failed clip, carrying the previous good render of the same name when there is one."""
    notify(ClipEvent(spec.name, "failed", seconds, error, remembered=remembered))
    old = cache.latest_key(cache_dir, spec.name) if keep_stale else None
    result = ClipResult(spec.name, False, error=error, seconds=seconds, remembered=remembered)
    if old is not None:
        meta = cache.load_entry(cache_dir, old) or {}
        result.stale = True
        result.files = cache.entry_files(cache_dir, old)
        result.meta = {**meta, "name": spec.name, "key": old}
    return result
