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
from collections.abc import Iterable

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


def write_search_script(path, records: Iterable[str]) -> str:
    """``window.SITEGEN_SEARCH = [...]`` written to ``path`` one record (from
    :func:`record_json`, in site order) at a time, so the whole site's text is never in
    memory at once. Returns the file's SHA-256."""
    digest = hashlib.sha256()
    with open(path, "wb") as fh:

        def put(text: str) -> None:
            data = text.encode()
            digest.update(data)
            fh.write(data)

        put("window.SITEGEN_SEARCH=[")
        for number, record in enumerate(records):
            put(("," if number else "") + record)
        put("];\n")
    return digest.hexdigest()
