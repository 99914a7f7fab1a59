"""The client-side search data: one record per page, shipped as a script.

The index is a ``.js`` file that assigns a global rather than a ``.json`` fetched at run
time, because browsers refuse ``fetch`` from ``file://`` pages and the site must work opened
from disk. The browser builds its inverted index from this data on first use
(``assets/search.js``): Latin words by prefix, and CJK text by overlapping character
bigrams, so a two-character query such as 齒輪 matches inside running Chinese text that has
no spaces between words.
"""

from __future__ import annotations

import hashlib
import json
import mmap
from collections.abc import Callable, Iterable, Sequence

#: Text kept per page; long pages are cut so the index stays small on large sites.
MAX_TEXT = 6000


def _dumps(value) -> str:
    return json.dumps(value, ensure_ascii=False, separators=(",", ":"))


def record_parts(text: str, toc: list[dict]) -> tuple[str, str]:
    """The JSON of a page's text (cut at :data:`MAX_TEXT`) and headings: the bulk of its
    record, which depends on its Markdown alone. Made once, by the process that converts the
    page, and kept in the fragment store beside it, so writing the index reads these small
    strings instead of every page's HTML."""
    # headings (h2/h3) in text order: the browser shows which one a match falls under
    headings = [[h["id"], h["title"]] for h in _flat(toc or [])]
    return _dumps(text[:MAX_TEXT]), _dumps(headings)


def record_json(title: str, url: str, path: list[str], parts: tuple[str, str]) -> str:
    """One page's record, ``{"h","p","t","u","x"}`` in that (sorted) order, compact UTF-8
    JSON; ``parts`` from :func:`record_parts`."""
    text, headings = parts
    return (
        f'{{"h":{headings},"p":{_dumps(" › ".join(path))},"t":{_dumps(title)},'
        f'"u":{_dumps(url)},"x":{text}}}'
    )


def _flat(toc: list[dict]) -> list[dict]:
    return [x for h in toc for x in (h, *_flat(h.get("children") or []))]


def record_key(salt: str, title: str, url: str, path: list[str], source: str) -> str:
    """What a page's record is made of: its title, URL, path of section titles and source
    key (the Markdown it was converted from); ``salt`` stands for the code that makes it."""
    text = f"{salt}\0{title}\0{url}\0{' › '.join(path)}\0{source}"
    return hashlib.sha256(text.encode()).hexdigest()


#: The last index written: its SHA-256 and, per URL, (record key, start, end) of its record.
IndexRows = tuple[str, dict[str, tuple[str, int, int]]]


def write_search_script(
    path,
    keys: Sequence[tuple[str, str]],
    records: Callable[[list[int]], Iterable[str]],
    previous: tuple[bytes | mmap.mmap, IndexRows] | None = None,
) -> IndexRows:
    """``window.SITEGEN_SEARCH = [...]`` written to ``path`` one record at a time, so the
    whole site's text is never in memory at once.

    ``keys``: (URL, :func:`record_key`, or "" for a record that is always made) in site
    order; ``records(positions)`` yields the records (:func:`record_json`) at those
    positions of ``keys``, in order. ``previous``: the bytes of the index the last build
    wrote and its rows; a record whose key is unchanged is copied from it, so a one-page
    edit makes one record, not one per page. Returns the new file's digest and rows."""
    old, old_rows = previous if previous is not None else (b"", {})
    fresh = [
        i for i, (url, key) in enumerate(keys) if not key or old_rows.get(url, ("",))[0] != key
    ]
    made = iter(records(fresh))
    fresh_at = set(fresh)
    digest = hashlib.sha256()
    rows: dict[str, tuple[str, int, int]] = {}
    at = 0
    with open(path, "wb", buffering=1 << 20) as fh:  # a few writes, not one per 8 KB

        def put(data: bytes) -> None:
            nonlocal at
            digest.update(data)
            fh.write(data)
            at += len(data)

        put(b"window.SITEGEN_SEARCH=[")
        for number, (url, key) in enumerate(keys):
            if number:
                put(b",")
            if number in fresh_at:
                data = next(made).encode()
            else:
                _key, start, end = old_rows[url]
                data = old[start:end]
            start = at
            put(data)
            if key:
                rows[url] = (key, start, at)
        put(b"];\n")
    return digest.hexdigest(), rows
