"""Render simulation clips (replay and/or video, poster, CSV/JSON, SVG plots), cached by content.

``render_clips(specs, cache_dir)`` resolves each :class:`ClipSpec` to a recording plan, looks
its key up in the cache (sims/clip_cache.py) and renders only what is missing. A render is three
kinds of job (sims/clip_worker.py): *simulate* (physics only, records the state of every frame;
writes the data files and, for ``"replay"``, the glTF replay), then for ``"video"`` only,
*render* one frame range of that state tape and *encode* the ranges into the WebM (and MP4).
Jobs run in worker processes (sims/clip_pool.py) in the order sims/clip_schedule.py hands them out,
simulations first, so one long clip's frame ranges keep every core busy.

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

import shutil
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sims import clip_cache
from sims.clip_schedule import ClipEvent, ClipRun, Progress, run_clips
from sims.clip_spec import DEFAULT_CAMERA, FORMATS, ClipSpec
from sims.recording import RecordingPlan, frame_count
from sims.render import requested_renderer
from sims.sources import load_plan_function, source_target

DEFAULT_TIMEOUT = 600.0


@dataclass
class ClipResult:
    """Outcome of one clip; ``files`` maps kinds (sims.clip_cache.FILES: replay, video, poster,
    csv, json, plot...) to paths in the cache."""

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
    fallback: str | None = None  # rendered now with TinyRenderer though EGL was asked: why


def spec_fields(spec: ClipSpec, seed: int, params: dict[str, Any]) -> dict[str, Any]:
    """The spec values that change the output: never the clip name or an absolute path."""
    source = spec.label or (spec.scenario if spec.kind == "scenario" else Path(spec.scenario).name)
    return {
        "kind": spec.kind,
        "scenario": source,
        "params": clip_cache.portable_params(params),
        "seed": seed,
        "width": spec.width,
        "height": spec.height,
        "fps": spec.fps,
        "seconds": spec.seconds,
        "speed": spec.speed,
        "renderer": requested_renderer(),
        # only when not the default, so the keys of existing follow-camera clips stay valid
        **({"camera": spec.camera} if spec.camera != DEFAULT_CAMERA else {}),
        **({"trail": True} if spec.trail else {}),
        "formats": sorted(set(spec.formats)),
    }


def planned(spec: ClipSpec) -> tuple[str, RecordingPlan, str]:
    """The spec's source target ("module:function"), its recording plan and its cache key:
    the fields that change the output, the source's files and the code that runs
    (:func:`sims.clip_cache.clip_key`)."""
    target = source_target(spec.kind)
    plan = load_plan_function(target)(spec)
    key = clip_cache.clip_key(
        spec_fields(spec, plan.seed, plan.params),
        clip_cache.key_files(plan),
        code=(target.partition(":")[0],),
    )
    return target, plan, key


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
    todo: list[ClipRun] = []
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
            target, plan, key = planned(spec)
        except Exception as exc:
            text = exc.args[0] if isinstance(exc, KeyError) and exc.args else str(exc)
            label = spec.label or spec.scenario
            results[i] = _failed(cache_dir, spec, f"{spec.kind} {label!r}: {text}", notify)
            continue
        meta = clip_cache.load_entry(cache_dir, key)
        if meta is not None:
            clip_cache.set_latest(cache_dir, spec.name, key)
            results[i] = _hit(cache_dir, spec, key, meta)
            notify(ClipEvent(spec.name, "cached", frames=meta.get("frames", 0)))
            continue
        remembered = None if retry_failed else clip_cache.load_failure(cache_dir, key)
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
        limit = spec.timeout if spec.timeout is not None else timeout
        frames = 0
        if "video" in spec.formats:  # the worker reports the real count of a measured length
            known = spec.seconds is not None or plan.length_known
            frames = frame_count(plan.length(spec.seconds), spec.fps, spec.speed) if known else 1
        todo.append(ClipRun(i, spec, key, target, tmp, frames, limit))
        notify(ClipEvent(spec.name, "queued", total=todo[-1].total))
    if todo:
        for clip in run_clips(todo, jobs, notify):
            done = _finish(cache_dir, clip, notify)
            results[clip.index] = done
            for i, spec in followers[clip.key]:
                results[i] = _share(cache_dir, spec, done, notify)
    return [r for r in results if r is not None]


def _check_spec(spec: ClipSpec) -> None:
    if spec.width < 16 or spec.height < 16 or spec.width % 2 or spec.height % 2:
        raise ValueError(f"size {spec.width}x{spec.height}: need even sides of at least 16")
    if spec.fps <= 0 or (spec.seconds is not None and spec.seconds <= 0):
        raise ValueError("fps and seconds must be positive")
    if not spec.speed >= 1:
        raise ValueError(f"speed must be at least 1, not {spec.speed!r}")
    if spec.timeout is not None and not spec.timeout > 0:
        raise ValueError(f"timeout must be positive, not {spec.timeout!r}")
    unknown = [f for f in spec.formats if f not in FORMATS]
    if not spec.formats or unknown:
        raise ValueError(
            f"formats must be some of {', '.join(FORMATS)}, not {list(spec.formats)!r}"
        )


def _hit(cache_dir: Path, spec: ClipSpec, key: str, meta: dict[str, Any]) -> ClipResult:
    return ClipResult(
        spec.name,
        True,
        files=clip_cache.entry_files(cache_dir, key, meta),
        meta={**meta, "name": spec.name, "key": key},
    )


def _pending(cache_dir: Path, spec: ClipSpec) -> ClipResult:
    """A clip left for a later build; shows the last good render of its name meanwhile."""
    result = ClipResult(spec.name, False, pending=True)
    old = clip_cache.latest_key(cache_dir, spec.name)
    meta = clip_cache.load_entry(cache_dir, old) if old is not None else None
    if old is not None and meta is not None:
        result.files = clip_cache.entry_files(cache_dir, old)
        result.meta = {**meta, "name": spec.name, "key": old}
    return result


def _share(cache_dir: Path, spec: ClipSpec, done: ClipResult, notify: Progress) -> ClipResult:
    """The result for a spec whose content was rendered under another name in this call."""
    if not done.ok:
        return _failed(cache_dir, spec, done.error or "failed", notify)
    key = done.meta["key"]
    clip_cache.set_latest(cache_dir, spec.name, key)
    notify(ClipEvent(spec.name, "cached", frames=done.meta.get("frames", 0)))
    return ClipResult(
        spec.name, True, files=dict(done.files), meta={**done.meta, "name": spec.name}
    )


def _finish(cache_dir: Path, clip: ClipRun, notify: Progress) -> ClipResult:
    elapsed = round(time.monotonic() - clip.started, 3)
    if clip.outcome is None:
        shutil.rmtree(clip.tmp, ignore_errors=True)
        error = clip.error or "unknown error"
        clip_cache.record_failure(cache_dir, clip.key, clip.spec.name, error)
        return _failed(cache_dir, clip.spec, error, notify, seconds=elapsed)
    clip_cache.commit_entry(cache_dir, clip.key, clip.tmp)
    clip_cache.clear_failure(cache_dir, clip.key)
    clip_cache.set_latest(cache_dir, clip.spec.name, clip.key)
    meta = clip.outcome
    notify(ClipEvent(clip.spec.name, "done", elapsed, frames=meta["frames"], total=meta["frames"]))
    return ClipResult(
        clip.spec.name,
        True,
        rendered=True,
        seconds=elapsed,
        fallback="; ".join(sorted(clip.fallbacks)) or None,
        files=clip_cache.entry_files(cache_dir, clip.key),
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
    old = clip_cache.latest_key(cache_dir, spec.name) if keep_stale else None
    result = ClipResult(spec.name, False, error=error, seconds=seconds, remembered=remembered)
    if old is not None:
        meta = clip_cache.load_entry(cache_dir, old) or {}
        result.stale = True
        result.files = clip_cache.entry_files(cache_dir, old)
        result.meta = {**meta, "name": spec.name, "key": old}
    return result
