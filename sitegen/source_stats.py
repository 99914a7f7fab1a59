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
from collections.abc import Callable, Iterator
from pathlib import Path, PurePosixPath
from typing import NamedTuple

#: Folder names the content scan never enters (sitegen.content).
SKIP_DIRS = {".git", ".hg", ".svn", "__pycache__", "node_modules", ".sitegen-cache"}
#: Folders below the content folder; course sites use three or four.
MAX_DEPTH = 32


def stat_key(st: os.stat_result) -> list[int]:
    """What a no-op build compares instead of reading the file: any write changes the
    change time (which, unlike the modification time, no tool can set back)."""
    return [st.st_size, st.st_mtime_ns, st.st_ctime_ns, st.st_ino]


class Found(NamedTuple):
    """One entry :class:`Walk` lists: ``rel`` is its path below the walked folder, ``real_dir``
    the real path of the folder holding it (symlinks resolved)."""

    entry: os.DirEntry
    path: Path
    rel: PurePosixPath
    real_dir: Path


class Walk:
    """The one walk of the content folder (and of the project, for ``sitegen serve``): every
    entry whose name is not hidden (``.x``) or a backup (``x~``), folder by folder in name
    order, the files of a folder before its subfolders, with its own stack (no recursion).

    A folder is only entered when the caller says so (:meth:`descend`), so each caller keeps
    its own judgement of symlinks and special files: :func:`sitegen.content.scan` follows
    links inside the content folder and reports the rest, :func:`stat_walk` gives up on any,
    the serve loop looks at them as files. :meth:`descend` holds the rules every caller shares:
    :data:`SKIP_DIRS`, the excluded folders (the output and the cache) and :data:`MAX_DEPTH`.
    A folder that cannot be listed goes to ``on_error(rel, exc)``; without one it raises."""

    def __init__(
        self,
        root: Path,
        exclude: set[Path] = frozenset(),  # type: ignore[assignment]
        on_error: Callable[[PurePosixPath, OSError], None] | None = None,
    ):
        self.exclude = {p.resolve() for p in exclude}
        self.on_error = on_error
        self._stack = [(root, PurePosixPath("."), root.resolve())]
        self._entered: list[tuple[Path, PurePosixPath, Path]] = []

    def __iter__(self) -> Iterator[Found]:
        while self._stack:
            here, rel_dir, real_dir = self._stack.pop()
            try:
                with os.scandir(here) as it:
                    entries = sorted(it, key=lambda e: e.name)
            except OSError as exc:
                if self.on_error is None:
                    raise
                self.on_error(rel_dir, exc)
                continue
            self._entered = []
            for entry in entries:
                name = entry.name
                if name.startswith(".") or name.endswith("~"):
                    continue
                yield Found(entry, here / name, rel_dir / name, real_dir)
            self._stack.extend(reversed(self._entered))

    def descend(self, found: Found, real: Path | None = None) -> str | None:
        """Walk the folder ``found`` (whose real path is ``real``, if it is a link) after the
        entries of its own folder; a skipped or excluded folder is passed over. A folder too
        deep is not entered: the reason comes back."""
        real = real if real is not None else found.real_dir / found.entry.name
        if found.entry.name in SKIP_DIRS or real in self.exclude:
            return None
        if len(found.rel.parts) > MAX_DEPTH:
            return f"folders nest deeper than {MAX_DEPTH} levels; this one was not read"
        self._entered.append((found.path, found.rel, real))
        return None


def stat_walk(content_root: Path, exclude: set[Path]) -> dict[str, list[int]] | None:
    """The stat key of every file :func:`scan` would read, without reading any: what a no-op
    build compares with the last scan's :attr:`SourceTree.stats`. None (so the full scan
    decides) as soon as anything needs :func:`scan`'s judgement: a symlink, a special file,
    an unreadable folder, a deep tree."""
    found: dict[str, list[int]] = {}
    walk = Walk(content_root, exclude)
    try:
        for item in walk:
            entry = item.entry
            if entry.is_symlink():
                return None
            if entry.is_dir(follow_symlinks=False):
                if walk.descend(item) is not None:
                    return None
            elif entry.is_file(follow_symlinks=False):
                found[str(item.rel)] = stat_key(entry.stat(follow_symlinks=False))
            else:
                return None
    except OSError:
        return None
    return found


def snapshot(root: Path, exclude: set[Path]) -> tuple:
    """Name, size and modification time of every file of ``root`` (links followed, linked
    folders not entered), by the content walk's rules: what ``sitegen serve`` compares to
    know that something changed."""
    out = []
    walk = Walk(root, exclude, on_error=lambda rel, exc: None)
    for item in walk:
        if item.entry.is_dir(follow_symlinks=False):
            walk.descend(item)
            continue
        try:
            st = item.path.stat()
        except OSError:
            continue
        out.append((str(item.rel), st.st_size, st.st_mtime_ns))
    return tuple(out)
