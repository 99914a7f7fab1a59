"""Files -> source records: find pages and assets under ``content/``, read front matter.

This is the I/O edge of the pipeline: everything after it works on the plain records made
here. Each record carries the SHA-256 of its bytes, which is what the cache keys on (a fresh
checkout has new mtimes but the same hashes, so it still hits the cache).
"""

from __future__ import annotations

import hashlib
import os
import re
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any

import yaml

from sitegen.errors import Diagnostics

PAGE_SUFFIXES = (".md", ".markdown")
_SKIP_DIRS = {".git", ".hg", ".svn", "__pycache__", "node_modules", ".sitegen-cache"}
_PREFIX = re.compile(r"^(\d+)[-_ .]+(?=\S)")
_FRONT_KEYS = {
    "title": str,
    "weight": int,
    "order": int,
    "slug": str,
    "draft": bool,
    "description": str,
}


@dataclass
class SourcePage:
    """A Markdown page as written by the author."""

    rel: PurePosixPath  # path relative to the content root, e.g. stage-1/w1/index.md
    text: str  # Markdown body, front matter removed
    body_line: int  # 1-based line in the file where ``text`` starts
    meta: dict[str, Any]
    digest: str
    is_index: bool
    prefix: int | None  # numeric ordering prefix from the file name
    stem: str  # file name without prefix and suffix

    @property
    def display(self) -> str:
        return str(self.rel)


@dataclass
class SourceAsset:
    """Any other file: copied to the same relative path in the site."""

    rel: PurePosixPath
    path: Path
    digest: str


@dataclass
class SourceTree:
    pages: list[SourcePage] = field(default_factory=list)
    assets: list[SourceAsset] = field(default_factory=list)
    dirs: list[PurePosixPath] = field(default_factory=list)


def split_name(name: str) -> tuple[int | None, str]:
    """``'03-foo bar'`` -> ``(3, 'foo bar')``; names without a prefix -> ``(None, name)``."""
    m = _PREFIX.match(name)
    if m:
        return int(m.group(1)), name[m.end() :]
    return None, name


def parse_front_matter(raw: str, file: str, diags: Diagnostics) -> tuple[dict[str, Any], str, int]:
    """Split YAML front matter from a page; validate its keys and types."""
    if not raw.startswith("---"):
        return {}, raw, 1
    lines = raw.split("\n")
    if lines[0].strip() != "---":
        return {}, raw, 1
    for end in range(1, len(lines)):
        if lines[end].strip() in ("---", "..."):
            break
    else:
        diags.error(file, 1, "front matter", "opening '---' has no closing '---'")
        return {}, raw, 1
    block = "\n".join(lines[1:end])
    body = "\n".join(lines[end + 1 :])
    try:
        node = yaml.compose(block)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        line = mark.line + 2 if mark else 1
        diags.error(file, line, "front matter", f"not valid YAML: {getattr(exc, 'problem', exc)}")
        return {}, body, end + 2
    meta: dict[str, Any] = {}
    if node is None:
        return meta, body, end + 2
    if not isinstance(node, yaml.MappingNode):
        diags.error(file, 2, "front matter", "must be a mapping of keys to values")
        return meta, body, end + 2
    for knode, vnode in node.value:
        key, line = str(knode.value), knode.start_mark.line + 2
        value = yaml.safe_load(yaml.serialize(vnode))
        want = _FRONT_KEYS.get(key)
        if want is None:
            diags.error(
                file,
                line,
                key,
                f"unknown front matter key (allowed: {', '.join(sorted(_FRONT_KEYS))})",
            )
        elif want is int and (isinstance(value, bool) or not isinstance(value, int)):
            diags.error(file, line, key, f"must be a whole number, got {value!r}")
        elif value is None:
            diags.error(file, line, key, "has no value")
        elif want is str and not isinstance(value, (str, int, float)):
            diags.error(file, line, key, f"must be text, got {value!r}")
        elif want is bool and not isinstance(value, bool):
            diags.error(file, line, key, f"must be true or false, got {value!r}")
        else:
            meta[key] = str(value) if want is str else value
    if "order" in meta and "weight" not in meta:
        meta["weight"] = meta.pop("order")
    return meta, body, end + 2


def read_page(path: Path, rel: PurePosixPath, data: bytes, diags: Diagnostics) -> SourcePage | None:
    try:
        raw = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data[: exc.start].count(b"\n") + 1
        diags.error(str(rel), line, "encoding", "not valid UTF-8")
        return None
    raw = raw.replace("\r\n", "\n").replace("\r", "\n")
    meta, body, body_line = parse_front_matter(raw, str(rel), diags)
    name = rel.name.rsplit(".", 1)[0]
    prefix, stem = split_name(name)
    return SourcePage(
        rel=rel,
        text=body,
        body_line=body_line,
        meta=meta,
        digest=hashlib.sha256(data).hexdigest(),
        is_index=stem.lower() in ("index", "readme", "_index"),
        prefix=prefix,
        stem=stem,
    )


def scan(content_root: Path, diags: Diagnostics, exclude: set[Path] | None = None) -> SourceTree:
    """Walk ``content_root`` in a fixed order and read every page and asset."""
    tree = SourceTree()
    exclude = {p.resolve() for p in (exclude or set())}
    for dirpath, dirnames, filenames in os.walk(content_root):
        here = Path(dirpath)
        dirnames[:] = sorted(
            d
            for d in dirnames
            if d not in _SKIP_DIRS and not d.startswith(".") and (here / d).resolve() not in exclude
        )
        rel_dir = os.path.relpath(dirpath, content_root).replace(os.sep, "/")
        if rel_dir != ".":
            tree.dirs.append(PurePosixPath(rel_dir))
        for name in sorted(filenames):
            if name.startswith(".") or name.endswith("~"):
                continue
            path = here / name
            rel = PurePosixPath(name if rel_dir == "." else f"{rel_dir}/{name}")
            try:
                data = path.read_bytes()
            except OSError as exc:
                diags.error(str(rel), None, "", f"cannot read: {exc.strerror}")
                continue
            if name.lower().endswith(PAGE_SUFFIXES):
                page = read_page(path, rel, data, diags)
                if page is not None and not page.meta.get("draft"):
                    tree.pages.append(page)
            else:
                tree.assets.append(SourceAsset(rel, path, hashlib.sha256(data).hexdigest()))
    return tree
