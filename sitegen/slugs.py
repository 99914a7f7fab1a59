"""Readable, safe slugs for Chinese and English titles.

CJK characters are kept (browsers show them readably in the address bar, and GitHub Pages
serves UTF-8 file names); ASCII is lower-cased; every run of anything else becomes ``-``.
The result never contains ``/``, ``..``, control or reserved characters, so it is safe as a
file name on every platform and, once percent-encoded, in a URL.
"""

from __future__ import annotations

import re
import unicodedata

_KEEP = re.compile(r"[^\w]+", re.UNICODE)
_RUNS = re.compile(r"-{2,}")
_WINDOWS_RESERVED = (
    {"con", "prn", "aux", "nul"} | {f"com{i}" for i in range(10)} | {f"lpt{i}" for i in range(10)}
)


def slugify(text: str, fallback: str = "page") -> str:
    """Turn a title into a slug: ``'W1 利用SSH維護倉儲'`` -> ``'w1-利用ssh維護倉儲'``."""
    text = unicodedata.normalize("NFKC", text).lower()
    slug = _KEEP.sub("-", text).replace("_", "-")
    slug = _RUNS.sub("-", slug).strip("-")
    slug = slug[:80].strip("-")
    if not slug or slug in _WINDOWS_RESERVED:
        slug = fallback if not slug else f"{slug}-"
    return slug


def heading_id(text: str, separator: str = "-") -> str:
    """Heading anchors: like :func:`slugify` but never empty and never starting with a digit."""
    slug = slugify(text, fallback="section")
    if slug[0].isdigit():
        slug = "h-" + slug
    return slug


def unique(slug: str, taken: set[str]) -> str:
    """Return ``slug`` or ``slug-2``, ``slug-3``... whichever is not in ``taken``; record it."""
    candidate, n = slug, 1
    while candidate in taken:
        n += 1
        candidate = f"{slug}-{n}"
    taken.add(candidate)
    return candidate
