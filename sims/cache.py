"""Content-hash keys for clips and the on-disk cache layout.

Key = sha256 over: the source's files (scenario file, ...) and the engine files below, by
content and package-relative name (never mtimes or absolute paths, so a fresh checkout hits the
same entries), the params, seed, size, fps, seconds, the requested renderer and the pybullet
and OpenCV versions. Layout::

    cache_dir/<key>/        clip.webm poster.png data.csv data.json path.svg meta.json
    cache_dir/latest/<name>.json   {"key": ...}  the last good render of each clip name
"""

from __future__ import annotations

import hashlib
import json
import re
import shutil
from functools import lru_cache
from importlib import metadata
from pathlib import Path
from typing import Any

PACKAGE_DIR = Path(__file__).resolve().parent
ROOT_DIR = PACKAGE_DIR.parent
CACHE_FORMAT = 1
ENGINE_FILES = (
    "world.py",
    "recording.py",
    "render.py",
    "video.py",
    "plot.py",
    "clip_worker.py",
    "sources.py",
    "models/*.py",
    "scenarios/__init__.py",
)
FILES = {
    "video": "clip.webm",
    "poster": "poster.png",
    "csv": "data.csv",
    "json": "data.json",
    "plot": "path.svg",
}
META = "meta.json"


def display_path(path: str | Path) -> str:
    """Package-relative (``sims/scenarios/x.py``) where possible, so keys and meta are portable."""
    p = Path(path).resolve()
    try:
        return p.relative_to(ROOT_DIR).as_posix()
    except ValueError:
        return p.name


@lru_cache(maxsize=256)
def _file_digest(path: str, size: int, mtime_ns: int) -> str:
    """Digest of the bytes; size and mtime only make the memo safe within one process."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def file_digest(path: str | Path) -> str:
    p = Path(path)
    st = p.stat()
    return _file_digest(str(p.resolve()), st.st_size, st.st_mtime_ns)


def engine_files() -> list[Path]:
    out: list[Path] = []
    for pattern in ENGINE_FILES:
        out += sorted(PACKAGE_DIR.glob(pattern))
    return out


def _versions() -> dict[str, str]:
    import cv2

    try:
        pybullet = metadata.version("pybullet")
    except metadata.PackageNotFoundError:
        pybullet = "unknown"
    return {"pybullet": pybullet, "opencv": cv2.__version__}


def clip_key(fields: dict[str, Any], source_files: list[str]) -> str:
    """Hex key from the spec fields that change the output and all relevant source bytes."""
    files = {display_path(f): file_digest(f) for f in [*source_files, *engine_files()]}
    payload = {
        "format": CACHE_FORMAT,
        "fields": fields,
        "files": dict(sorted(files.items())),
        "versions": _versions(),
    }
    text = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def entry_dir(cache_dir: Path, key: str) -> Path:
    return Path(cache_dir) / key


def entry_files(cache_dir: Path, key: str) -> dict[str, Path]:
    d = entry_dir(cache_dir, key)
    return {kind: d / name for kind, name in FILES.items()}


def load_entry(cache_dir: Path, key: str) -> dict[str, Any] | None:
    """The entry's meta if the entry is complete, else None."""
    d = entry_dir(cache_dir, key)
    try:
        meta = json.loads((d / META).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    if not all(f.is_file() for f in entry_files(cache_dir, key).values()):
        return None
    return meta


def commit_entry(cache_dir: Path, key: str, tmp: Path) -> None:
    """Move a finished temp dir into place; an entry that appeared meanwhile wins."""
    target = entry_dir(cache_dir, key)
    if load_entry(cache_dir, key) is not None:
        shutil.rmtree(tmp, ignore_errors=True)
        return
    shutil.rmtree(target, ignore_errors=True)
    tmp.rename(target)


def _pointer(cache_dir: Path, name: str) -> Path:
    safe = re.sub(r"[^A-Za-z0-9._-]+", "_", name)
    return Path(cache_dir) / "latest" / f"{safe}.json"


def set_latest(cache_dir: Path, name: str, key: str) -> None:
    path = _pointer(cache_dir, name)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps({"key": key}) + "\n"
    if not path.is_file() or path.read_text(encoding="utf-8") != text:
        tmp = path.with_suffix(".tmp")
        tmp.write_text(text, encoding="utf-8")
        tmp.replace(path)


def latest_key(cache_dir: Path, name: str) -> str | None:
    try:
        key = json.loads(_pointer(cache_dir, name).read_text(encoding="utf-8"))["key"]
    except (OSError, ValueError, KeyError, TypeError):
        return None
    return key if load_entry(cache_dir, key) is not None else None
