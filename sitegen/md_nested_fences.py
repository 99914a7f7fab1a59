"""Fenced code inside a content tab or an admonition (indented under ``===`` / ``!!!``).

Tabs come from pymdown-extensions' ``tabbed`` (the syntax MkDocs Material uses, so pages move
between the two unchanged), admonitions from Python-Markdown. Neither lets Python-Markdown's
``fenced_code`` see a fence that is indented inside them: it would come out as a paragraph of
inline code. pymdown-extensions' answer is ``superfences``, which replaces ``fenced_code`` and
highlights through ``pymdownx.highlight``; this site highlights through ``codehilite`` with the
highlight cache (``sitegen.highlight_cache.LazyLexer``), so instead this small preprocessor hands
each indented fence to ``fenced_code`` itself.
"""

from __future__ import annotations

import re

import markdown
from markdown.extensions import Extension
from markdown.preprocessors import Preprocessor


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


class NestedFencesExtension(Extension):
    def extendMarkdown(self, md: markdown.Markdown) -> None:  # noqa: N802 (Markdown API)
        md.preprocessors.register(_NestedFences(md), "sitegen_nested_fences", 26)
