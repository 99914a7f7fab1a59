"""Scene builders by scene name. Adding a scene = a module with ``build(client, seed, **opts)``."""

from __future__ import annotations

from typing import Any

from sims.models.common import SceneModel

#: scenes built in Python (``2w1a`` is a scene file: sims/scene/resolve.py FILE_SCENES)
SCENES = {"cart": "sims.models.cart"}


def build_scene(scene: str, client: int, seed: int, **options: Any) -> SceneModel:
    import importlib

    if scene not in SCENES:
        raise ValueError(f"unknown scene {scene!r} (known: {', '.join(sorted(SCENES))})")
    return importlib.import_module(SCENES[scene]).build(client, seed, **options)
