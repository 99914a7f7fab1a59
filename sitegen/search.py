"""The client-side search data: one record per page, shipped as a script.

The index is a ``.js`` file that assigns a global rather than a ``.json`` fetched at run
time, because browsers refuse ``fetch`` from ``file://`` pages and the site must work opened
from disk. The browser builds its inverted index from this data on first use
(``assets/search.js``): Latin words by prefix, and CJK text by overlapping character
bigrams, so a two-character query such as 齒輪 matches inside running Chinese text that has
no spaces between words.
"""

from __future__ import annotations

import json

#: Text kept per page; long pages are cut so the index stays small on large sites.
MAX_TEXT = 6000


def search_records(pages: list[dict]) -> list[dict]:
    """``pages``: dicts with title, url, path (breadcrumb titles) and text, in site order."""
    return [
        {
            "t": p["title"],
            "u": p["url"],
            "p": " › ".join(p["path"]),
            "x": p["text"][:MAX_TEXT],
            # headings (h2/h3) in text order: the browser shows which one a match falls under
            "h": [[h["id"], h["title"]] for h in _flat(p.get("toc") or [])],
        }
        for p in pages
    ]


def _flat(toc: list[dict]) -> list[dict]:
    return [x for h in toc for x in (h, *_flat(h.get("children") or []))]


def search_script(records: list[dict]) -> bytes:
    """Serialise deterministically as ``window.SITEGEN_SEARCH = [...]``."""
    data = json.dumps(records, ensure_ascii=False, separators=(",", ":"), sort_keys=True)
    return f"window.SITEGEN_SEARCH={data};\n".encode()


def write_search_script(path, pages) -> str:
    """:func:`search_script` written to ``path`` one page at a time (the same bytes), so the
    whole site's text is never in memory at once; ``pages`` may be a generator. Returns the
    file's SHA-256."""
    import hashlib

    digest = hashlib.sha256()
    with open(path, "wb") as fh:

        def put(text: str) -> None:
            data = text.encode()
            digest.update(data)
            fh.write(data)

        put("window.SITEGEN_SEARCH=[")
        for number, page in enumerate(pages):
            record = search_records([page])[0]
            text = json.dumps(record, ensure_ascii=False, separators=(",", ":"), sort_keys=True)
            put(("," if number else "") + text)
        put("];\n")
    return digest.hexdigest()
