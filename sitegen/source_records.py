"""The last scan's source records as the build cache keeps them, with texts read on demand.

A one-page edit of a 1000-page site takes 999 records from the last scan (sitegen.content's
``known``). What the build needs of an unchanged page is its path, front matter, digest, title
heading and a key of its text, not the text itself: only the pages it converts or renders
again read their text. So the cache keeps the records as plain tuples, and every text as
UTF-8 in a file of texts that an edit only appends to (sitegen.cache writes both); a page
taken from them decodes its text on first use (sitegen.page_text.DeferredText). Loading and
saving 1000 records then costs a few milliseconds instead of decoding, re-encoding and
rewriting 4 MB of text each time.
"""

from __future__ import annotations

from pathlib import Path, PurePosixPath
from typing import Any

from sitegen.content import SourceAsset, SourcePage
from sitegen.page_text import deferred


class TextBlob:
    """The texts of the cached records, as read from their file (``name`` in the cache
    folder); a deferred page's text is a slice of it."""

    __slots__ = ("data", "name")

    def __init__(self, data: bytes, name: str):
        self.data = data
        self.name = name

    def __getitem__(self, where: slice) -> bytes:
        return self.data[where]


def pack(
    records: dict[str, tuple[list[int], Any]], base: TextBlob | None, tail: int
) -> tuple[dict[str, tuple], bytearray, int]:
    """``rel -> (stat key, SourcePage | SourceAsset | None)`` as plain rows, the texts to add
    at ``tail`` (the end of ``base``'s file), and how many bytes of texts the rows use. A page
    still as :func:`unpack` made it from ``base`` keeps its row and its text's place, so a
    one-page edit neither re-encodes nor writes 999 texts again."""
    rows: dict[str, tuple] = {}
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
            start = tail + len(extra)
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
    return rows, extra, live


def shared_blob(records: dict[str, tuple[list[int], Any]]) -> TextBlob | None:
    """The blob the records :func:`unpack` made read their texts from (None if none)."""
    for _key, record in records.values():
        held = getattr(record, "__dict__", {}).get("_text_from")
        if held is not None:
            return held[0]
    return None


def compact(
    rows: dict[str, tuple], base: bytes, tail: int, extra: bytes
) -> tuple[dict[str, tuple], bytes]:
    """The rows with only the texts they use, in one new blob (texts before ``tail`` are in
    ``base``, the others in ``extra``)."""
    fresh = bytearray()
    out: dict[str, tuple] = {}
    for rel, row in rows.items():
        if row[1] == "page":
            start, end = row[-2], row[-1]
            text = extra[start - tail : end - tail] if start >= tail else base[start:end]
            at = len(fresh)
            fresh += text
            row = (*row[:-2], at, len(fresh))
        out[rel] = row
    return out, bytes(fresh)


def unpack(rows: dict[str, tuple], blob: TextBlob) -> dict[str, tuple[list[int], Any]]:
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
