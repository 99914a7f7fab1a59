"""Content tabs in Markdown, for steps that differ per system ("Windows / macOS / Linux").

The syntax is pymdown-extensions' ``tabbed`` (so pages move between MkDocs Material and sitegen
unchanged)::

    === "Windows"
        py -m pip install sitegen

    === "Linux"
        python3 -m pip install sitegen

Consecutive ``===`` blocks form one tab set. The output needs no JavaScript: one radio input
per tab with its label, then the tab's content; the theme's CSS shows the checked tab's content,
and the radios give keyboard use (Tab to the set, arrow keys between tabs) for free. Ids are
numbered per page, so the output is deterministic. Written here rather than depending on
pymdown-extensions for one small block processor.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as etree

import markdown
from markdown.blockprocessors import BlockProcessor
from markdown.extensions import Extension
from markdown.preprocessors import Preprocessor

TAB = re.compile(r'^=== +"([^"\n]*)" *(?:\n|$)')


class _TabsProcessor(BlockProcessor):
    def __init__(self, parser, ext: TabsExtension):
        super().__init__(parser)
        self.ext = ext

    def _set(self, parent: etree.Element) -> etree.Element | None:
        last = self.lastChild(parent)
        if last is not None and last.tag == "div" and last.get("class") == "tabbed-set":
            return last
        return None

    def test(self, parent: etree.Element, block: str) -> bool:
        if TAB.match(block):
            return True
        # an indented block right after a tab continues that tab's content
        return block.startswith(" " * self.tab_length) and self._set(parent) is not None

    def run(self, parent: etree.Element, blocks: list[str]) -> None:
        block = blocks.pop(0)
        m = TAB.match(block)
        tabset = self._set(parent)
        if m is None:
            assert tabset is not None
            content, rest = self.detab(block)
            self.parser.parseChunk(tabset[-1], content)
        else:
            if tabset is None:
                self.ext.sets += 1
                tabset = etree.SubElement(parent, "div", {"class": "tabbed-set"})
            number = sum(1 for el in tabset if el.tag == "input") + 1
            ident = f"__tabbed_{self.ext.sets}_{number}"
            radio = etree.SubElement(
                tabset, "input", {"type": "radio", "name": f"__tabbed_{self.ext.sets}", "id": ident}
            )
            if number == 1:
                radio.set("checked", "checked")
            label = etree.SubElement(tabset, "label", {"for": ident})
            label.text = m.group(1)
            box = etree.SubElement(tabset, "div", {"class": "tabbed-block"})
            content, rest = self.detab(block[m.end() :])
            self.parser.parseChunk(box, content)
        if rest:
            blocks.insert(0, rest)


class _NestedFences(Preprocessor):
    """Fenced code inside a tab or an admonition (indented under ``===`` / ``!!!``).

    Python-Markdown's fenced_code only sees fences at the margin, so an indented fence would
    come out as a paragraph of inline code. Each such fence is handed to fenced_code with its
    indent removed; the placeholder it returns goes back at the same indent, so the container
    still holds it. Fences anywhere else are left to fenced_code as before.
    """

    OPEN = re.compile(r"^( *)(?:===|!!!|\?\?\?\+?) ")
    FENCE = re.compile(r"^(`{3,}|~{3,})")

    def run(self, lines: list[str]) -> list[str]:
        if not any(self.OPEN.match(line) for line in lines):
            return lines
        fenced = self.md.preprocessors["fenced_code_block"]
        out: list[str] = []
        indent, i = None, 0  # indent: content indent of the container we are in
        while i < len(lines):
            line = lines[i]
            m = self.OPEN.match(line)
            if m:
                indent = len(m.group(1)) + 4
            elif indent is not None and line.strip() and not line.startswith(" " * indent):
                indent = None
            f = (
                self.FENCE.match(line[indent:])
                if indent and line.startswith(" " * indent)
                else None
            )
            if f:
                end = next(
                    (j for j in range(i + 1, len(lines)) if lines[j].strip() == f.group(1)), None
                )
                if end is not None:
                    block = [x[indent:] for x in lines[i : end + 1]]
                    out.extend((" " * indent + x) if x else x for x in fenced.run(block))
                    i = end + 1
                    continue
            out.append(line)
            i += 1
        return out


class TabsExtension(Extension):
    def __init__(self, **kwargs):
        self.sets = 0
        super().__init__(**kwargs)

    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        md.registerExtension(self)  # so md.reset() calls our reset: ids restart on every page
        md.parser.blockprocessors.register(_TabsProcessor(md.parser, self), "sitegen_tabs", 104)
        md.preprocessors.register(_NestedFences(md), "sitegen_nested_fences", 26)

    def reset(self) -> None:
        self.sets = 0
