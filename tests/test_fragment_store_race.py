"""Worker processes that make a new fragment store at the same moment all keep their pages.

Two workers opening a store that does not exist yet race to switch it to WAL mode; the loser
sees "database is locked" at once (that switch does not wait on the busy timeout). The store
used to take that for damage and delete the file, pulling it from under the other worker: a
cold build then failed now and then with "no such table: fragment" or "database disk image
is malformed" (seen under load once the Markdown stage got faster, so that the workers' first
writes came closer together).
"""

from __future__ import annotations

import multiprocessing
import sqlite3
import sys

import pytest

from sitegen.fragment_store import FragmentStore
from sitegen.markdown_render import Rendered


class _LockedOnce:
    """A connection whose first switch to WAL finds the file locked, as the loser of two
    workers making a new store does."""

    raised = False

    def __init__(self, db: sqlite3.Connection):
        self.db = db

    def execute(self, sql: str, *args):
        if sql.startswith("PRAGMA journal_mode") and not _LockedOnce.raised:
            _LockedOnce.raised = True
            raise sqlite3.OperationalError("database is locked")
        return self.db.execute(sql, *args)

    def __getattr__(self, name: str):
        return getattr(self.db, name)


def test_a_store_found_locked_is_waited_for_not_deleted(tmp_path, monkeypatch):
    path = tmp_path / "fragments.sqlite"
    other_worker = FragmentStore(path)
    other_worker.put_many([("page", Rendered("<p>kept</p>", [], [], "kept"))])
    connect = sqlite3.connect
    monkeypatch.setattr(_LockedOnce, "raised", False)
    monkeypatch.setattr(sqlite3, "connect", lambda *a, **k: _LockedOnce(connect(*a, **k)))
    assert FragmentStore(path).keys() == {"page"}  # the file was not removed
    assert _LockedOnce.raised


def _worker(path: str, barrier, number: int) -> None:
    from pathlib import Path

    store = FragmentStore(Path(path))
    barrier.wait()  # open the new store together
    store.put_many([(f"page-{number}", Rendered(f"<p>{number}</p>", [], [], str(number)))])


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="workers fork on Linux")
def test_workers_opening_a_new_store_together_keep_every_page(tmp_path):
    ctx = multiprocessing.get_context("fork")
    for trial in range(8):
        path = tmp_path / f"store-{trial}" / "fragments.sqlite"
        barrier = ctx.Barrier(3)
        workers = [ctx.Process(target=_worker, args=(str(path), barrier, n)) for n in range(3)]
        for w in workers:
            w.start()
        for w in workers:
            w.join(60)
        assert [w.exitcode for w in workers] == [0, 0, 0], trial
        assert FragmentStore(path).keys() == {"page-0", "page-1", "page-2"}, trial
