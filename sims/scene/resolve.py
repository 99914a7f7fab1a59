"""``open_scene(name_or_path)``: what the remote API runner, the clips and the World load.

A bundled name (``"cart"``; ``"2w1a"``) stays a name; ``"2w1a"`` is built from the scene
description shipped as package data in ``sims/scene/bundled/`` (derived from the course's
``2w1a.ttt``; installed with the package, so a wheel behaves as a checkout). A bundled file that
is missing is an error (an incomplete install).
Anything else is a scene file path (``.ttt``, ``.simscene.xml``, or the repository's
``.scene.json``), loaded once per process and file version, and a ``.ttt`` or XML file decoded
once per content across processes (sims/scene/scene_cache.py; loading a scene runs nothing). A
missing or unreadable file raises :class:`SceneFileError` with a one-line message naming it.
"""

from __future__ import annotations

import os
from functools import lru_cache
from pathlib import Path
from typing import Any

from sims.models import SCENES

BUNDLED_SCENES = Path(__file__).resolve().parent / "bundled"
#: Bundled names served from a scene description in sims/scene/bundled/ (the file is the truth).
FILE_SCENES = {"2w1a": "2w1a.scene.json"}


class SceneFileError(ValueError):
    """A scene file that cannot be opened or read (message names the file)."""


def bundled_names() -> list[str]:
    return sorted(set(SCENES) | set(FILE_SCENES))


def bundled_file(name: str) -> Path:
    """The package-data file a bundled scene name is built from; missing is an error."""
    path = BUNDLED_SCENES / FILE_SCENES[name]
    if not path.is_file():
        raise SceneFileError(
            f"{path}: the bundled scene {name!r} is missing from the installed sims package "
            "(reinstall sitegen)"
        )
    return path


def is_bundled(name: Any) -> bool:
    return isinstance(name, str) and (name in SCENES or name in FILE_SCENES)


def open_scene(name_or_path: str | os.PathLike[str]) -> Any:
    """A bundled scene name (str, for sims.models) or a loaded Scene model."""
    if isinstance(name_or_path, str) and name_or_path in FILE_SCENES:
        return load_file(bundled_file(name_or_path))
    if isinstance(name_or_path, str) and name_or_path in SCENES:
        return name_or_path
    path = Path(name_or_path).expanduser()
    if not path.is_file():
        known = ", ".join(bundled_names())
        raise SceneFileError(f"{name_or_path}: no such scene file (bundled scenes: {known})")
    return load_file(path)


def load_file(path: Path) -> Any:
    path = path.resolve()
    stat = path.stat()
    return _load(str(path), stat.st_mtime_ns, stat.st_size)


@lru_cache(maxsize=16)
def _load(path: str, mtime_ns: int, size: int) -> Any:
    del mtime_ns, size  # part of the cache key: an edited file is read again
    if path.endswith(".scene.json"):
        from sims.scene.jsonfile import read_json

        return read_json(Path(path))
    from sims.scene.errors import SceneError
    from sims.scene.scene_cache import load as cached

    try:
        return cached(path, _decode)  # decoded once per file content (scene_cache.py)
    except SceneFileError:
        raise
    except SceneError as exc:  # its one line names the file already
        raise SceneFileError(str(exc)) from None
    except (OSError, ValueError) as exc:
        raise SceneFileError(f"{path}: {exc}") from exc


def _decode(path: str) -> Any:
    """Read a .ttt or XML scene (the readers are imported only when a file is decoded)."""
    try:
        from sims.scene.load import load_scene
    except ImportError as exc:  # the readers are not there yet
        raise SceneFileError(f"{path}: scene files cannot be read here ({exc})") from exc
    return load_scene(path)
