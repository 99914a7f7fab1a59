"""``load_scene(path)``: read any CoppeliaSim scene file into the scene model.

The format is chosen by the file's first bytes, not its name: ``VREP`` is the binary format
(:mod:`sims.scene.ttt`), ``<`` (after an optional byte-order mark and white space) the XML format
(:mod:`sims.scene.xml`). Anything unreadable raises :class:`SceneError` (``file: error: object:
message``); what a reader understood only in part is listed in ``Scene.notes``. Loading runs
nothing. Only a regular file is read, and never more than ``MAX_FILE_BYTES`` of it
(:mod:`sims.scene.limits`): ``/dev/zero`` or a named pipe is refused, not read until memory ends.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

from sims.scene.errors import SceneError
from sims.scene.limits import MAX_FILE_BYTES
from sims.scene.model import Scene
from sims.scene.ttt import read_ttt
from sims.scene.xml import read_xml

__all__ = ["SceneError", "load_scene", "read_scene"]

MAX_BYTES = MAX_FILE_BYTES  # a scene file larger than this is refused, not read into memory


def load_scene(path: str | Path) -> Scene:
    path = Path(path)
    return read_scene(read_file(path), str(path))


def read_file(path: Path) -> bytes:
    """The bytes of a scene file: a regular file of at most ``MAX_BYTES``, read once (a file
    that grows meanwhile is refused too)."""
    source = str(path)
    too_big = f"larger than {MAX_BYTES} bytes: larger than any scene this reader accepts"
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    except IsADirectoryError:
        raise SceneError(source, "file", "is a directory, not a scene file") from None
    except FileNotFoundError:
        raise SceneError(source, "file", "no such file") from None
    except OSError as exc:
        raise SceneError(source, "file", f"cannot be read: {exc.strerror or exc}") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise SceneError(source, "file", "is a directory, not a scene file")
        if not stat.S_ISREG(info.st_mode):
            raise SceneError(source, "file", "not a regular file (a device or a pipe): not read")
        if info.st_size > MAX_BYTES:
            raise SceneError(source, "file", f"{info.st_size} bytes: {too_big}")
        chunks: list[bytes] = []
        total = 0
        while total <= MAX_BYTES:
            piece = os.read(fd, min(1 << 20, MAX_BYTES + 1 - total))
            if not piece:
                break
            chunks.append(piece)
            total += len(piece)
        if total > MAX_BYTES:
            raise SceneError(source, "file", too_big)
        return b"".join(chunks)
    except OSError as exc:
        raise SceneError(source, "file", f"cannot be read: {exc.strerror or exc}") from None
    finally:
        os.close(fd)


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
