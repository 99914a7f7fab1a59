"""The build cache: what the last build made, keyed by content hashes.

``state.json`` (input fingerprint, output manifest, and each source's stat key) is what a
no-op rebuild reads and stops at; ``sources.pickle`` with ``sources-*.texts`` (each source
file's parsed record by its stat key; the texts apart, sitegen.source_records),
``fragments.pickle`` (per source hash: ids, table of contents; per page: the input and
context keys; the search index's rows) and ``fragments.sqlite`` (sitegen.fragment_store) are
what a partial rebuild needs. A stat key only stands for a hash already taken
(sitegen.source_stats). A cache that cannot be read (other version, truncated file) is simply
ignored: the build is then a cold one.
"""

from __future__ import annotations

import contextlib
import json
import os
import pickle
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from sitegen import __version__

FORMAT = f"sitegen-cache-9-{__version__}"


@dataclass
class State:
    """What a no-op check reads: fingerprint, output manifest, stat keys (state.json)."""

    fingerprint: str = ""
    output: str = ""
    manifest: dict[str, list] = field(default_factory=dict)
    rosters: dict[str, Any] = field(default_factory=dict)
    #: the no-op check without reading the sources: each source file's stat key when the
    #: fingerprint was taken (empty: not trusted, read them), and the digest of everything
    #: else in the fingerprint (config, theme, code, integrations)
    sources: dict[str, list[int]] = field(default_factory=dict)
    rest: str = ""


@dataclass
class Fragments:
    """What a partial build reuses of the last one (fragments.pickle)."""

    #: source key -> (ids, pickled toc, directives, highlighted blocks); the HTML is in
    #: fragments.sqlite (fragment_store)
    markdown: dict[str, Any] = field(default_factory=dict)
    #: url -> (input key, context hash, output digest, diagnostics, own key): see
    #: sitegen/page_jobs.py
    pages: dict[str, tuple] = field(default_factory=dict)
    #: page_jobs.PagePhase.tree_digest of the last build (its input keys' shared part)
    tree: str = ""
    #: the search index written: digest and rows (sitegen.search.write_search_script)
    search: tuple = ()
    #: name -> (inputs hash, {output path: digest}) for the site-wide files (build.SiteWide)
    site_wide: dict[str, tuple] = field(default_factory=dict)


class Cache:
    def __init__(self, directory: Path):
        self.dir = directory

    def load_state(self) -> State:
        try:
            raw = json.loads((self.dir / "state.json").read_text(encoding="utf-8"))
            if raw.get("format") != FORMAT:
                return State()
            return State(
                raw["fingerprint"],
                raw["output"],
                raw["manifest"],
                raw.get("rosters", {}),
                raw.get("sources", {}),
                raw.get("rest", ""),
            )
        except (OSError, ValueError, KeyError, TypeError):
            return State()

    def save_state(self, state: State) -> None:
        data = {
            "format": FORMAT,
            "fingerprint": state.fingerprint,
            "output": state.output,
            "manifest": state.manifest,
            "rosters": state.rosters,
            "sources": state.sources,
            "rest": state.rest,
        }
        self._write(
            self.dir / "state.json", json.dumps(data, ensure_ascii=False, sort_keys=True).encode()
        )

    def load_fragments(self) -> Fragments:
        try:
            with open(self.dir / "fragments.pickle", "rb") as fh:
                fmt, frag = pickle.load(fh)
            return frag if fmt == FORMAT and isinstance(frag, Fragments) else Fragments()
        except (OSError, pickle.UnpicklingError, EOFError, ValueError, TypeError, AttributeError):
            return Fragments()

    def save_fragments(self, frag: Fragments) -> None:
        self._dump(self.dir / "fragments.pickle", frag)

    def load_sources(self, root: Path) -> dict[str, tuple[list[int], Any]]:
        """The last scan of ``root``: its records (sitegen.content.SourceTree.records), each
        page's text read on demand (sitegen.source_records), or nothing (another folder: a
        moved file keeps its stat key but not its path)."""
        from sitegen.source_records import TextBlob, unpack

        try:
            with open(self.dir / "sources.pickle", "rb") as fh:
                fmt, saved = pickle.load(fh)
            if fmt != FORMAT or not isinstance(saved, tuple) or saved[0] != str(root):
                return {}
            _root, rows, name, size = saved
            data = (self.dir / name).read_bytes()
            if len(data) < size:  # cut short: the texts the rows point at are not all there
                return {}
            return unpack(rows, TextBlob(data, name))
        except (
            OSError,
            pickle.UnpicklingError,
            EOFError,
            ValueError,
            TypeError,
            AttributeError,
            LookupError,
        ):
            return {}

    def save_sources(self, root: Path, records: dict[str, tuple[list[int], Any]]) -> None:
        """The records as rows (``sources.pickle``) and their texts in ``sources-*.texts``:
        the texts of pages read anew are appended to the last file, which is written afresh
        (under a new name, so the rows always name a complete file) once it is mostly texts
        no page uses."""
        from sitegen.source_records import compact, pack, shared_blob

        self.dir.mkdir(parents=True, exist_ok=True)
        base = shared_blob(records)
        tail = self._size(base.name) if base is not None else -1
        if base is None or tail < len(base.data):  # gone, or not the file the texts came from
            base, tail = None, 0
        rows, extra, live = pack(records, base, tail)
        if base is not None and tail + len(extra) <= 2 * live + (64 << 10):
            name = base.name
            with open(self.dir / name, "ab") as fh:
                fh.write(extra)
            size = tail + len(extra)
        else:
            rows, data = compact(rows, base.data if base is not None else b"", tail, extra)
            name = f"sources-{time.time_ns()}.texts"
            self._write(self.dir / name, data)
            size = len(data)
        self._dump(self.dir / "sources.pickle", (str(root), rows, name, size))
        for old in self.dir.glob("sources-*.texts"):
            if old.name != name:
                with contextlib.suppress(OSError):
                    old.unlink()

    def _size(self, name: str) -> int:
        try:
            return (self.dir / name).stat().st_size
        except OSError:
            return -1

    def _dump(self, path: Path, value: Any) -> None:
        """Pickled straight to the file: never a second copy of what it holds in memory."""
        self.dir.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        with open(tmp, "wb", buffering=1 << 20) as fh:
            pickle.dump((FORMAT, value), fh, protocol=pickle.HIGHEST_PROTOCOL)
        os.replace(tmp, path)

    def _write(self, path: Path, data: bytes) -> None:
        self.dir.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
