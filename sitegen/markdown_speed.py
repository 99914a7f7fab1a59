"""Python-Markdown made cheaper per page and linear in a page's size.

Three things Python-Markdown does that a site build pays for on every page:

* ``codehilite`` creates a new Pygments formatter, and with it a new stylesheet, for every
  code block. :func:`cached_formatter` hands out one formatter per set of options (in
  practice one per language); Pygments formatters keep no state between ``format`` calls.
* The block parser keeps the blocks still to parse in a list and takes each one off the
  front with ``pop(0)`` (and pushes a remainder back with ``insert(0, ...)``), which moves
  the whole rest of the list every time: quadratic in the number of blocks. :class:`BlockQueue`
  offers the same operations in constant time.
* ``footnotes`` keeps the order of references in a list and looks each one up with ``in``
  and ``index``, and numbers each reference by building the list of all definitions:
  quadratic in the number of footnotes. :class:`_OrderList` and a definition map answer in
  constant time.

The output is byte-identical to stock Python-Markdown (``tests/test_build_speed.py``
compares them).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as etree
from collections.abc import Iterable, Iterator
from typing import Any

import markdown
from markdown.extensions import Extension
from markdown.extensions.footnotes import FootnoteExtension, FootnoteInlineProcessor
from pygments.formatters import HtmlFormatter

_FORMATTERS: dict[str, HtmlFormatter] = {}


def cached_formatter(**options: Any) -> HtmlFormatter:
    """The ``pygments_formatter`` of codehilite: one HTML formatter per distinct options."""
    key = repr(sorted(options.items()))
    formatter = _FORMATTERS.get(key)
    if formatter is None:
        formatter = _FORMATTERS[key] = HtmlFormatter(**options)
    return formatter


class BlockQueue:
    """The blocks still to parse, front at the end of a list, so the parser's ``pop(0)``,
    ``insert(0, x)`` and ``[0]`` cost O(1) instead of O(blocks)."""

    __slots__ = ("_rev",)

    def __init__(self, blocks: Iterable[str]):
        self._rev = list(blocks)
        self._rev.reverse()

    def __len__(self) -> int:
        return len(self._rev)

    def __bool__(self) -> bool:
        return bool(self._rev)

    def __iter__(self) -> Iterator[str]:
        return reversed(self._rev)

    def __getitem__(self, index: int | slice) -> Any:
        if isinstance(index, slice):
            return list(self)[index]
        n = len(self._rev)
        if index < 0:
            index += n
        if not 0 <= index < n:
            raise IndexError("block index out of range")
        return self._rev[n - 1 - index]

    def __setitem__(self, index: int, value: str) -> None:
        n = len(self._rev)
        if index < 0:
            index += n
        if not 0 <= index < n:
            raise IndexError("block index out of range")
        self._rev[n - 1 - index] = value

    def pop(self, index: int = -1) -> str:
        n = len(self._rev)
        if index < 0:
            index += n
        if not 0 <= index < n:
            raise IndexError("pop from empty or out of range")
        return self._rev.pop(n - 1 - index)

    def insert(self, index: int, value: str) -> None:
        n = len(self._rev)
        if index < 0:
            index = max(0, index + n)
        index = min(index, n)
        self._rev.insert(n - index, value)

    def append(self, value: str) -> None:
        self._rev.insert(0, value)


class LinearBlocksExtension(Extension):
    """Feed the block parser a :class:`BlockQueue` instead of a plain list."""

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        parser = md.parser

        def parse_chunk(parent: Any, text: str) -> None:
            parser.parseBlocks(parent, BlockQueue(text.split("\n\n")))  # type: ignore[arg-type]

        parser.parseChunk = parse_chunk  # type: ignore[method-assign]


class _OrderList(list):
    """The footnote reference order with O(1) ``in`` and ``index``."""

    def __init__(self) -> None:
        super().__init__()
        self._at: dict[str, int] = {}

    def append(self, item: str) -> None:
        self._at.setdefault(item, len(self))
        super().append(item)

    def __contains__(self, item: object) -> bool:
        return item in self._at

    def index(self, item: str, *args: Any) -> int:  # type: ignore[override]
        if args:
            return super().index(item, *args)
        try:
            return self._at[item]
        except KeyError:
            raise ValueError(f"{item!r} is not in list") from None


class LinearFootnotesExtension(FootnoteExtension):
    """Python-Markdown's ``footnotes`` with the reference order kept in an :class:`_OrderList`
    and each definition's number in a map (stock numbering rebuilds the list of all
    definitions for every reference)."""

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        super().extendMarkdown(md)
        stock = md.inlinePatterns["footnote"]
        md.inlinePatterns.register(_FootnoteRefs(stock.pattern, self), "footnote", 175)

    def reset(self) -> None:
        super().reset()
        self.footnote_order = _OrderList()
        self.defined: dict[str, int] = {}

    def setFootnote(self, id: str, text: str) -> None:  # noqa: A002, N802 (Markdown API)
        self.defined.setdefault(id, len(self.defined))  # an OrderedDict keeps first positions
        super().setFootnote(id, text)


class _FootnoteRefs(FootnoteInlineProcessor):
    """The stock reference pattern, numbering a reference in O(1)."""

    footnotes: LinearFootnotesExtension

    def handleMatch(self, m: re.Match[str], data: str) -> tuple[Any, Any, Any]:  # noqa: N802
        notes = self.footnotes
        ref = m.group(1)
        if ref not in notes.footnotes:
            return None, None, None
        notes.addFootnoteRef(ref)
        if not notes.getConfig("USE_DEFINITION_ORDER"):
            number = notes.footnote_order.index(ref) + 1
        else:
            number = notes.defined[ref] + 1
        sup = etree.Element("sup")
        a = etree.SubElement(sup, "a")
        sup.set("id", notes.makeFootnoteRefId(ref, found=True))
        a.set("href", "#" + notes.makeFootnoteId(ref))
        a.set("class", "footnote-ref")
        a.text = notes.getConfig("SUPERSCRIPT_TEXT").format(number)
        return sup, m.start(0), m.end(0)
