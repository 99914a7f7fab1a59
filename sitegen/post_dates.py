"""Dates of blog posts: the forms authors write, normalised to one sortable ISO string.

Front matter gives ``2021-03-04`` (YAML reads it as a date), ``2021-03-04 10:20`` or
``2021-03-04T10:20:00+08:00`` (text). One normal form (``YYYY-MM-DDTHH:MM:SS`` plus an
offset when one was given) keeps page metadata plain data, sorts posts by date, and is what
the Atom feed needs; a date without an offset is taken as UTC there.
"""

from __future__ import annotations

import datetime as dt
import re

_FORMS = ("%Y-%m-%d", "%Y-%m-%d %H:%M", "%Y-%m-%d %H:%M:%S", "%Y-%m-%dT%H:%M", "%Y-%m-%dT%H:%M:%S")
_OFFSET = re.compile(r"(Z|[+-]\d\d:?\d\d)$")


def parse_post_date(value: object) -> str | None:
    """The normal form of ``value``, or None when it is not a date sitegen understands."""
    if isinstance(value, dt.datetime):
        return _fmt(value)
    if isinstance(value, dt.date):
        return f"{value.isoformat()}T00:00:00"
    if not isinstance(value, str):
        return None
    text = value.strip()
    offset = ""
    m = _OFFSET.search(text)
    if m and len(text) > 10:
        raw = m.group(1)
        offset = "Z" if raw == "Z" else f"{raw[:3]}:{raw[-2:]}"
        text = text[: m.start()].strip()
    for form in _FORMS:
        try:
            when = dt.datetime.strptime(text, form)
        except ValueError:
            continue
        return when.strftime("%Y-%m-%dT%H:%M:%S") + ("" if offset == "Z" else offset)
    return None


def _fmt(value: dt.datetime) -> str:
    text = value.strftime("%Y-%m-%dT%H:%M:%S")
    off = value.utcoffset()
    if off:
        minutes = int(off.total_seconds() // 60)
        sign = "+" if minutes >= 0 else "-"
        text += f"{sign}{abs(minutes) // 60:02d}:{abs(minutes) % 60:02d}"
    return text


def day(normal: str) -> str:
    """``2021-03-04`` of a normal form, for display."""
    return normal[:10]


def atom_time(normal: str) -> str:
    """RFC 3339 as Atom wants it: the offset given, else UTC."""
    return normal if _OFFSET.search(normal) else normal + "Z"
