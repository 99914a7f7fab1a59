"""Writing the site: all or nothing, and only what changed.

The new site is assembled in a sibling temporary folder and swapped in with renames, so a
failed build leaves the previous site intact. Files whose bytes did not change are
hard-linked from the previous site (same inode, so their mtimes stay as they were); a build
in which nothing changed touches nothing at all.
"""

from __future__ import annotations

import hashlib
import os
import shutil
from dataclasses import dataclass
from pathlib import Path


@dataclass
class OutFile:
    """One output file: bytes made by the build, or an existing file to copy."""

    digest: str
    data: bytes | None = None
    source: Path | None = None


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


def current_digests(out_dir: Path, manifest: dict[str, list]) -> dict[str, str]:
    """Digest of each file now in ``out_dir``, trusting the manifest where the stat matches."""
    found: dict[str, str] = {}
    if not out_dir.is_dir():
        return found
    for dirpath, _dirs, files in os.walk(out_dir):
        for name in files:
            path = Path(dirpath) / name
            rel = path.relative_to(out_dir).as_posix()
            if unchanged(out_dir, rel, manifest):
                found[rel] = manifest[rel][0]
            else:
                found[rel] = file_digest(path)
    return found


def publish(
    out_dir: Path, files: dict[str, OutFile], manifest: dict[str, list]
) -> tuple[dict[str, list], list[str]]:
    """Make ``out_dir`` hold exactly ``files``. Returns (new manifest, changed paths)."""
    now = current_digests(out_dir, manifest)
    changed = sorted(rel for rel, f in files.items() if now.get(rel) != f.digest)
    removed = sorted(set(now) - set(files))
    if not changed and not removed:
        return {rel: [f.digest, *(_stat_key(out_dir / rel) or [])] for rel, f in files.items()}, []
    out_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = out_dir.parent / f".{out_dir.name}.building-{os.getpid()}"
    old = out_dir.parent / f".{out_dir.name}.previous-{os.getpid()}"
    for leftover in (tmp, old):
        if leftover.exists():
            shutil.rmtree(leftover)
    try:
        for rel in sorted(files):
            f = files[rel]
            target = tmp / rel
            target.parent.mkdir(parents=True, exist_ok=True)
            if now.get(rel) == f.digest:
                _link_or_copy(out_dir / rel, target)
            elif f.data is not None:
                target.write_bytes(f.data)
            else:
                assert f.source is not None
                _link_or_copy(f.source, target)
        if out_dir.exists():
            os.replace(out_dir, old)
        os.replace(tmp, out_dir)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        if old.exists() and not out_dir.exists():
            os.replace(old, out_dir)
        raise
    shutil.rmtree(old, ignore_errors=True)
    new_manifest = {rel: [f.digest, *(_stat_key(out_dir / rel) or [])] for rel, f in files.items()}
    return new_manifest, changed + [f"(removed) {r}" for r in removed]


def _link_or_copy(src: Path, dst: Path) -> None:
    try:
        os.link(src, dst)
    except OSError:
        shutil.copy2(src, dst)
