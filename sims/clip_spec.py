"""``ClipSpec``: one clip to render, as plain data the renderer and its workers share.

Its own module so that the recording sources and the worker can name it without importing
the renderer (``sims.clips`` re-exports it)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

#: The clip cameras (sims/camera.py); the first is the default, everywhere (sitegen.yml too).
CAMERAS = ("follow", "overview")
DEFAULT_CAMERA = CAMERAS[0]


@dataclass(frozen=True)
class ClipSpec:
    """One clip to render. ``seconds``/``seed`` None = the source's own duration/seed.

    ``seconds`` is the simulated length; ``speed`` the time-lapse factor (``speed=4`` plays
    80 simulated seconds in 20 s of video; data files keep every sample). ``timeout``: this
    clip's wall-clock safety net per job (None: render_clips's). ``label``: a portable name
    of the source for keys and outputs (default: ``scenario``). ``formats``: what the clip is
    shown as, ``"replay"`` (a glTF scene the page plays in 3D, sims/replay/) and/or
    ``"video"`` (WebM, and MP4 where an H.264 encoder is installed)."""

    name: str
    scenario: str
    width: int = 480
    height: int = 360
    fps: int = 20
    seconds: float | None = None
    seed: int | None = None
    params: dict[str, Any] = field(default_factory=dict)
    kind: str = "scenario"
    speed: float = 1.0
    timeout: float | None = None
    label: str | None = None
    camera: str = DEFAULT_CAMERA  # or "overview": one fixed camera framing the whole path
    trail: bool = False  # the path so far drawn on the floor (sims/camera.py)
    formats: tuple[str, ...] = ("video",)  # "replay" and/or "video"


FORMATS = ("replay", "video")
