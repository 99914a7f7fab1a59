"""A clip's replay files: ``replay.glb``, ``replay.js`` (the same bytes for ``file://``) and the
poster.

A page opened from disk may not ``fetch`` a file beside it (Chromium refuses file:// origins),
but it may run a ``<script src>``. So the ``.glb`` also ships as a script holding it in base64,
which hands it to the page's viewer: ``window.sitegenReplay(document.currentScript, "...")``
(templates/assets/replay/replay.js). The script names no clip: two clips of the same content
share one cache entry, and the viewer knows which figure asked for it.

The poster is the replay's starting view (same camera, t = 0), drawn once by pybullet's
TinyRenderer from the recorded first state: it stands in for the viewer before it loads, when
WebGL is missing, and for readers who prefer reduced motion until they press play. One frame of
TinyRenderer costs less than starting the EGL plugin (measured: 0.1-0.2 s against 0.7-1.4 s).
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import Any

from sims.clip_cache import FILES
from sims.replay.export import FOV_DEG, ReplayTape

NEAR, FAR = 0.01, 100.0


def replay_script(glb: bytes) -> str:
    """The script form of a replay (see the module docstring)."""
    data = base64.b64encode(glb).decode("ascii")
    return f'window.sitegenReplay(document.currentScript,"{data}");\n'


def write_replay(
    out: Path, tape: ReplayTape, spec: Any, plan: Any, first: tuple[list, list[float]]
) -> None:
    """Write the replay, its script and its poster into the clip folder ``out``.

    ``first``: the state tape layout and the state of the first sample (sims/state_tape.py)."""
    aspect = spec.width / spec.height
    glb = tape.glb(fps=spec.fps, speed=spec.speed, aspect=aspect, trail=spec.trail)
    (out / FILES["replay"]).write_bytes(glb)
    (out / FILES["replay_js"]).write_text(replay_script(glb), encoding="ascii")
    write_poster(out / FILES["poster"], tape, plan, first, spec.width, spec.height)


def write_poster(
    path: Path,
    tape: ReplayTape,
    plan: Any,
    first: tuple[list, list[float]],
    width: int,
    height: int,
) -> None:
    import numpy as np

    from sims.quiet import pybullet as p
    from sims.state_tape import apply_state
    from sims.video import write_png
    from sims.world import World

    layout, state = first
    cam = tape.camera(width / height)
    with World(plan.scene, seed=plan.seed, **plan.scene_options) as world:
        apply_state(world, [(b, tuple(j)) for b, j in layout], np.asarray(state))
        view = p.computeViewMatrix(cam.eye, cam.target, (0.0, 0.0, 1.0))
        proj = p.computeProjectionMatrixFOV(FOV_DEG, width / height, NEAR, FAR)
        image = world.render(width, height, camera=(view, proj))
    write_png(path, image)
