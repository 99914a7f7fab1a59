"""``load_scene(path)``: read any CoppeliaSim scene file into the scene model.

The format is chosen by the file's first bytes, not its name: ``VREP`` is the binary format
(:mod:`sims.scene.ttt`), ``<`` (after an optional byte-order mark and white space) the XML format
(:mod:`sims.scene.xml`). Anything unreadable raises :class:`SceneError` (``file: error: object:
message``); what a reader understood only in part is listed in ``Scene.notes``. Loading runs
nothing.
"""

from __future__ import annotations

from pathlib import Path

from sims.scene.errors import SceneError
from sims.scene.model import Scene
from sims.scene.ttt import read_ttt
from sims.scene.xml import read_xml

__all__ = ["SceneError", "load_scene", "read_scene"]

MAX_BYTES = 256 * 1024 * 1024  # a scene file larger than this is refused, not read into memory


def load_scene(path: str | Path) -> Scene:
    path = Path(path)
    source = str(path)
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise SceneError(source, "file", f"{size} bytes: larger than any scene we read")
        data = path.read_bytes()
    except IsADirectoryError:
        raise SceneError(source, "file", "is a directory, not a scene file") from None
    except FileNotFoundError:
        raise SceneError(source, "file", "no such file") from None
    except OSError as exc:
        raise SceneError(source, "file", f"cannot be read: {exc.strerror or exc}") from None
    return read_scene(data, source)


def read_scene(data: bytes, source: str) -> Scene:
    """Read a scene from bytes; ``source`` names it in messages."""
    if data[:4] == b"VREP":
        return read_ttt(data, source)
    head = data[:64].lstrip(b"\xef\xbb\xbf \t\r\n")
    if head.startswith(b"<"):
        return read_xml(data, source)
    if not data:
        raise SceneError(source, "file", "empty file")
    raise SceneError(
        source, "file", "not a CoppeliaSim scene (neither a VREP binary header nor XML)"
    )
