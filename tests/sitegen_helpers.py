"""Shared helpers for the site-build tests: write a content tree, build it, read pages."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from sitegen.build import BuildOptions, BuildReport, build

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"


def write_tree(root: Path, files: dict[str, str | bytes]) -> Path:
    for rel, data in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        if isinstance(data, bytes):
            path.write_bytes(data)
        else:
            path.write_text(data, encoding="utf-8")
    return root


def run_build(source: Path, output: Path, **kw) -> BuildReport:
    return build(BuildOptions(source=source, output=output, log=lambda line: None, **kw))


def settled_build(tmp_path: Path, monkeypatch, files: dict[str, str | bytes]):
    """``files`` built once, with the racy-stat window off so that the files written a moment
    ago count as settled (the cache trusts their stat keys); returns (src, out, cache)."""
    import sitegen.content

    monkeypatch.setattr(sitegen.content, "RACY_NS", 0)
    src = write_tree(tmp_path / "src", files)
    out, cache = tmp_path / "site", tmp_path / "cache"
    run_build(src, out, cache_dir=cache)
    return src, out, cache


def run_cli(*args: str, cwd: Path | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "sitegen", *args],
        capture_output=True,
        text=True,
        cwd=cwd,
        timeout=600,
    )


def hrefs(html: str) -> list[str]:
    return re.findall(r'\s(?:href|src)="([^"]*)"', html)


def pager(html: str) -> tuple[str | None, str | None]:
    """(previous title, next title) from a page's first pager."""
    nav = re.search(r'<nav class="pager"[^>]*>(.*?)</nav>', html, re.S).group(1)
    prev = re.search(r'rel="prev"[^>]*>« [^:]+: (.*?)</a>', nav)
    nxt = re.search(r'rel="next"[^>]*>[^:]+: (.*?) »</a>', nav)
    return (prev.group(1) if prev else None, nxt.group(1) if nxt else None)


def snapshot(folder: Path) -> dict[str, bytes]:
    return {
        p.relative_to(folder).as_posix(): p.read_bytes()
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }


def mtimes(folder: Path) -> dict[str, int]:
    return {
        p.relative_to(folder).as_posix(): p.stat().st_mtime_ns
        for p in sorted(folder.rglob("*"))
        if p.is_file()
    }
