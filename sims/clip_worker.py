"""Renders one clip inside a worker process: World + Recorder + WebM writer + data files.

Runs as ``python -m sims.clip_worker JOB.json`` in a fresh process, so every clip has its own
pybullet client and a clip that hangs can be killed without touching the others. The outcome
is written as ``result.json`` next to the clip files; the parent reads it (a killed worker
leaves none, a crashed one leaves its stderr in ``worker.log``).
"""

from __future__ import annotations

import json
import math
import sys
import time
import traceback
from pathlib import Path
from typing import Any

from sims.cache import FILES, META, display_path
from sims.plot import path_svg
from sims.recording import RecordingTimeout, record
from sims.render import requested_renderer
from sims.sources import load_plan_function
from sims.video import WebmWriter, write_png
from sims.world import World

JOB, RESULT, LOG = "job.json", "result.json", "worker.log"


def render_job(job: dict[str, Any]) -> dict[str, Any]:
    """Render ``job["spec"]`` into ``job["out_dir"]``; returns the meta dict."""
    from sims.clips import ClipSpec

    spec = ClipSpec(**job["spec"])
    out = Path(job["out_dir"])
    plan = load_plan_function(job["target"])(spec)
    length = spec.seconds if spec.seconds is not None else plan.duration
    poster_index = max(1, round(length * spec.fps)) // 2
    poster: list[Any] = []
    with WebmWriter(out / FILES["video"], spec.width, spec.height, spec.fps) as video:

        def on_frame(world: World) -> None:
            image = world.render(spec.width, spec.height, plan.follow or world.model.robot)
            if video.frames == poster_index:
                poster.append(image)
            video.write(image)

        recording, renderer = record(
            plan,
            fps=spec.fps,
            seconds=spec.seconds,
            on_frame=on_frame,
            deadline=time.monotonic() + job["time_limit"],
            render_with=requested_renderer(),
        )
        written = video.frames
    write_png(out / FILES["poster"], poster[0])
    title = f"{spec.scenario} (seed {plan.seed}): path of {recording.subject}"
    (out / FILES["plot"]).write_text(
        path_svg(recording.column("x"), recording.column("y"), title, recording.breaks),
        encoding="utf-8",
    )
    (out / FILES["csv"]).write_text(recording.to_csv(), encoding="utf-8")
    header = {
        "kind": spec.kind,
        "scenario": spec.scenario,
        "seed": plan.seed,
        "params": plan.params,
        "fps": spec.fps,
        "scene": plan.scene,
    }
    (out / FILES["json"]).write_text(recording.to_json(**header), encoding="utf-8")
    meta = {
        "kind": spec.kind,
        "scenario": spec.scenario,
        "description": plan.description,
        "source": display_path(plan.source_path),
        "scene": plan.scene,
        "seed": plan.seed,
        "params": plan.params,
        "duration": round(written / spec.fps, 3),
        "frames": written,
        "fps": spec.fps,
        "width": spec.width,
        "height": spec.height,
        "renderer": renderer,
        "files": dict(FILES),
    }
    (out / META).write_text(json.dumps(meta, sort_keys=True, indent=1) + "\n", encoding="utf-8")
    return meta


def child_main(job: dict[str, Any]) -> None:
    """Process entry point: never raises; the outcome goes to result.json."""
    started = time.monotonic()
    label = f"{job['spec'].get('kind', 'scenario')} {job['spec']['scenario']!r}"
    try:
        meta = render_job(job)
        result = {"ok": True, "meta": meta}
    except RecordingTimeout as exc:
        result = {
            "ok": False,
            "error": f"{label} passed its time limit of {_seconds(job['time_limit'])} ({exc})",
        }
    except Exception as exc:  # reported, not raised: the other clips go on
        where = traceback.extract_tb(exc.__traceback__)[-1]
        result = {
            "ok": False,
            "error": f"{label} failed: {type(exc).__name__}: {exc} "
            f"({Path(where.filename).name}:{where.lineno})",
        }
    result["seconds"] = round(time.monotonic() - started, 3)
    Path(job["out_dir"], RESULT).write_text(json.dumps(result), encoding="utf-8")


def _seconds(value: float) -> str:
    return f"{value:g} s" if math.isfinite(value) else "inf"


if __name__ == "__main__":
    child_main(json.loads(Path(sys.argv[1]).read_text(encoding="utf-8")))
