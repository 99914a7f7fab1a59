"""Files named by their content in a temporary cache folder, for pybullet calls that read
only from files (meshes for the EGL renderer, texture images): written once, atomically, so
concurrent worlds and workers share them and a half-written file is never read."""

from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path


def content_file(folder: str, suffix: str, data: bytes) -> str:
    """The path of ``data`` under ``$TMPDIR/folder``, named by its SHA-256 (written if new)."""
    directory = Path(tempfile.gettempdir()) / folder
    target = directory / f"{hashlib.sha256(data).hexdigest()[:32]}{suffix}"
    if not target.is_file():
        directory.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile("wb", dir=directory, suffix=".tmp", delete=False) as f:
            f.write(data)
        os.replace(f.name, target)
    return str(target)
