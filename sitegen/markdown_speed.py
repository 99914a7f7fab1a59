"""Python-Markdown made cheaper per page and linear in a page's size.

What Python-Markdown does that a site build pays for on every page:

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
* The inline step tries every inline pattern (fifteen of them: code, links, emphasis, ...) on
  every piece of text, one ``finditer`` each, though most prose holds none of the characters
  any of them starts with. :class:`SkippingInlineProcessor` first looks for those characters
  (:func:`sitegen.regex_starts.start_needles`), and hands the text back as it is when there
  is none, as the patterns would have.
* The block parser asks every block processor to test every block: it reads the block
  (``blocks[0]``) and lists the processors again each time, and most tests scan the whole
  block with a regular expression for a mark it does not hold (``>``, ``#``, ``!!!``).
  ``parse_blocks`` reads both once, and :class:`NeedlePattern` lets a search give up at once
  on a block that lacks what every match holds.

The output is byte-identical to stock Python-Markdown (``tests/test_build_speed.py`` and
``tests/test_markdown_speed.py`` compare them).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as etree
from collections.abc import Iterable, Iterator
from typing import Any

import markdown
from markdown.extensions import Extension
from markdown.extensions.footnotes import FootnoteExtension, FootnoteInlineProcessor
from markdown.treeprocessors import InlineProcessor
from pygments.formatters import HtmlFormatter

from sitegen.regex_starts import holds_any, required_needles, start_needles

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
    """Feed the block parser a :class:`BlockQueue` instead of a plain list; read the block under
    test once per processor round instead of once per processor; let the processors' searches
    skip text that cannot hold a match (:class:`NeedlePattern`)."""

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        parser = md.parser
        seen: set[int] = set()  # processors whose patterns were given needles

        def parse_chunk(parent: Any, text: str) -> None:
            parser.parseBlocks(parent, BlockQueue(text.split("\n\n")))  # type: ignore[arg-type]

        def parse_blocks(parent: Any, blocks: Any) -> None:
            """The stock loop: each processor in turn tests the first block, the first whose
            ``run`` does not return False consumes it. A test only sees the block, so the
            block is read again only after a ``run`` that declined (it may have changed it)."""
            processors = list(parser.blockprocessors)
            skip_impossible_searches(p for p in processors if id(p) not in seen)
            seen.update(id(p) for p in processors)
            while blocks:
                block, fresh = blocks[0], True
                for processor in processors:
                    if not fresh:
                        block, fresh = blocks[0], True
                    if processor.test(parent, block):
                        if processor.run(parent, blocks) is not False:
                            break
                        fresh = False

        parser.parseChunk = parse_chunk  # type: ignore[method-assign]
        parser.parseBlocks = parse_blocks  # type: ignore[method-assign]


def skip_impossible_searches(processors: Iterable[Any]) -> None:
    """Give each processor's compiled patterns a :class:`NeedlePattern` stand-in where the
    strings every match holds are known (and are not plain spaces or newlines, which nearly
    every block holds: checking for them would only cost time)."""
    for processor in processors:
        for name in dir(processor):
            if name.startswith("__"):
                continue
            value = getattr(processor, name, None)
            if not isinstance(value, re.Pattern):
                continue
            needles = required_needles(value)
            if needles and not any(n in (" ", "\n", "\t") for n in needles):
                setattr(processor, name, NeedlePattern(value, needles))


class NeedlePattern:
    """A compiled pattern whose ``search`` and ``finditer`` first look for the strings every
    match holds (:func:`sitegen.regex_starts.required_needles`): a paragraph of prose holds no
    ``>``, so the block-quote test need not scan it with a regular expression. Everything else
    is the pattern's own."""

    __slots__ = ("pattern_object", "needles")

    def __init__(self, pattern: re.Pattern, needles: tuple[str, ...]):
        self.pattern_object = pattern
        self.needles = needles

    def search(self, string: str, *args: Any) -> re.Match | None:
        for needle in self.needles:
            if needle in string:
                return self.pattern_object.search(string, *args)
        return None

    def finditer(self, string: str, *args: Any) -> Iterator[re.Match]:
        for needle in self.needles:
            if needle in string:
                return self.pattern_object.finditer(string, *args)
        return iter(())

    def __getattr__(self, name: str) -> Any:
        return getattr(self.pattern_object, name)


class SkippingInlineProcessor(InlineProcessor):
    """Python-Markdown's inline step, skipping text in which no inline pattern can match.

    A text is handed back unchanged when a search for the characters (or literal starts,
    such as a line break's two spaces and newline) that the patterns' matches begin with
    finds none: then none of the patterns would match it either. When a pattern's starts are
    not known (one that may match the empty string, or start beyond ASCII), every text goes
    through the stock step."""

    def __init__(self, md: markdown.Markdown):
        super().__init__(md)
        self._made_for: list[Any] | None = None
        self._holds: Any = None

    def run(self, tree: etree.Element, ancestors: list[str] | None = None) -> etree.Element:
        patterns = list(self.inlinePatterns)
        if patterns != self._made_for:  # an extension may add patterns after this was made
            found = start_needles(p.getCompiledRegExp() for p in patterns)
            self._holds = holds_any(found) if found is not None else None
            self._made_for = patterns
        return super().run(tree, ancestors)

    def _InlineProcessor__handleInline(self, data: str, patternIndex: int = 0) -> str:  # noqa: N802, N803
        if self._holds is not None and not self._holds(data):
            return data
        return _STOCK_INLINE(self, data, patternIndex)


_STOCK_INLINE = InlineProcessor._InlineProcessor__handleInline  # type: ignore[attr-defined]


class SkippingInlineExtension(Extension):
    """Register :class:`SkippingInlineProcessor` in place of the stock inline step."""

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        md.treeprocessors.register(SkippingInlineProcessor(md), "inline", 20)


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
