"""What a clip's figure and gallery entry say, in the site's language, from a render's meta.

The words come from sitegen/i18n.py; the numbers from the clip's meta (sims/clip_worker.py):
``duration`` is simulated seconds, a video lasts ``frames / fps`` seconds (a time-lapse of
``speed``), a replay plays simulated time at ``speed`` unless the reader picks another.
Captions therefore state all three, so they never contradict the player (issue 26: a gallery
said "75.0 s" under a 0:09 video). Parameters are shown as ``name: value``, leaving out unset
(None) values and naming files by their file name; the renderer is an internal and not shown.
"""

from __future__ import annotations

import math
from typing import Any

SPEEDS = (0.25, 0.5, 1.0, 2.0, 4.0)  # the replay's speed choices; the clip's own is added
VIEWER_WORDS = ("play", "pause", "timeline", "speed", "reset_view", "fullscreen", "replay_keys")
VIEWER_WORDS += ("no_webgl", "replay_failed", "video", "series")  # the replay figure's words


def number(value: float) -> str:
    """``4`` for 4.0, ``0.25`` as is: how speeds and parameters read."""
    return f"{value:g}"


def clock(seconds: float) -> str:
    """m:ss, as a video player shows a length (whole seconds, rounded down)."""
    whole = int(math.floor(seconds + 1e-9))
    return f"{whole // 60}:{whole % 60:02d}"


def video_seconds(meta: dict[str, Any]) -> float:
    fps = float(meta.get("fps") or 1)
    return float(meta.get("frames") or 0) / fps


def facts(meta: dict[str, Any], strings: dict[str, str], replay: bool) -> str:
    """``模擬 75.0 秒 · 8× 快轉 · 影片 0:09`` (video) or ``模擬 75.0 秒 · 以 8× 播放`` (replay)."""
    simulated = strings["simulated_seconds"].format(s=f"{float(meta.get('duration', 0)):.1f}")
    speed = float(meta.get("speed") or 1)
    parts = [simulated]
    if replay:
        if speed != 1:
            parts.append(strings["played_at"].format(x=number(speed)))
    else:
        if speed != 1:
            parts.append(strings["timelapse"].format(x=number(speed)))
        parts.append(strings["video_length"].format(t=clock(video_seconds(meta))))
    return " · ".join(parts)


def speed_choices(speed: float) -> list[dict[str, Any]]:
    """The speed selector's options, the clip's own speed among them and selected."""
    values = sorted(set(SPEEDS) | {float(speed)})
    return [
        {"value": number(v), "label": f"{number(v)}×", "selected": v == float(speed)}
        for v in values
    ]


def parameter_text(meta: dict[str, Any], strings: dict[str, str]) -> str:
    """``亂數種子 2021 · moves: 5 · scene: rover.simscene.xml``: no JSON, no unset values."""
    parts = [f"{strings['seed']} {meta.get('seed')}"]
    for key, value in sorted((meta.get("params") or {}).items()):
        if value is None:
            continue
        if isinstance(value, str) and value.startswith("file:"):
            value = value[len("file:") :]
        elif isinstance(value, bool):
            value = "true" if value else "false"
        elif isinstance(value, float):
            value = number(value)
        parts.append(f"{key}: {value}")
    return " · ".join(parts)


def length_text(meta: dict[str, Any], strings: dict[str, str], formats: list[str]) -> str:
    """The gallery's length row: the caption's facts, and for a video its frames and size."""
    text = facts(meta, strings, replay="replay" in formats)
    if "video" in formats:
        video = facts(meta, strings, replay=False) if "replay" in formats else text
        if "replay" in formats:
            text += " · " + strings["video"] + ": " + video.split(" · ", 1)[-1]
        text += (
            f" ({meta.get('frames', '?')} {strings['frames']}, "
            f"{meta.get('width')}×{meta.get('height')})"
        )
    return text
