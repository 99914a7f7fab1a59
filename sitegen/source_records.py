"""The last scan's source records as the build cache keeps them, with texts read on demand.

A one-page edit of a 1000-page site takes 999 records from the last scan (sitegen.content's
``known``). What the build needs of an unchanged page is its path, front matter, digest, title
heading and a key of its text, not the text itself: only the pages it converts or renders
again read their text. So the cache keeps the records as plain tuples with every text as
UTF-8 in one blob, and a page taken from it decodes its text on first use
(sitegen.page_text.DeferredText). Loading and saving 1000 records then costs a few milliseconds
instead of decoding and re-encoding 4 MB of text each time.
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath
from typing import Any

from sitegen.content import SourceAsset, SourcePage
from sitegen.page_text import deferred


def pack(records: dict[str, tuple[list[int], Any]]) -> tuple[dict[str, tuple], bytes]:
    """``rel -> (stat key, SourcePage | SourceAsset | None)`` as plain rows and one blob of
    the pages' texts. A page still as :func:`unpack` made it keeps its row and its text's
    place in the loaded blob, and the texts read anew are added after it, so a one-page edit
    neither re-encodes nor copies 999 texts; the blob is written afresh once more than half
    of it is texts no page uses."""
    rows: dict[str, tuple] = {}
    base = _shared_blob(records)
    extra = bytearray()
    live = 0
    for rel, (key, record) in records.items():
        if isinstance(record, SourcePage):
            row = record.__dict__.get("_row")
            held = record.__dict__.get("_text_from")
            if row is not None and held is not None and held[0] is base and row[0] == key:
                rows[rel] = row
                live += row[-1] - row[-2]
                continue
            data = record.text_bytes()
            start = len(base) + len(extra)
            extra += data
            live += len(data)
            rows[rel] = (
                key,
                "page",
                str(record.rel),
                record.body_line,
                record.meta,
                record.digest,
                record.is_index,
                record.prefix,
                record.stem,
                record.text_key,
                record.heading,
                start,
                start + len(data),
            )
        elif isinstance(record, SourceAsset):
            rows[rel] = (key, "asset", str(record.rel), str(record.path), record.digest)
        else:
            rows[rel] = (key, "draft")
    blob = base + extra
    if len(blob) > 2 * live:  # mostly old texts: copy the live ones into a new blob
        return _compact(rows, blob)
    return rows, blob


def _shared_blob(records: dict[str, tuple[list[int], Any]]) -> bytes:
    """The blob the records :func:`unpack` made read their texts from (b"" if none)."""
    for _key, record in records.values():
        held = getattr(record, "__dict__", {}).get("_text_from")
        if held is not None:
            return held[0]
    return b""


def _compact(rows: dict[str, tuple], blob: bytes) -> tuple[dict[str, tuple], bytes]:
    fresh = bytearray()
    out: dict[str, tuple] = {}
    for rel, row in rows.items():
        if row[1] == "page":
            start = len(fresh)
            fresh += blob[row[-2] : row[-1]]
            row = (*row[:-2], start, len(fresh))
        out[rel] = row
    return out, bytes(fresh)


def unpack(rows: dict[str, tuple], blob: bytes) -> dict[str, tuple[list[int], Any]]:
    """The records :func:`pack` made, each page's text deferred."""
    records: dict[str, tuple[list[int], Any]] = {}
    for rel, row in rows.items():
        key, kind = row[0], row[1]
        if kind == "page":
            (_k, _kind, path, body_line, meta, digest, is_index, prefix, stem) = row[:9]
            text_k, heading, start, end = row[9:]
            record: Any = deferred(
                SourcePage,
                (blob, start, end),
                rel=PurePosixPath(path),
                body_line=body_line,
                meta=meta,
                digest=digest,
                is_index=is_index,
                prefix=prefix,
                stem=stem,
                text_key=text_k,
                heading=heading,
                _row=row,
            )
        elif kind == "asset":
            record = SourceAsset(PurePosixPath(row[2]), Path(row[3]), row[4])
        else:
            record = None
        records[rel] = (key, record)
    return records
