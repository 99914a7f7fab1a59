"""What the build knows of a page's Markdown text without reading it again: its key and
its first heading, and records whose text is decoded only when first used.

A leaf module (no sitegen imports): the scan (sitegen.content), navigation (sitegen.nav) and
the build cache (sitegen.source_records) all use it.
"""

from __future__ import annotations

import dataclasses
import functools
import hashlib
import re
from typing import Any

_HEADING = re.compile(r"^(#{1,6})[ \t]+(.+?)[ \t]*#*[ \t]*$")
_FENCE = re.compile(r"^\s*(```|~~~)")
# Inline Markdown in a heading, for its plain-text title (menu, <title>, h1, search, slug):
# `code`, [text](url) and ![alt](src), **strong**/__strong__, *em*, and backslash escapes.
_INLINE = (
    (re.compile(r"(`+)\s?(.+?)\s?\1"), r"\2"),
    (re.compile(r"!?\[([^\]]*)\]\([^)]*\)"), r"\1"),
    (re.compile(r"(\*\*|__)(?=\S)(.+?)(?<=\S)\1"), r"\2"),
    (re.compile(r"\*(?=\S)([^*]+?)(?<=\S)\*"), r"\1"),
    (re.compile(r"\\([\\`*_{}\[\]()#+\-.!|])"), r"\1"),
)


def plain_title(heading: str) -> str:
    """A heading's text as a reader sees it: ``Preview: `sitegen serve``` -> ``Preview: sitegen
    serve``. Only what is cheap to undo without a Markdown parser (headings are short)."""
    if not any(c in heading for c in "`[*_\\"):
        return heading
    for pattern, keep in _INLINE:
        heading = pattern.sub(keep, heading)
    return heading.strip()


def first_heading(text: str) -> tuple[str | None, int, bool]:
    """Return (title, level, is_first_content_line) for the first ATX heading outside code.
    Reads line by line up to the heading (usually the first line), not the whole text."""
    in_fence, seen_content = False, False
    start, size = 0, len(text)
    while start <= size:
        end = text.find("\n", start)
        if end < 0:
            end = size
        line = text[start:end]
        start = end + 1
        if _FENCE.match(line):
            in_fence = not in_fence
            seen_content = True
            continue
        if in_fence:
            continue
        m = _HEADING.match(line)
        if m:
            return plain_title(m.group(2).strip()), len(m.group(1)), not seen_content
        if line.strip():
            seen_content = True
    return None, 0, False


class DeferredText:
    """For a record dataclass with a ``text`` field: the field may be left unset and given a
    source instead (:func:`deferred`); it is decoded and kept at its first use."""

    def __getattr__(self, name: str) -> Any:  # only called when the attribute is missing
        if name == "text" and "_text_from" in self.__dict__:
            text = self.__dict__["text"] = self.text_bytes().decode()
            del self.__dict__["_text_from"]
            return text
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def text_bytes(self) -> bytes:
        """The text as UTF-8, without decoding a deferred text."""
        held = self.__dict__.get("_text_from")
        if held is not None:
            blob, start, end = held
            return bytes(blob[start:end])
        return self.text.encode()  # type: ignore[attr-defined]


def text_key(text: str) -> str:
    """What the Markdown cache keys a text on (sitegen.markdown_stage)."""
    return hashlib.sha256(text.encode()).hexdigest()


@functools.cache
def _defaults(cls: type) -> tuple[dict[str, Any], tuple[tuple[str, Any], ...]]:
    """The field defaults of ``cls`` (but ``text``'s): plain values, and default factories."""
    plain: dict[str, Any] = {}
    made: list[tuple[str, Any]] = []
    for f in dataclasses.fields(cls):
        if f.name == "text":
            continue
        if f.default is not dataclasses.MISSING:
            plain[f.name] = f.default
        elif f.default_factory is not dataclasses.MISSING:
            made.append((f.name, f.default_factory))
    return plain, tuple(made)


def deferred(cls: type, text_from: tuple[Any, int, int], **values: Any) -> Any:
    """An instance of the dataclass ``cls`` with ``values``, its ``text`` to be decoded from
    ``text_from`` = (blob, start, end) when first used. Fields not given take their
    defaults."""
    plain, made = _defaults(cls)
    obj = cls.__new__(cls)
    fields = obj.__dict__
    fields.update(plain)
    for name, factory in made:
        if name not in values:
            fields[name] = factory()
    fields.update(values)
    fields["_text_from"] = text_from
    return obj
