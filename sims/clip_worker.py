"""The three phases of a clip, run in worker processes: simulate, render frame ranges, encode.

1. **simulate** runs the clip's source in a World without a renderer (physics only, fast),
   writes the data files (CSV, JSON, SVG plots), for a replay the ``.glb`` and its poster
   (sims/replay/clip.py; a replay-only clip ends here) and, for a video, a *state tape*: for
   every video frame, the pose of every body and the position of every joint (``states.npz``,
   sims/state_tape.py).
2. **render** rebuilds the scene in a World with the renderer, and for one frame range sets
   each recorded state and draws it (``frames-NNNNNN.rgb``, raw RGB). Ranges are independent,
   so one long clip keeps every core busy; a range never depends on what its process drew
   before (``Renderer.new_sequence``), so the bytes do not depend on how ranges were scheduled.
3. **encode** writes the ranges, in order, to ``clip.webm`` (and ``clip.mp4`` where ffmpeg has
   H.264), ``poster.png`` (middle frame, unless the replay made it) and ``meta.json``.

``python -m sims.clip_worker`` serves jobs: one JSON line per job on stdin, one JSON line per
progress report or result on stdout (C-level output of pybullet/EGL goes to stderr, the worker's
log). A worker keeps its last render World, so consecutive ranges of one clip skip the rebuild.
``render_job`` runs all three phases in the calling process (``sitegen remote-api --record``).
"""

from __future__ import annotations

import json
import math
import os
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from sims.clip_cache import FILES, META
from sims.plot import path_svg, series_svg
from sims.recording import RecordingTimeout, frame_count, record
from sims.render import requested_renderer
from sims.sources import load_plan_function
from sims.state_tape import SceneChanged, apply_state, capture_state, covers, layout_of
from sims.video import Mp4Writer, WebmWriter, mp4_encoder, write_png
from sims.world import World

STATES = "states.npz"
Progress = Callable[[int], None]


def _label(spec: dict[str, Any]) -> str:
    return f"{spec.get('kind', 'scenario')} {spec.get('label') or spec['scenario']!r}"


# -- phase 1: simulate -----------------------------------------------------------------------
def simulate(job: dict[str, Any], progress: Progress | None = None) -> dict[str, Any]:
    """Run the source; write data files and the state tape into ``out_dir``."""
    from sims.clip_cache import portable_params
    from sims.clip_spec import ClipSpec
    from sims.replay.export import ReplayTape

    spec = ClipSpec(**job["spec"])
    out = Path(job["out_dir"])
    plan = load_plan_function(job["target"])(spec)
    length = spec.seconds if spec.seconds is not None else plan.duration
    video = "video" in spec.formats
    total = frame_count(length, spec.fps, spec.speed)
    states: list[list[float]] = []
    seen: dict[str, Any] = {}
    tape = ReplayTape(plan.follow) if "replay" in spec.formats else None

    def on_frame(world: World) -> None:
        if "layout" not in seen:
            seen["layout"] = layout_of(world)
        elif world.steps < seen["steps"] and not covers(world, seen["layout"]):  # a reset
            raise SceneChanged(f"the scene's bodies changed at frame {len(states)}")
        seen["steps"] = world.steps
        states.append(capture_state(world, seen["layout"]))
        if progress is not None:
            progress(len(states))

    def on_sample(world: World) -> None:
        if "first" not in seen:  # the state the poster shows
            seen["first_layout"] = layout_of(world)
            seen["first"] = capture_state(world, seen["first_layout"])
        assert tape is not None
        tape.sample(world)

    deadline = time.monotonic() + job["time_limit"]
    recording, _ = record(
        plan,
        fps=spec.fps,
        seconds=spec.seconds,
        on_frame=on_frame if video else None,
        deadline=deadline,
        speed=spec.speed,
        on_sample=on_sample if tape is not None else None,
    )
    follow = plan.follow or recording.subject
    if video:
        if not states or len(states) > total:  # fewer: the source ended the clip early
            raise RuntimeError(f"recorded {len(states)} frames, expected {total}")
        total = len(states)
        np.savez(
            out / STATES,
            states=np.asarray(states, dtype=np.float64),
            layout=np.asarray(json.dumps(seen["layout"])),
            world=np.asarray(
                json.dumps({"scene": plan.scene, "seed": plan.seed, "options": plan.scene_options})
            ),
        )
    name = spec.label or spec.scenario
    params = portable_params(plan.params)
    scene = Path(plan.scene).name if Path(plan.scene).is_absolute() else plan.scene
    write_data(out, recording, spec, plan, name, params, scene)
    meta = {
        "kind": spec.kind,
        "scenario": name,
        "description": plan.description,
        "source": spec.label or _portable(plan.source_path),
        "scene": scene,
        "seed": plan.seed,
        "params": params,
        "frames": total if video else 0,
        "samples": len(recording.rows),
        "duration": round(len(recording.rows) / spec.fps, 3),
        "fps": spec.fps,
        "speed": spec.speed,
        "width": spec.width,
        "height": spec.height,
        "formats": sorted(set(spec.formats)),
        "follow": follow,
    }
    if tape is not None:
        from sims.replay.clip import write_replay

        poster = (seen["first_layout"], seen["first"])
        write_replay(out, tape, spec, plan, poster)
    if not video:  # nothing left to draw: the clip is complete
        return finish_meta(out, meta, "tinyrenderer")
    return meta


def write_data(out: Path, recording, spec, plan, name: str, params: dict, scene: str) -> None:
    """The data files every clip has: CSV, JSON and the two plots (sims/plot.py)."""
    title = f"{name} · {plan.seed} · {recording.subject}"  # names only: any site language
    xs, ys = recording.column("x"), recording.column("y")
    (out / FILES["plot"]).write_text(path_svg(xs, ys, title, recording.breaks), encoding="utf-8")
    (out / FILES["series"]).write_text(series_svg(recording, spec.fps), encoding="utf-8")
    (out / FILES["csv"]).write_text(recording.to_csv(), encoding="utf-8")
    header = {"kind": spec.kind, "scenario": name, "seed": plan.seed, "params": params}
    header |= {"fps": spec.fps, "speed": spec.speed, "scene": scene}
    (out / FILES["json"]).write_text(recording.to_json(**header), encoding="utf-8")


def finish_meta(out: Path, meta: dict[str, Any], renderer: str) -> dict[str, Any]:
    """The clip's meta.json: what ran, and the files the entry holds."""
    meta = dict(meta)
    (out / STATES).unlink(missing_ok=True)
    meta.pop("follow", None)
    meta["renderer"] = renderer
    meta["files"] = {kind: name for kind, name in FILES.items() if (out / name).is_file()}
    (out / META).write_text(json.dumps(meta, sort_keys=True, indent=1) + "\n", encoding="utf-8")
    return meta


def _portable(path: str) -> str:
    from sims.clip_cache import display_path

    return display_path(path)


# -- phase 2: render a frame range -------------------------------------------------------------
class WorldCache:
    """The worker's render World, kept while consecutive ranges come from the same clip."""

    def __init__(self) -> None:
        self.key: str | None = None
        self.world: World | None = None
        self.path: np.ndarray | None = None  # the followed object's positions (camera plans)

    def get(self, key: str, make: Callable[[], World]) -> World:
        if key != self.key or self.world is None:
            self.close()
            self.world = make()
            self.key = key
        return self.world

    def close(self) -> None:
        if self.world is not None:
            self.world.close()
        self.world, self.key, self.path = None, None, None


def followed_path(
    world: World, layout: list[tuple[int, tuple[int, ...]]], states: np.ndarray, follow: str
) -> np.ndarray:
    """Where ``follow`` is in every recorded frame (N×3): what the overview camera frames and
    the trail draws. A function of the tape alone, so every frame range gets the same plan."""
    out = np.empty((len(states), 3), dtype=np.float64)
    for n, state in enumerate(states):
        apply_state(world, layout, state)
        out[n] = world.object_pose(follow)[0]
    return out


def range_file(out: Path, start: int) -> Path:
    return out / f"frames-{start:06d}.rgb"


def render_range(
    job: dict[str, Any], progress: Progress | None = None, worlds: WorldCache | None = None
) -> dict[str, Any]:
    """Render frames ``job["start"]`` to ``job["stop"]`` of the state tape to a raw RGB file."""
    out = Path(job["out_dir"])
    spec = job["spec"]
    width, height = spec["width"], spec["height"]
    with np.load(out / STATES) as tape:
        every_state = tape["states"]
        states = every_state[job["start"] : job["stop"]]
        layout = [(b, tuple(j)) for b, j in json.loads(str(tape["layout"]))]
        setup = json.loads(str(tape["world"]))
    renderer = requested_renderer()
    cache = worlds or WorldCache()
    world_key = json.dumps([str(out), renderer])

    def make() -> World:
        world = World(setup["scene"], seed=setup["seed"], render_with=renderer, **setup["options"])
        if not covers(world, layout):
            world.close()
            raise SceneChanged("the rebuilt scene does not match the recorded one")
        return world

    world = cache.get(world_key, make)
    try:
        mode, trail = spec.get("camera", "follow"), spec.get("trail", False)
        if (mode != "follow" or trail) and cache.path is None:
            cache.path = followed_path(world, layout, every_state, job["follow"])
        fixed = None
        if mode == "overview":
            from sims.camera import matrices, overview_for
            from sims.render import FAR, FOV_DEG, NEAR

            ov = overview_for(cache.path, world.model.camera.yaw, FOV_DEG, width / height)
            fixed = matrices(ov, FOV_DEG, width / height, NEAR, FAR)
        world.new_render_sequence()
        deadline = time.monotonic() + job["time_limit"]
        with open(range_file(out, job["start"]), "wb") as f:
            for n, state in enumerate(states, 1):
                if time.monotonic() > deadline:
                    raise RecordingTimeout(f"time limit passed at frame {job['start'] + n - 1}")
                apply_state(world, layout, state)
                image = world.render(width, height, job["follow"], fixed)
                if trail:
                    from sims.camera import draw_trail
                    from sims.render import chase_camera

                    view, proj = fixed or chase_camera(world, width, height, job["follow"])
                    image = draw_trail(image, cache.path[: job["start"] + n], view, proj)
                f.write(np.ascontiguousarray(image).tobytes())
                if progress is not None:
                    progress(n)
        return {
            "renderer": world.renderer,
            "frames": len(states),
            "fallback": world.renderer_fallback,
        }
    finally:
        if worlds is None:
            cache.close()


# -- phase 3: encode ---------------------------------------------------------------------------
def encode(job: dict[str, Any], progress: Progress | None = None) -> dict[str, Any]:
    """Join the ranges into ``clip.webm`` and, where ffmpeg has H.264, ``clip.mp4`` (+ the
    poster, unless the replay made it) and write ``meta.json``."""
    import contextlib

    out = Path(job["out_dir"])
    spec = job["spec"]
    meta = dict(job["meta"])
    width, height, total = spec["width"], spec["height"], meta["frames"]
    size = width * height * 3
    poster_index = total // 2 if "replay" not in spec.get("formats", ()) else -1
    done = 0
    with contextlib.ExitStack() as stack:
        writers: list[Any] = [
            stack.enter_context(WebmWriter(out / FILES["video"], width, height, spec["fps"]))
        ]
        if mp4_encoder() is not None:
            writers.append(
                stack.enter_context(Mp4Writer(out / FILES["mp4"], width, height, spec["fps"]))
            )
        for start in job["starts"]:
            path = range_file(out, start)
            with open(path, "rb") as f:
                while chunk := f.read(size):
                    frame = np.frombuffer(chunk, dtype=np.uint8).reshape(height, width, 3)
                    if done == poster_index:
                        write_png(out / FILES["poster"], frame)
                    for writer in writers:
                        writer.write(frame)
                    done += 1
                    if progress is not None:
                        progress(done)
            path.unlink()
    if done != total:
        raise RuntimeError(f"encoded {done} frames, expected {total}")
    return finish_meta(out, meta, job["renderer"])


def range_starts(total: int, size: int) -> list[int]:
    """Frame range starts: fixed by the clip's frame count alone, never by the worker count."""
    return list(range(0, total, size)) or [0]


RANGE_FRAMES = 60  # frames per render job: ~1 s of EGL work, small enough to share out


def simulate_fenced(job: dict[str, Any], progress: Progress | None = None) -> dict[str, Any]:
    """``simulate`` in a forked child with no network and no socket outside it (the clip's
    scripts, Python and Lua, run there; sims/remote_api/isolate.py), killed past its limit."""
    from sims.remote_api.isolate import KILL_GRACE, call_isolated

    limit = job["time_limit"] + KILL_GRACE
    return call_isolated(lambda: simulate(job, progress), limit, _label(job["spec"]))


def render_job(job: dict[str, Any]) -> tuple[dict[str, Any], str | None]:
    """All three phases in this process (the simulation in a fenced child): the clip's meta
    (as the workers would write it) and why EGL fell back (None: it did not; see
    ``sims.render.fallback_note``)."""
    meta = simulate_fenced(job)
    if "files" in meta:  # no video: simulate finished the clip
        return meta, None
    starts = range_starts(meta["frames"], RANGE_FRAMES)
    worlds = WorldCache()
    renderers = set()
    fallbacks = set()
    try:
        for start in starts:
            stop = min(start + RANGE_FRAMES, meta["frames"])
            part = {**job, "start": start, "stop": stop, "follow": meta["follow"]}
            drawn = render_range(part, worlds=worlds)
            renderers.add(drawn["renderer"])
            fallbacks.add(drawn["fallback"])
    finally:
        worlds.close()
    renderer = "+".join(sorted(renderers))
    meta = encode({**job, "meta": meta, "starts": starts, "renderer": renderer})
    return meta, "; ".join(sorted(r for r in fallbacks if r)) or None


# -- the worker process ------------------------------------------------------------------------
def run_phase(job: dict[str, Any], progress: Progress, worlds: WorldCache) -> dict[str, Any]:
    phase = job["phase"]
    if phase == "simulate":
        worlds.close()  # a World per process with EGL: free it before the next clip's
        return simulate_fenced(job, progress)
    if phase == "render":
        return render_range(job, progress, worlds)
    if phase == "encode":
        return encode(job, progress)
    raise ValueError(f"unknown phase {phase!r}")


def outcome(job: dict[str, Any], run: Callable[[], dict[str, Any]]) -> dict[str, Any]:
    """``{"ok": True, "result": ...}`` or ``{"ok": False, "error": one line naming the clip}``."""
    label = _label(job["spec"])
    try:
        return {"ok": True, "result": run()}
    except RecordingTimeout as exc:
        limit = job["time_limit"]
        shown = f"{limit:g} s" if math.isfinite(limit) else "inf"
        return {"ok": False, "error": f"{label} passed its wall-clock limit of {shown} ({exc})"}
    except Exception as exc:  # reported, not raised: the other clips go on
        where = traceback.extract_tb(exc.__traceback__)[-1]
        return {
            "ok": False,
            "error": f"{label} failed: {type(exc).__name__}: {exc} "
            f"({Path(where.filename).name}:{where.lineno})",
        }


def serve() -> None:
    """Job loop of a worker process (see the module docstring for the protocol)."""
    channel = os.fdopen(os.dup(1), "w", buffering=1, encoding="utf-8")
    os.dup2(2, 1)  # pybullet and EGL print at the C level: into the log, not the channel
    sys.stdout = sys.stderr
    worlds = WorldCache()

    def send(message: dict[str, Any]) -> None:
        channel.write(json.dumps(message) + "\n")

    send({"ready": True})  # imports done: the parent starts the job's wall clock now

    for line in sys.stdin:
        if not line.strip():
            continue
        job = json.loads(line)
        last = [0.0]

        def progress(n: int, job_id: int = job["id"], last: list[float] = last) -> None:
            now = time.monotonic()
            if now - last[0] >= 0.1:
                last[0] = now
                send({"id": job_id, "progress": n})

        send({"id": job["id"], **outcome(job, lambda job=job: run_phase(job, progress, worlds))})
    worlds.close()


if __name__ == "__main__":
    serve()
