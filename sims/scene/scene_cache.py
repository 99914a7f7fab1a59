"""A content-hash cache of decoded scene files: a scene read again costs a JSON read, not a decode.

Why: every remote API run, clip and benchmark repeat is a fresh process (runs are isolated), so
the in-process memo in sims/scene/resolve.py never sees a second read; decoding the course's 1 MB
``2w1a.ttt`` (Huffman tables, then the objects) takes 0.3-0.4 s of a 2-3 s run, reading it back
from here about 0.05 s.

Key: sha256 over the readers' code (:func:`located.code_keys.code_key` of ``sims.scene.load``:
the modules a decoding runs, their data files and library versions, so a changed reader never
serves an old decoding) and the file's bytes (never its name, time or place). Entry:
``<key>.json``, the :class:`sims.scene.model.Scene` written field by field with floats in full
(``repr``) precision, read back through the checked reader of sims/scene/jsonfile.py: a cache file
is data, loading it runs nothing (no pickle). An entry is only written when reading it back gives
a Scene equal to the decoded one, so a hit is exactly what decoding would give; ``source`` is not
stored (it is the path the scene is read from now).

Where: ``$SITEGEN_SCENE_CACHE`` (``off`` turns the cache off), else
``$XDG_CACHE_HOME/sitegen/scenes``, else ``~/.cache/sitegen/scenes``: outside any project, so
nothing is ever committed. Writes are atomic (a temporary file renamed); an entry that cannot be
read is decoded again and replaced; a folder that cannot be written is not an error (the scene is
simply decoded each time). At most ``MAX_ENTRIES`` entries are kept (the oldest go first).
"""

from __future__ import annotations

import base64
import contextlib
import dataclasses
import hashlib
import json
import os
import tempfile
from collections.abc import Callable
from functools import lru_cache
from pathlib import Path

from sims.scene import jsonfile
from sims.scene.model import Scene, TextureMapping

FORMAT = "sitegen-scene-cache/1"
ENV = "SITEGEN_SCENE_CACHE"
MAX_ENTRIES = 64
#: the module scene files are decoded from (sims/scene/resolve.py ``_decode``)
READERS = "sims.scene.load"


def cache_dir() -> Path | None:
    """The cache folder, or None when ``$SITEGEN_SCENE_CACHE`` is ``off`` (or there is no home)."""
    chosen = os.environ.get(ENV, "").strip()
    if chosen.lower() == "off":
        return None
    if chosen:
        return Path(chosen).expanduser()
    base = os.environ.get("XDG_CACHE_HOME", "").strip()
    try:
        root = Path(base) if base else Path.home() / ".cache"
    except RuntimeError:  # no home folder to be found: no cache
        return None
    return root / "sitegen" / "scenes"


@lru_cache(maxsize=1)
def readers_digest() -> str:
    """The key of the code that decodes (:data:`READERS`) and stores a scene (this module and
    its JSON reader): their import closure, once per process."""
    from located.code_keys import code_key

    return hashlib.sha256(f"{FORMAT}\0{code_key(READERS, __name__)}".encode()).hexdigest()


def key_for(data: bytes) -> str:
    return hashlib.sha256(readers_digest().encode() + data).hexdigest()[:40]


def dumps(scene: Scene) -> str:
    """The scene without its ``source``, floats exact; sorted keys, so the same scene gives the
    same bytes."""
    plain = _plain(dataclasses.replace(scene, source=""))
    return json.dumps({"format": FORMAT, "scene": plain}, sort_keys=True, separators=(",", ":"))


NUMBERS = {int, float}


@lru_cache(maxsize=64)
def _names(cls: type) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(cls))


def _plain(value: object) -> object:
    """Records as dicts and sequences as lists (what dataclasses.asdict gives, without its deep
    copy of every number: a scene holds tens of thousands)."""
    if dataclasses.is_dataclass(value):
        names = _names(type(value))
        if isinstance(value, TextureMapping):  # its image is held once, in Scene.textures
            names = tuple(n for n in names if n != "image")
        return {name: _plain(getattr(value, name)) for name in names}
    if isinstance(value, bytes):
        return base64.b64encode(value).decode("ascii")
    if isinstance(value, (tuple, list)):
        if set(map(type, value)) <= NUMBERS:
            return list(value)
        return [_plain(v) for v in value]
    return value


def loads(text: str, source: str) -> Scene:
    """An entry read back through jsonfile's checked reader (raises ValueError if it is not one)."""
    data = json.loads(text)
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        raise ValueError("not a scene cache entry")
    scene = jsonfile._build(Scene, data.get("scene"), source)
    return dataclasses.replace(jsonfile.with_textures(scene, source), source=source)


def load(path: str | Path, decode: Callable[[str], Scene]) -> Scene:
    """``decode(path)``, or the cached decoding of a file with the same bytes."""
    source = str(path)
    folder = cache_dir()
    if folder is None:
        return decode(source)
    from sims.scene.load import read_file  # bounded: a regular file of limited size

    data = read_file(Path(source))  # raises SceneError naming the problem
    entry = folder / f"{key_for(data)}.json"
    try:
        scene = loads(entry.read_text(encoding="utf-8"), source)
        with contextlib.suppress(OSError):
            os.utime(entry)  # recently used: the last to be pruned
        return scene
    except (OSError, ValueError, UnicodeDecodeError):
        pass  # no entry yet, or one that cannot be read: decode and (re)write it
    scene = decode(source)
    _store(folder, entry, scene, source)
    return scene


#: scenes larger than this (objects, mesh numbers) are not cached: writing and checking an
#: entry holds the scene three times over, and decoding such a scene is the rarer cost
MAX_CACHED = (20_000, 1_000_000)


def _store(folder: Path, entry: Path, scene: Scene, source: str) -> None:
    values = sum(
        len(m.vertices) + len(m.indices) for o in scene.objects if o.shape for m in o.shape.meshes
    )
    if len(scene.objects) > MAX_CACHED[0] or values > MAX_CACHED[1]:
        return
    text = dumps(scene)
    try:
        if loads(text, source) != scene:
            return  # something the JSON form cannot carry exactly: never cache an approximation
    except ValueError:
        return
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=folder, prefix=".", suffix=".tmp")
    except OSError:
        return  # a folder that cannot be written: decode each time
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, entry)
        _prune(folder)
    except OSError:
        Path(tmp).unlink(missing_ok=True)


def _prune(folder: Path) -> None:
    """Keep the ``MAX_ENTRIES`` newest entries."""
    entries = []
    for path in folder.glob("*.json"):
        try:
            entries.append((path.stat().st_mtime_ns, path.name, path))
        except OSError:
            continue
    for _, _, path in sorted(entries, reverse=True)[MAX_ENTRIES:]:
        path.unlink(missing_ok=True)
