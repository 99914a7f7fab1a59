"""Writing the site: all or nothing, only what changed, one build at a time.

A build takes a lock on its output folder (:func:`output_lock`; a second build of the same
output exits with a clear message instead of colliding), fills an empty sibling folder
(:func:`staging`) and swaps it in. On Linux the swap is one atomic ``renameat2`` exchange, so at
every instant a complete site sits at the output path; where the file system cannot exchange,
two renames are used and a site stranded between them by a crash is put back by the next build
(:func:`recover`), which also removes the temporary folders a killed build leaves. A few
changes to a big site are renamed over their old versions one file at a time instead
(:func:`_update_in_place`): every file is always complete, old or new.

Output files never share an inode with the sources (a hard link would let ``echo x >>
site/a.txt`` change ``content/a.txt``, and let a Pages upload follow whatever the source is):
files are copied, as a reflink where the file system offers one, keeping their mtime.
"""

from __future__ import annotations

import contextlib
import errno
import fcntl
import hashlib
import os
import shutil
import sys
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from sitegen.errors import BuildError, Diagnostic

_FICLONE = 0x40049409  # ioctl: share the source's blocks copy-on-write (btrfs, XFS, ...)
_RENAME_EXCHANGE = 2
_AT_FDCWD = -100
_held: dict[tuple[Path, int], int] = {}  # (lock file, thread) -> nesting depth
_held_guard = threading.Lock()


@dataclass
class OutFile:
    """One output file: bytes made by the build, or an existing file to copy."""

    digest: str
    data: bytes | None = None
    source: Path | None = None
    move: bool = False  # source is the build's own scratch file: renamed into place, not copied


def from_bytes(data: bytes) -> OutFile:
    return OutFile(hashlib.sha256(data).hexdigest(), data=data)


def file_digest(path: Path) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def _stat_key(path: Path) -> list[int] | None:
    try:
        st = path.stat()
    except OSError:
        return None
    return [st.st_size, st.st_mtime_ns, st.st_ino]


def unchanged(
    out_dir: Path, rel: str, manifest: dict[str, list], digest: str | None = None
) -> bool:
    """``rel`` is still the file the last build wrote (same stat; same digest if given)."""
    entry = manifest.get(rel)
    if not entry or (digest is not None and entry[0] != digest):
        return False
    return entry[1:] == _stat_key(out_dir / rel)


def intact(out_dir: Path, manifest: dict[str, list]) -> bool:
    """Every file of the last build is still there, untouched (the no-op check)."""
    return (
        bool(manifest)
        and out_dir.is_dir()
        and all(unchanged(out_dir, rel, manifest) for rel in manifest)
    )


@dataclass
class Survey:
    """The output folder as the build found it, one stat per file (:func:`survey`): what
    each file holds (the manifest's digest where the stat still matches, else read), its stat
    key, and the paths that share their inode with another file. Taken once per build and
    used by every "is this output file still the one the last build wrote?" question."""

    digests: dict[str, str] = field(default_factory=dict)
    keys: dict[str, list[int]] = field(default_factory=dict)
    linked: list[str] = field(default_factory=list)

    def unchanged(self, manifest: dict[str, list], rel: str, digest: str | None = None) -> bool:
        """:func:`unchanged` without another stat."""
        entry = manifest.get(rel)
        if not entry or (digest is not None and entry[0] != digest):
            return False
        return entry[1:] == self.keys.get(rel)


def survey(out_dir: Path, manifest: dict[str, list]) -> Survey:
    """Every file now in ``out_dir`` (as ``os.walk`` lists files: a symlinked folder is not
    entered), with one stat each (see :class:`Survey`)."""
    found = Survey()
    if not out_dir.is_dir():
        return found
    stack = [("", str(out_dir))]
    while stack:
        rel_dir, here = stack.pop()
        with os.scandir(here) as it:
            entries = list(it)
        for entry in entries:
            rel = rel_dir + entry.name
            if entry.is_dir():
                if not entry.is_symlink():
                    stack.append((rel + "/", entry.path))
                continue
            try:
                st = entry.stat()
                key = [st.st_size, st.st_mtime_ns, st.st_ino]
            except OSError:
                st, key = None, None
            old = manifest.get(rel)
            if key is not None and old and old[1:] == key:
                found.digests[rel] = old[0]
            else:
                found.digests[rel] = file_digest(Path(entry.path))
            if key is not None:
                found.keys[rel] = key
            with contextlib.suppress(OSError):
                if entry.is_symlink():  # the link count of the link itself
                    st = entry.stat(follow_symlinks=False)
                if st is not None and st.st_nlink > 1:
                    found.linked.append(rel)
    return found


def publish(
    out_dir: Path,
    files: dict[str, OutFile],
    manifest: dict[str, list],
    found: Survey | None = None,
    afresh: bool = False,
) -> tuple[dict[str, list], list[str]]:
    """Make ``out_dir`` hold exactly ``files``. Returns (new manifest, changed paths).
    ``found``: the :func:`survey` of ``out_dir`` the build took under the same output lock
    (taken here if not given). ``afresh`` (``build --clean``): always a new folder swapped in
    whole, so not even an empty folder is left from before."""
    with output_lock(out_dir):
        if found is None:
            found = survey(out_dir, manifest)
        now, keys, linked = dict(found.digests), dict(found.keys), found.linked
        removed = sorted(set(now) - set(files))
        for rel in linked:
            del now[rel]  # shares its inode (a site written before issue 15): write it anew
        changed = sorted(rel for rel, f in files.items() if now.get(rel) != f.digest)
        if (changed or removed) and not afresh and _few(out_dir, changed, removed, len(files)):
            _update_in_place(out_dir, files, changed, removed)
        elif changed or removed or afresh:
            keys = {}  # every file is written anew into a new folder: new inodes
            with staging(out_dir) as tmp:
                for rel in sorted(files):
                    f = files[rel]
                    target = tmp / rel
                    target.parent.mkdir(parents=True, exist_ok=True)
                    if now.get(rel) == f.digest:
                        copy_file(out_dir / rel, target)
                    elif f.data is not None:
                        target.write_bytes(f.data)
                    elif f.move and f.source is not None:
                        os.replace(f.source, target)  # pages streamed out while rendering
                    else:
                        assert f.source is not None
                        copy_file(f.source, target)
    for rel in changed:
        keys.pop(rel, None)
    new_manifest = {
        rel: [f.digest, *(keys.get(rel) or _stat_key(out_dir / rel) or [])]
        for rel, f in files.items()
    }
    return new_manifest, changed + [f"(removed) {r}" for r in removed]


#: Sites with fewer files are always published through a new folder swapped in whole (the
#: strongest guarantee, and cheap at that size); bigger ones take few changes in place.
IN_PLACE_MIN_FILES = 200


def _few(out_dir: Path, changed: list[str], removed: list[str], total: int) -> bool:
    """Few enough changes in a big enough site to update it in place (an edit of a page or
    two): copying every unchanged file into a new folder and deleting the old one would make a
    one-page edit of a 1000-page site cost as much as building it (measured: bench/
    build_bench.py). Only where each changed path is a plain file or new."""
    if total < IN_PLACE_MIN_FILES or len(changed) + len(removed) > max(32, total // 10):
        return False
    if not out_dir.is_dir():
        return False
    if out_dir.is_symlink():
        return False
    for rel in changed:
        target = out_dir / rel
        if target.is_symlink() or target.is_dir():
            return False
        for parent in target.relative_to(out_dir).parents:
            folder = out_dir / parent
            if folder.is_symlink() or (folder.exists() and not folder.is_dir()):
                return False
    return True


def _update_in_place(
    out_dir: Path, files: dict[str, OutFile], changed: list[str], removed: list[str]
) -> None:
    """Write each changed file's new version first (in the staging folder, which a crash
    leaves for :func:`recover`), then rename each over its old version: every file of the site
    is at every instant its complete old or complete new version, and the renames take
    microseconds. Unchanged files are not touched (same inode, same mtime)."""
    tmp = _sibling(out_dir, f"building-{os.getpid()}")
    shutil.rmtree(tmp, ignore_errors=True)
    tmp.mkdir()
    try:
        ready: list[tuple[Path, Path]] = []
        for number, rel in enumerate(changed):
            f = files[rel]
            if f.move and f.source is not None:
                ready.append((f.source, out_dir / rel))  # streamed page: already on disk
                continue
            part = tmp / str(number)
            if f.data is not None:
                part.write_bytes(f.data)
            else:
                assert f.source is not None
                copy_file(f.source, part)
            ready.append((part, out_dir / rel))
        _crash_point("in place, before the renames")
        for part, target in ready:
            target.parent.mkdir(parents=True, exist_ok=True)
            os.replace(part, target)
        for rel in removed:
            with contextlib.suppress(FileNotFoundError):
                os.unlink(out_dir / rel)
            for parent in (out_dir / rel).relative_to(out_dir).parents:
                if str(parent) != ".":
                    with contextlib.suppress(OSError):
                        (out_dir / parent).rmdir()  # only when empty
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def copy_file(src: Path, dst: Path) -> None:
    """A new inode with ``src``'s bytes and mtime: a reflink where the file system offers one,
    else a copy; never a hard link. ``src`` may be a symlink the content scan allowed."""
    if not _reflink(src, dst):
        shutil.copyfile(src, dst)  # in-kernel copy (sendfile) on Linux
    st = os.stat(src)
    os.utime(dst, ns=(st.st_atime_ns, st.st_mtime_ns))


def _reflink(src: Path, dst: Path) -> bool:
    with open(src, "rb") as fin, open(dst, "wb") as fout:
        try:
            fcntl.ioctl(fout.fileno(), _FICLONE, fin.fileno())
        except OSError:
            return False
    return True


# ---------------------------------------------------------------- lock, staging, swap


def _sibling(out_dir: Path, what: str) -> Path:
    return out_dir.parent / f".{out_dir.name}.sitegen-{what}"


@contextlib.contextmanager
def output_lock(out_dir: Path) -> Iterator[None]:
    """Hold the output's lock (re-entrant within a thread); recover what a crash left first.

    The lock is ``flock`` on ``.<name>.sitegen-lock`` beside the output (removed when the build
    ends), so the kernel drops it when a build dies, however it dies. A second build does not
    wait: it raises :class:`BuildError` naming the process that holds the lock."""
    out_dir = Path(os.path.abspath(out_dir))
    lock_path = _sibling(out_dir, "lock")
    key = (lock_path, threading.get_ident())
    with _held_guard:
        depth = _held.get(key, 0)
        if depth:
            _held[key] = depth + 1
    if depth:
        try:
            yield
        finally:
            with _held_guard:
                _held[key] -= 1
        return
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    fd = _acquire(lock_path, out_dir)
    try:
        with _held_guard:
            _held[key] = 1
        try:
            recover(out_dir)
            yield
        finally:
            with _held_guard:
                del _held[key]
    finally:
        with contextlib.suppress(OSError):
            os.unlink(lock_path)  # still locked: a build that opened it now re-checks the inode
        os.close(fd)  # releases the flock


def _acquire(lock_path: Path, out_dir: Path) -> int:
    """Open and flock the lock file; retry if its holder removed it meanwhile."""
    while True:
        fd = os.open(lock_path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 32, 0).decode("ascii", "replace").strip() or "unknown"
            os.close(fd)
            raise BuildError(
                "output busy",
                [
                    Diagnostic(
                        str(out_dir),
                        None,
                        "output",
                        f"another sitegen build (process {holder}) is writing this site "
                        "right now; run again when it has finished",
                    )
                ],
            ) from None
        try:
            same = os.stat(lock_path).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            os.ftruncate(fd, 0)
            os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
            return fd
        os.close(fd)  # we locked a file the previous holder had just removed: try again


def recover(out_dir: Path) -> list[str]:
    """Undo what a killed build left beside ``out_dir`` (call with the lock held).

    A previous site stranded between the two renames of the fallback swap goes back to the
    output path; temporary folders of dead builds are removed. Returns what was done."""
    done: list[str] = []
    leftovers = sorted(
        {
            *out_dir.parent.glob(f".{glob_escape(out_dir.name)}.sitegen-previous*"),
            *out_dir.parent.glob(f".{glob_escape(out_dir.name)}.previous-*"),  # before 0.2
        },
        key=lambda p: p.stat().st_mtime_ns if p.exists() else 0,
    )
    if leftovers and not os.path.lexists(out_dir):
        os.rename(leftovers.pop(), out_dir)  # the newest previous site is the last good one
        done.append(f"recovered the previous site into {out_dir}")
    for stale in [
        *leftovers,
        *out_dir.parent.glob(f".{glob_escape(out_dir.name)}.sitegen-building-*"),
        *out_dir.parent.glob(f".{glob_escape(out_dir.name)}.building-*"),  # before 0.2
    ]:
        shutil.rmtree(stale, ignore_errors=True)
        done.append(f"removed {stale.name}")
    return done


def glob_escape(name: str) -> str:
    return "".join(f"[{c}]" if c in "*?[" else c for c in name)


@contextlib.contextmanager
def staging(out_dir: Path) -> Iterator[Path]:
    """``with staging(out) as new:`` fill the empty folder ``new``; when the block ends
    normally ``new`` replaces ``out`` (see :func:`swap_in`), when it raises ``new`` is removed
    and ``out`` is left as it was. Takes the output lock (re-entrant)."""
    out_dir = Path(os.path.abspath(out_dir))
    with output_lock(out_dir):
        tmp = _sibling(out_dir, f"building-{os.getpid()}")
        shutil.rmtree(tmp, ignore_errors=True)
        tmp.mkdir()
        try:
            yield tmp
            swap_in(tmp, out_dir)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


def swap_in(new: Path, out_dir: Path) -> None:
    """Put the complete folder ``new`` at ``out_dir``; the old site is removed afterwards."""
    if not os.path.lexists(out_dir):
        os.rename(new, out_dir)
        return
    if _exchange(new, out_dir):
        _crash_point("after exchange")
        shutil.rmtree(new, ignore_errors=True)  # holds the old site now
        return
    previous = _sibling(out_dir, "previous")
    shutil.rmtree(previous, ignore_errors=True)
    os.rename(out_dir, previous)
    try:
        _crash_point("between renames")
        os.rename(new, out_dir)
    except BaseException:
        if not os.path.lexists(out_dir):
            os.rename(previous, out_dir)
        raise
    shutil.rmtree(previous, ignore_errors=True)


def _crash_point(where: str) -> None:
    """Where a crash hurts most; tests replace this to kill the build right there."""


def _exchange(a: Path, b: Path) -> bool:
    """Atomically swap two paths (Linux ``renameat2(RENAME_EXCHANGE)``); False if unsupported."""
    if not sys.platform.startswith("linux"):
        return False
    import ctypes  # here, not at the top: only a whole-site swap needs it (~3 ms to import)

    try:
        renameat2 = ctypes.CDLL(None, use_errno=True).renameat2
    except (OSError, AttributeError):
        return False
    renameat2.argtypes = [
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_int,
        ctypes.c_char_p,
        ctypes.c_uint,
    ]
    if renameat2(_AT_FDCWD, os.fsencode(a), _AT_FDCWD, os.fsencode(b), _RENAME_EXCHANGE) == 0:
        return True
    err = ctypes.get_errno()
    if err in (errno.EINVAL, errno.ENOSYS, errno.ENOTSUP, errno.EOPNOTSUPP, errno.EXDEV):
        return False
    raise OSError(err, os.strerror(err), str(b))
