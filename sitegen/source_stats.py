"""Stat keys of the content files: how a build knows, without reading them, that they have
not changed since the last build read them.

A no-op build compares the stat key of every content file with the one the last build
recorded (:func:`stat_walk`), and a partial build takes each unchanged file's record from
the last scan instead of reading and parsing it again (``sitegen.content.scan``'s
``known``). A file written within :data:`sitegen.content.RACY_NS` of a scan is never
trusted: a second write in the same timestamp tick would not change its key.
"""

from __future__ import annotations

import os
from pathlib import Path

#: Folder names the content scan never enters (sitegen.content).
SKIP_DIRS = {".git", ".hg", ".svn", "__pycache__", "node_modules", ".sitegen-cache"}
#: Folders below the content folder; course sites use three or four.
MAX_DEPTH = 32


def stat_key(st: os.stat_result) -> list[int]:
    """What a no-op build compares instead of reading the file: any write changes the
    change time (which, unlike the modification time, no tool can set back)."""
    return [st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_ino]


def stat_walk(content_root: Path, exclude: set[Path]) -> dict[str, list[int]] | None:
    """The stat key of every file :func:`scan` would read, without reading any: what a no-op
    build compares with the last scan's :attr:`SourceTree.stats`. None (so the full scan
    decides) as soon as anything needs :func:`scan`'s judgement: a symlink, a special file,
    an unreadable folder, a deep tree."""
    excluded = {str(p.resolve()) for p in exclude}
    found: dict[str, list[int]] = {}
    stack: list[tuple[str, str, int]] = [(str(content_root.resolve()), "", 0)]
    try:
        while stack:
            here, rel_dir, depth = stack.pop()
            with os.scandir(here) as it:
                for entry in it:
                    name = entry.name
                    if name.startswith(".") or name.endswith("~"):
                        continue
                    if entry.is_symlink():
                        return None
                    rel = f"{rel_dir}{name}"
                    if entry.is_dir(follow_symlinks=False):
                        if name in SKIP_DIRS or entry.path in excluded:
                            continue
                        if depth + 1 > MAX_DEPTH:
                            return None
                        stack.append((entry.path, f"{rel}/", depth + 1))
                    elif entry.is_file(follow_symlinks=False):
                        found[rel] = stat_key(entry.stat(follow_symlinks=False))
                    else:
                        return None
    except OSError:
        return None
    return found
