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
        {"t": p["title"], "u": p["url"], "p": " › ".join(p["path"]), "x": p["text"][:MAX_TEXT]}
        for p in pages
    ]


def search_script(records: list[dict]) -> bytes:
    """Serialise deterministically as ``window.SITEGEN_SEARCH = [...]``."""
    data = json.dumps(records, ensure_ascii=False, separators=(",", ":"), sort_keys=True)
    return f"window.SITEGEN_SEARCH={data};\n".encode()
