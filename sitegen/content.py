"""Files -> source records: find pages and assets under ``content/``, read front matter.

This is the I/O edge of the pipeline: everything after it works on the plain records made
here. Each record carries the SHA-256 of its bytes, which is what the cache keys on (a fresh
checkout has new mtimes but the same hashes, so it still hits the cache).
"""

from __future__ import annotations

import hashlib
import os
import re
import time
from dataclasses import dataclass, field
from pathlib import Path, PurePosixPath
from typing import Any

from sitegen.errors import Diagnostics
from sitegen.page_text import DeferredText, first_heading, text_key
from sitegen.source_stats import MAX_DEPTH as MAX_DEPTH  # the folder depth scan reads to
from sitegen.source_stats import Walk, stat_key

PAGE_SUFFIXES = (".md", ".markdown")
MAX_PAGE_BYTES = 8 << 20  # a Markdown page; course pages are tens of kilobytes
MAX_ASSET_BYTES = 100 << 20  # any other file: GitHub refuses to store larger files
_PREFIX = re.compile(r"^(\d+)[-_ .]+(?=\S)")
_FRONT_KEYS = {
    "title": str,
    "weight": int,
    "order": int,
    "slug": str,
    "draft": bool,
    "description": str,
    # slide decks and blog posts (sitegen/slides.py, sitegen/blog.py)
    "slides": bool,
    "date": "date",
    "tags": "tags",
    "summary": str,
    "aliases": "tags",  # old URLs of the page, a list like tags (sitegen/redirects.py)
}


@dataclass
class SourcePage(DeferredText):
    """A Markdown page as written by the author. A record taken from the build cache reads
    its ``text`` only when something uses it (sitegen.source_records)."""

    rel: PurePosixPath  # path relative to the content root, e.g. stage-1/w1/index.md
    text: str  # Markdown body, front matter removed
    body_line: int  # 1-based line in the file where ``text`` starts
    meta: dict[str, Any]
    digest: str
    is_index: bool
    prefix: int | None  # numeric ordering prefix from the file name
    stem: str  # file name without prefix and suffix
    #: made from ``text`` when the file is read: its key (page_text.text_key) and first
    #: heading (page_text.first_heading), which the build needs of every page, text or not
    text_key: str = field(default="", init=False, repr=False, compare=False)
    heading: tuple | None = field(default=None, init=False, repr=False, compare=False)


@dataclass
class SourceAsset:
    """Any other file: copied to the same relative path in the site."""

    rel: PurePosixPath
    path: Path
    digest: str


@dataclass
class SourceTree:
    """Everything the scan found under the content folder, in walk order."""

    pages: list[SourcePage] = field(default_factory=list)
    assets: list[SourceAsset] = field(default_factory=list)
    #: path -> stat key of every file read (:func:`stat_key`), for the next build's no-op check
    stats: dict[str, list[int]] = field(default_factory=dict)
    #: path -> (stat key, SourcePage, SourceAsset or None for a draft) of each file read
    #: without a problem, for the next scan (``known``)
    records: dict[str, tuple[list[int], Any]] = field(default_factory=dict)
    #: False when a file was written within :data:`RACY_NS` of the scan: its stat key might
    #: not change with its next edit, so the next build must read the files again
    stats_trusted: bool = True


#: A file modified less than this before the scan may be modified again within the file
#: system's timestamp granularity without its stat changing ("racily clean", as git says).
RACY_NS = 2_000_000_000


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
    # imported here, not at the top: YAML costs ~25 ms to import, and a build that reads
    # no front matter (a page edit, most pages) needs none of it
    import yaml

    from located import yaml as located_yaml

    try:
        node = located_yaml.compose(block, file, first_line=2)
    except located_yaml.YamlError as exc:
        diags.error(file, exc.line or 1, "front matter", exc.message)
        return {}, body, end + 2
    meta: dict[str, Any] = {}
    if node is None:
        return meta, body, end + 2
    from located.yamlwalk import Walker

    if not isinstance(node, yaml.MappingNode):
        diags.error(file, 2, "front matter", "must be a mapping of keys to values")
        return meta, body, end + 2
    walk = Walker(file, first_line=2)
    for key, _knode, vnode in walk.mapping(node, "front matter", allowed=_FRONT_KEYS):
        value = _front_value(walk, key, vnode)
        if value is not None:
            meta[key] = value
    diags.extend(_named_by_key(walk.problems))
    if "order" in meta and "weight" not in meta:
        meta["weight"] = meta.pop("order")
    return meta, body, end + 2


_BAD_DATE = "not a date: {} (write YYYY-MM-DD or YYYY-MM-DD HH:MM)"


def _front_value(walk: Any, key: str, vnode: Any) -> Any:
    """One front matter value checked against :data:`_FRONT_KEYS` (None, with a problem
    recorded at its line, when it is not what the key takes)."""
    import yaml

    from located.yaml import short_repr, to_python

    try:
        value = to_python(vnode)
    except ValueError as exc:  # a timestamp that is no date (2021-02-30): YAML raises
        if not isinstance(vnode, yaml.ScalarNode):
            walk.fail(vnode, key, f"cannot be read: {exc}")
            return None
        value = str(vnode.value)  # the text as written: a title, or a date reported below
    want = _FRONT_KEYS[key]
    problem = None
    if value is None:
        problem = "has no value"
    elif want is int and (isinstance(value, bool) or not isinstance(value, int)):
        problem = f"must be a whole number, got {short_repr(value)}"
    elif want in ("date", "tags"):
        checked = _post_value(want, value)
        if checked is None or (want == "tags" and isinstance(checked, str)):
            problem = checked or _BAD_DATE.format(short_repr(value))
        else:
            return checked
    elif want is str and not isinstance(value, (str, int, float)):
        problem = f"must be text, got {short_repr(value)}"
    elif want is bool and not isinstance(value, bool):
        problem = f"must be true or false, got {short_repr(value)}"
    if problem is not None:
        walk.fail(vnode, key, problem)
        return None
    return str(value) if want is str else value


def _named_by_key(problems: list) -> list:
    """Front matter problems name the key (``title``), not its path (``front matter.title``);
    an unknown key's message lists the keys a page takes."""
    import dataclasses

    out = []
    for d in problems:
        field = d.field.removeprefix("front matter.")
        message = d.message
        if message.startswith("unknown key"):
            message = f"unknown front matter key (allowed: {', '.join(sorted(_FRONT_KEYS))})"
        out.append(dataclasses.replace(d, field=field, message=message))
    return out


def _post_value(want: str, value: Any) -> Any:
    """A post's ``date`` in its normal form (None if it does not parse), or its ``tags`` as a
    tuple of names (an error message as a str when they are not a list or comma list)."""
    if want == "date":
        from sitegen.post_dates import parse_post_date

        return parse_post_date(value)
    items = value.split(",") if isinstance(value, str) else value
    if not isinstance(items, list) or not all(isinstance(t, (str, int, float)) for t in items):
        from located.yaml import short_repr

        got = short_repr(value)
        return f"must be a list of names or a comma-separated text, got {got}"
    return tuple(dict.fromkeys(str(t).strip() for t in items if str(t).strip()))


def read_page(
    path: Path, rel: PurePosixPath, data: bytes, diags: Diagnostics, digest: str | None = None
) -> SourcePage | None:
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
    page = SourcePage(
        rel=rel,
        text=body,
        body_line=body_line,
        meta=meta,
        digest=digest or hashlib.sha256(data).hexdigest(),
        is_index=stem.lower() in ("index", "readme", "_index"),
        prefix=prefix,
        stem=stem,
    )
    page.text_key = text_key(body)
    page.heading = first_heading(body)
    return page


def scan(
    content_root: Path,
    diags: Diagnostics,
    exclude: set[Path] | None = None,
    known: dict[str, tuple[list[int], Any]] | None = None,
    walked: dict[str, list[int]] | None = None,
) -> SourceTree:
    """Walk ``content_root`` in a fixed order and read every page and asset.

    ``known``: the last scan's :attr:`SourceTree.records`; a plain file whose stat key is the
    one recorded there (and not racily new) is taken from it instead of read again.
    ``walked``: every file's stat key as :func:`sitegen.source_stats.stat_walk` found it just
    before; when it names exactly the files of ``known``, nothing came or went, and the walk
    is not made again (:func:`_rescan`).

    The walk (:class:`sitegen.source_stats.Walk`, shared with ``stat_walk`` and ``sitegen
    serve``) keeps its own stack (no recursion, so no depth can overflow Python's), stops at
    :data:`MAX_DEPTH` folders, and scan reports instead of reading: a symlink whose target lies
    outside the content folder (never followed: it would publish that file), a symlink loop,
    anything that is not a regular file or folder, and files above the size limits."""
    tree = SourceTree()
    recent = time.time_ns() - RACY_NS
    if known and walked is not None and walked.keys() == known.keys():
        return _rescan(content_root, diags, known, walked, recent)
    boundary = content_root.resolve()

    def unreadable(rel_dir: PurePosixPath, exc: OSError) -> None:
        diags.error(_display(rel_dir), None, "", f"cannot read folder: {exc.strerror}")

    walk = Walk(content_root, exclude or set(), on_error=unreadable)
    for found in walk:
        entry, path, rel = found.entry, found.path, found.rel
        try:
            plain = not entry.is_symlink()  # the common case: its type without a stat
        except OSError:
            plain = False  # reported by _inside_target
        if plain and entry.is_file(follow_symlinks=False):
            if not (known and _reuse(entry, str(rel), known, tree, recent)):
                _read_file(path, rel, tree, diags, recent)
            continue
        real = _inside_target(entry, path, rel, boundary, found.real_dir, diags)
        if real is None:
            continue
        if real.is_dir():
            problem = walk.descend(found, real)
            if problem is not None:
                diags.error(str(rel), None, "", problem)
        elif real.is_file():
            _read_file(path, rel, tree, diags, recent)
        else:
            diags.error(str(rel), None, "", "not a regular file or folder; not published")
    return tree


def _rescan(
    content_root: Path, diags: Diagnostics, known: dict, walked: dict, recent: int
) -> SourceTree:
    """The same files as the last scan, every one a plain file read cleanly then (stat_walk
    leaves symlinks and special files to the full walk): take them in the last scan's order
    (its records are in walk order), reading only those whose stat key changed."""
    tree = SourceTree()
    for rel, (old_key, record) in known.items():
        key = walked[rel]
        if key == old_key and max(key[1], key[2]) < recent:
            _record(tree, rel, key, record, True)
        else:
            _read_file(content_root / rel, PurePosixPath(rel), tree, diags, recent)
    return tree


def _reuse(entry: os.DirEntry, rel: str, known: dict, tree: SourceTree, recent: int) -> bool:
    """Take ``rel``'s record from the last scan if its stat key is unchanged."""
    old = known.get(rel)
    if old is None:
        return False
    try:
        st = entry.stat(follow_symlinks=False)
    except OSError:
        return False
    key = stat_key(st)
    if key != old[0] or max(st.st_mtime_ns, st.st_ctime_ns) >= recent:
        return False
    _record(tree, rel, key, old[1], True)
    return True


def _record(tree: SourceTree, rel: str, key: list[int], record: Any, keep: bool) -> None:
    """A file read cleanly: a page, an asset, or None (a draft page); ``keep``: its stat key
    may be trusted by the next scan (it was not written just before this one)."""
    tree.stats[rel] = key
    if keep:
        tree.records[rel] = (key, record)
    if isinstance(record, SourcePage):
        tree.pages.append(record)
    elif record is not None:
        tree.assets.append(record)


def _display(rel: PurePosixPath) -> str:
    return str(rel) if rel.parts else "."


def _inside_target(
    entry: os.DirEntry, path: Path, rel: PurePosixPath, boundary: Path, real_dir: Path, diags
) -> Path | None:
    """The real path behind ``entry``, or None (with an error) if it must not be followed."""
    try:
        is_link = entry.is_symlink()
    except OSError as exc:
        diags.error(str(rel), None, "", f"cannot read: {exc.strerror}")
        return None
    if not is_link:
        return real_dir / entry.name
    target = Path(os.path.realpath(path))
    if not target.is_relative_to(boundary):
        diags.error(
            str(rel),
            None,
            "symlink",
            f"points outside the content folder (to {target}); it is not followed. "
            "Copy the file into the content folder instead",
        )
        return None
    if not target.exists():
        diags.error(str(rel), None, "symlink", "points to nothing (a broken link)")
        return None
    if target.is_dir() and real_dir.is_relative_to(target):
        diags.error(str(rel), None, "symlink", "points to a folder that contains it (a loop)")
        return None
    return target


def _read_file(
    path: Path, rel: PurePosixPath, tree: SourceTree, diags: Diagnostics, recent: int
) -> None:
    """Read a page (bounded) or hash an asset (in blocks), enforcing the size limits."""
    is_page = rel.name.lower().endswith(PAGE_SUFFIXES)
    limit = MAX_PAGE_BYTES if is_page else MAX_ASSET_BYTES
    kind = "a Markdown page" if is_page else "a file"
    h = hashlib.sha256()
    data = b""
    try:
        with open(path, "rb") as fh:
            st = os.fstat(fh.fileno())
            if is_page:  # one read of the size the file has (a page is small)
                data = fh.read(min(st.st_size, limit) + 1)
                if len(data) > st.st_size:  # it grew while being read
                    data += fh.read(limit + 1 - len(data))
                size = len(data)
                h.update(data)
            else:
                size = 0
                for block in iter(lambda: fh.read(1 << 20), b""):
                    size += len(block)
                    if size > limit:
                        break
                    h.update(block)
            if size > limit:
                diags.error(
                    str(rel),
                    None,
                    "",
                    f"{kind} larger than the limit of {limit // (1 << 20)} MiB; not published",
                )
                return
    except OSError as exc:
        diags.error(str(rel), None, "", f"cannot read: {exc.strerror}")
        return
    key = stat_key(st)
    keep = max(st.st_mtime_ns, st.st_ctime_ns) < recent
    tree.stats_trusted &= keep
    record: SourcePage | SourceAsset | None = SourceAsset(rel, path, h.hexdigest())
    if is_page:
        reported = len(diags.items)
        record = read_page(path, rel, data, diags, h.hexdigest())
        if len(diags.items) > reported or record is None:  # read again: its problems too
            tree.stats[str(rel)] = key
            if record is not None and not record.meta.get("draft"):
                tree.pages.append(record)
            return
        if record.meta.get("draft"):
            record = None
    _record(tree, str(rel), key, record, keep)
