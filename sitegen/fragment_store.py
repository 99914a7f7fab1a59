"""Rendered Markdown kept on disk, one page at a time, so memory does not grow with the site.

A build used to hold every page's HTML and text in memory from conversion to publishing
(~90 MB at 5000 pages). Here each converted page goes into an SQLite table in the cache
folder as soon as it is made (by whichever worker process made it) and is read back only
when its page is rendered or the search index is written; the build keeps just the ids,
table of contents and directives of each page (what links and the tree need).

SQLite because it is in the standard library, takes concurrent writers from the worker
processes (WAL mode, a busy timeout), and keeps the cache one file instead of thousands (file
creation is the slow part of a build on many disks). A store that cannot be opened or read is
replaced by an empty one: the pages it held are converted again.
"""

from __future__ import annotations

import os
import pickle
import sqlite3
import time
from collections.abc import Iterable, Iterator, Mapping
from pathlib import Path
from typing import Any

from sitegen.search import record_parts

_SCHEMA = (
    "CREATE TABLE IF NOT EXISTS fragment (key TEXT PRIMARY KEY, data BLOB NOT NULL)",
    # the page's search record parts (sitegen.search.record_parts): the index is written
    # from these small strings, not from every page's pickled HTML
    "CREATE TABLE IF NOT EXISTS search (key TEXT PRIMARY KEY, text TEXT, headings TEXT)",
    # highlighted code blocks by content (sitegen.highlight_cache)
    "CREATE TABLE IF NOT EXISTS highlight (key TEXT PRIMARY KEY, html TEXT NOT NULL)",
)


class FragmentStore:
    """``key -> Rendered`` in ``<cache>/fragments.sqlite``; safe to use after ``fork``."""

    def __init__(self, path: Path):
        self.path = path
        self._db: sqlite3.Connection | None = None
        self._pid = 0

    def _conn(self) -> sqlite3.Connection:
        if self._db is None or self._pid != os.getpid():  # a forked worker opens its own
            self._db = self._open()
            self._pid = os.getpid()
        return self._db

    def _open(self) -> sqlite3.Connection:
        self.path.parent.mkdir(parents=True, exist_ok=True)
        removed = False
        for _wait in range(500):
            try:
                db = sqlite3.connect(str(self.path), timeout=120, isolation_level=None)
                db.execute("PRAGMA journal_mode=WAL")
                db.execute("PRAGMA synchronous=OFF")  # a cache: losing it only costs time
                for table in _SCHEMA:
                    db.execute(table)
                return db
            except sqlite3.DatabaseError as exc:
                # two workers making a new store at once: one finds it locked (switching to
                # WAL does not wait on the busy timeout). Not damage: removing the file would
                # pull it from under the other worker ("no such table", "malformed").
                if "locked" in str(exc):
                    time.sleep(0.01)
                    continue
                if removed:
                    raise
                removed = True
                for suffix in ("", "-wal", "-shm"):
                    Path(f"{self.path}{suffix}").unlink(missing_ok=True)
        raise sqlite3.OperationalError(f"{self.path}: still locked after 5 s")

    def keys(self) -> set[str]:
        try:
            return {row[0] for row in self._conn().execute("SELECT key FROM fragment")}
        except sqlite3.DatabaseError:
            self.clear()
            return set()

    def get(self, key: str) -> Any:
        row = self._conn().execute("SELECT data FROM fragment WHERE key = ?", (key,)).fetchone()
        if row is None:
            raise KeyError(key)
        return pickle.loads(row[0])

    def highlighted(self, key: str) -> str | None:
        """A highlighted code block's HTML, or None (sitegen.highlight_cache's lookup)."""
        try:
            row = self._conn().execute("SELECT html FROM highlight WHERE key = ?", (key,))
            found = row.fetchone()
        except sqlite3.DatabaseError:
            return None
        return None if found is None else found[0]

    def put_many(
        self, items: Iterable[tuple[str, Any]], blocks: Mapping[str, str] | None = None
    ) -> None:
        """Store ``(key, Rendered)`` pairs, each with its search record parts, and the code
        blocks highlighted meanwhile (``blocks``: key -> HTML)."""
        rows, parts = [], []
        for key, rendered in items:
            rows.append((key, pickle.dumps(rendered, protocol=pickle.HIGHEST_PROTOCOL)))
            parts.append((key, *record_parts(rendered.text, rendered.toc)))
        db = self._conn()
        db.execute("BEGIN IMMEDIATE")
        try:
            db.executemany("INSERT OR REPLACE INTO fragment VALUES (?, ?)", rows)
            db.executemany("INSERT OR REPLACE INTO search VALUES (?, ?, ?)", parts)
            if blocks:
                db.executemany("INSERT OR REPLACE INTO highlight VALUES (?, ?)", blocks.items())
            db.execute("COMMIT")
        except BaseException:
            db.execute("ROLLBACK")
            raise

    def search_parts(self, keys: list[str]) -> dict[str, tuple[str, str]]:
        """``key -> (text JSON, headings JSON)`` for those of ``keys`` the store has (a few
        queries for the whole list, not one per page)."""
        found: dict[str, tuple[str, str]] = {}
        db = self._conn()
        for i in range(0, len(keys), 500):
            batch = keys[i : i + 500]
            marks = ",".join("?" * len(batch))
            query = f"SELECT key, text, headings FROM search WHERE key IN ({marks})"
            found.update((k, (t, h)) for k, t, h in db.execute(query, batch))
        return found

    def keep_only(self, keys: set[str], blocks: set[str] | None = None) -> None:
        """Forget every fragment no page uses any more, and (``blocks`` given) every
        highlighted code block none of them holds."""
        stale = self.keys() - keys
        db = self._conn()
        old_blocks: set[str] = set()
        if blocks is not None:
            old_blocks = {r[0] for r in db.execute("SELECT key FROM highlight")} - blocks
        if stale or old_blocks:
            db.execute("BEGIN IMMEDIATE")
            db.executemany("DELETE FROM fragment WHERE key = ?", [(k,) for k in stale])
            db.executemany("DELETE FROM search WHERE key = ?", [(k,) for k in stale])
            db.executemany("DELETE FROM highlight WHERE key = ?", [(k,) for k in old_blocks])
            db.execute("COMMIT")

    def clear(self) -> None:
        self.close()
        for suffix in ("", "-wal", "-shm"):
            Path(f"{self.path}{suffix}").unlink(missing_ok=True)

    def close(self) -> None:
        if self._db is not None and self._pid == os.getpid():
            self._db.close()
        self._db = None


class Renders(Mapping):
    """``url -> Rendered`` for every page: generated pages held in memory, Markdown pages
    read from the store when asked for (nothing is kept after use)."""

    def __init__(self, store: FragmentStore, keys: dict[str, str], held: dict[str, Any]):
        self.store = store
        self.keys_by_url = keys  # url -> source key, Markdown pages
        self.held = held  # url -> Rendered, generated pages and folders without index.md

    def __getitem__(self, url: str) -> Any:
        found = self.held.get(url)
        if found is not None:
            return found
        return self.store.get(self.keys_by_url[url])

    def __iter__(self) -> Iterator[str]:
        yield from self.held
        yield from (url for url in self.keys_by_url if url not in self.held)

    def __len__(self) -> int:
        return len(self.held) + sum(1 for url in self.keys_by_url if url not in self.held)
