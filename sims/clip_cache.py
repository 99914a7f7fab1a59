"""Content-hash keys for clips and the on-disk cache layout.

Key = sha256 over: the source's files (scenario file, script...) by content and file name, the
code that renders a clip as :func:`located.code_keys.code_key` keys it (the import closure of
the clip worker and of the source kind's module: our modules and data files by package-relative
name and bytes, never mtimes or absolute paths, so a checkout copied or moved elsewhere hits the
same entries; the versions of the third-party libraries it imports), the spec fields (params,
seed, size, fps, seconds, speed, camera, trail, formats, the requested renderer:
:func:`sims.clips.spec_fields`) and the MP4 encoder found on the system. Layout::

    cache_dir/<key>/        meta.json and the files its "files" lists (FILES: the names by kind)
    cache_dir/latest/<name>.json   {"key": ...}  the last good render of each clip name
    cache_dir/failed/<key>.json    {"name": ..., "error": ...}  a render of these inputs failed
"""

from __future__ import annotations

import hashlib
import json
import re
import shutil
from functools import lru_cache
from pathlib import Path
from typing import Any

PACKAGE_DIR = Path(__file__).resolve().parent
ROOT_DIR = PACKAGE_DIR.parent
CACHE_FORMAT = 2
#: the module every clip's code runs from (the worker; its closure covers the built-in sources)
ENGINE = "sims.clip_worker"
FILES = {  # every kind of file a clip may have; an entry's meta.json lists the ones it has
    "video": "clip.webm",
    "mp4": "clip.mp4",
    "poster": "poster.png",
    "csv": "data.csv",
    "json": "data.json",
    "plot": "path.svg",
    "series": "series.svg",
    "replay": "replay.glb",
    "replay_js": "replay.js",
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


def _encoder() -> str:
    """The MP4 encoder (a program, not a Python library: outside the code key)."""
    from sims.video import mp4_encoder

    return mp4_encoder() or "none"


def clip_key(fields: dict[str, Any], source_files: list[str], code: tuple[str, ...] = ()) -> str:
    """Hex key from the spec fields that change the output, the source files' bytes and the
    code that runs: :data:`ENGINE` and the modules ``code`` names (a source kind's module)."""
    from located.code_keys import code_key

    files = {_source_name(f): file_digest(f) for f in source_files}
    payload = {
        "format": CACHE_FORMAT,
        "fields": fields,
        "files": dict(sorted(files.items())),
        "code": code_key(ENGINE, *sorted(set(code))),
        "encoder": _encoder(),
    }
    text = json.dumps(payload, sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


def _file_params(params: dict[str, Any]) -> dict[str, Path]:
    """Params naming a file (a scene file, say): keyed by the file's bytes, not its path."""
    out = {}
    for key, value in params.items():
        if isinstance(value, str) and Path(value).is_absolute() and Path(value).is_file():
            out[key] = Path(value)
    return out


def _source_name(path: str | Path) -> str:
    """How a source file is named in a key: package-relative inside sims/, else its file name."""
    p = Path(path).resolve()
    try:
        return p.relative_to(PACKAGE_DIR).as_posix()
    except ValueError:
        return f"source/{p.name}"


def scene_files(scene: str) -> list[str]:
    """The scene file a clip's world is built from: a path, or a bundled name's shipped file."""
    if Path(scene).is_absolute() and Path(scene).is_file():
        return [scene]
    try:
        from sims.scene.resolve import FILE_SCENES, bundled_file
    except ImportError:
        return []
    return [str(bundled_file(scene))] if scene in FILE_SCENES else []


def key_files(plan: Any) -> list[str]:
    """The files whose bytes identify a clip's source: the plan's, the scene file its world is
    built from, and files its params name (a script's scene file)."""
    files = [*plan.hash_files, *scene_files(str(plan.scene))]
    files += [str(p) for p in _file_params(plan.params).values()]
    return list(dict.fromkeys(files))


def portable_params(params: dict[str, Any]) -> dict[str, Any]:
    """``params`` with file paths replaced by ``file:NAME`` (for keys, meta and data files)."""
    return {**params, **{k: f"file:{p.name}" for k, p in _file_params(params).items()}}


def entry_dir(cache_dir: Path, key: str) -> Path:
    return Path(cache_dir) / key


def _read_meta(cache_dir: Path, key: str) -> dict[str, Any] | None:
    try:
        meta = json.loads((entry_dir(cache_dir, key) / META).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None
    return meta if isinstance(meta, dict) and isinstance(meta.get("files"), dict) else None


def entry_files(cache_dir: Path, key: str, meta: dict[str, Any] | None = None) -> dict[str, Path]:
    """The entry's files by kind (those its meta lists)."""
    meta = meta if meta is not None else _read_meta(cache_dir, key)
    d = entry_dir(cache_dir, key)
    files = meta.get("files", {}) if meta else {}
    return {kind: d / name for kind, name in files.items() if FILES.get(kind) == name}


def load_entry(cache_dir: Path, key: str) -> dict[str, Any] | None:
    """The entry's meta if the entry is complete, else None."""
    meta = _read_meta(cache_dir, key)
    if meta is None:
        return None
    files = entry_files(cache_dir, key, meta)
    if not files or not all(f.is_file() for f in files.values()):
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


def _failure_file(cache_dir: Path, key: str) -> Path:
    return Path(cache_dir) / "failed" / f"{key}.json"


def record_failure(cache_dir: Path, key: str, name: str, error: str) -> None:
    """Remember that rendering these inputs failed, so the next build does not run them again."""
    path = _failure_file(cache_dir, key)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps({"name": name, "error": error}) + "\n", encoding="utf-8")


def load_failure(cache_dir: Path, key: str) -> str | None:
    """The remembered error for these inputs, or None."""
    try:
        return str(json.loads(_failure_file(cache_dir, key).read_text(encoding="utf-8"))["error"])
    except (OSError, ValueError, KeyError, TypeError):
        return None


def clear_failure(cache_dir: Path, key: str) -> None:
    _failure_file(cache_dir, key).unlink(missing_ok=True)
